#include "io/chunk_compressor.h"

#include <libdeflate.h>

#include <algorithm>
#include <cstring>
#include <new>
#include <utility>

namespace bpm::detail {

namespace {

// HDF5's shuffle of a chunk of `elements` elements whose first `given` are at `data` and
// the rest zero: byte b of element i goes to b * elements + i.
void shuffle_bytes(const unsigned char* data, size_t given, size_t elements, size_t element_size, unsigned char* out) {
    for (size_t i = 0; i < given; ++i)
        for (size_t b = 0; b < element_size; ++b) out[b * elements + i] = data[i * element_size + b];
    if (given < elements)
        for (size_t b = 0; b < element_size; ++b) std::memset(out + b * elements + given, 0, elements - given);
}
template <size_t E>
void shuffle_bytes(const unsigned char* data, size_t given, size_t elements, unsigned char* out) {
    shuffle_bytes(data, given, elements, E, out);  // inlined with E known: the byte loop unrolled
}

}  // namespace

ChunkCompressor::ChunkCompressor() : deflate_(libdeflate_alloc_compressor(int(kDeflateLevel))) {
    if (!deflate_) throw std::bad_alloc();
}

ChunkCompressor::~ChunkCompressor() { libdeflate_free_compressor(deflate_); }

void ChunkCompressor::compress(const unsigned char* data, size_t bytes, size_t element_size, bool shuffle,
                               bool shuffle_in_pipeline, Stored& out) {
    compress(data, bytes, bytes, element_size, shuffle, shuffle_in_pipeline, out);
}

void ChunkCompressor::compress(const unsigned char* data, size_t given, size_t bytes, size_t element_size,
                               bool shuffle, bool shuffle_in_pipeline, Stored& out) {
    const unsigned char* in = data;
    if (shuffle) {
        unsigned char* shuffled = shuffled_.room(bytes);
        const size_t elements = bytes / element_size, given_elements = given / element_size;
        // The common sizes with the size known to the compiler, which then unrolls the
        // byte loop (the generic loop was ~2 % of the 832k floor).
        switch (element_size) {
            case 4: shuffle_bytes<4>(data, given_elements, elements, shuffled); break;
            case 8: shuffle_bytes<8>(data, given_elements, elements, shuffled); break;
            default: shuffle_bytes(data, given_elements, elements, element_size, shuffled);
        }
        in = shuffled;
    } else if (given < bytes) {
        // The zeros after the given bytes, in the shuffle's buffer (deflate wants the chunk
        // in one piece; a buffer of the writer's own held another chunk's worth).
        unsigned char* padded = shuffled_.room(bytes);
        std::memcpy(padded, data, given);
        std::memset(padded + given, 0, bytes - given);
        in = padded;
    }
    // A chunk that deflate does not make smaller is stored without deflate (the optional
    // filter skipped), as HDF5's own deflate filter does when zlib's output does not fit
    // in about the input's size.
    unsigned char* to = out.buffer.room(bytes);
    out.filter_mask = shuffle_in_pipeline && !shuffle ? 1u : 0u;
    out.size = libdeflate_zlib_compress(deflate_, in, bytes, to, bytes);
    if (out.size == 0) {
        std::memcpy(to, in, bytes);
        out.size = bytes;
        out.filter_mask |= shuffle_in_pipeline ? 2u : 1u;
    }
}

// Shuffling pays on index arrays (phi/pieces: 6x smaller shuffled, 3.8x unshuffled) but
// not on most float64 arrays: coordinates read from text with few digits and barycentric
// coordinates with exact 0 and 1 deflate better as they are (fandisk's original/vertices:
// 61 kB unshuffled, 128 kB shuffled). Which way wins differs between meshes for the same
// dataset (node_image: shuffled 12 % smaller on elephant, 16 % larger on fandisk;
// original/vertices, node_edge_parameter, node_original_vertex likewise), so the data
// decide. Earlier writers deflated the whole first chunk both ways and kept the smaller:
// every dataset of a small file is one chunk, so a small file was compressed twice
// (bpm-simplify elephant --vertices 1000 --threads 1: 0.226 -> 0.213 s CPU without the
// second deflate, median of 7 alternated runs on a busy machine). A sample of 16 kB in 8
// blocks spread over the chunk chooses as the whole chunk on nearly every dataset of the
// 18 reference outputs (scripts/reference-outputs.sh); where not, the two ways are within
// a few percent, and the files grew by at most 0.27 % (armadillo --vertices 1000, format 2.0);
// armadillo's 1x and 2x Loop subdivisions kept their sizes. A prefix of the chunk as the
// sample chose worse (4-16 kB: up to 5-10 % larger files): the arrays are ordered by
// coarse triangle or vertex, and their start is not typical of the rest.
bool ChunkCompressor::shuffle_pays(const unsigned char* data, size_t bytes, size_t element_size) {
    const size_t elements = bytes / element_size;
    const size_t per_block =
        std::min(elements, std::max<size_t>(1, kShuffleSampleBytes / kShuffleSampleBlocks / element_size));
    const size_t blocks = per_block * kShuffleSampleBlocks >= elements ? 1 : kShuffleSampleBlocks;
    const size_t block_bytes = (blocks == 1 ? elements : per_block) * element_size;
    unsigned char* sample = sample_.room(blocks * block_bytes);
    for (size_t b = 0; b < blocks; ++b) {
        const size_t first = blocks == 1 ? 0 : (elements - per_block) * b / (blocks - 1);
        std::memcpy(sample + b * block_bytes, data + first * element_size, block_bytes);
    }
    const size_t sample_bytes = blocks * block_bytes;
    compress(sample, sample_bytes, element_size, false, false, trial_);
    const size_t unshuffled = trial_.size;
    compress(sample, sample_bytes, element_size, true, true, trial_);
    return trial_.size < unshuffled;
}

bool ChunkCompressor::compress_first_chunk(const unsigned char* data, size_t bytes, size_t element_size,
                                           Stored& out) {
    if (element_size < 2) {
        compress(data, bytes, element_size, false, false, out);
        return false;
    }
    if (bytes > 2 * kShuffleSampleBytes) {
        const bool shuffle = shuffle_pays(data, bytes, element_size);
        compress(data, bytes, element_size, shuffle, shuffle, out);
        return shuffle;
    }
    // Small enough that deflating it twice costs no more than a sample twice and the
    // chunk once: the smaller of the two is kept (ties unshuffled).
    compress(data, bytes, element_size, false, false, out);
    compress(data, bytes, element_size, true, true, trial_);
    if (trial_.size >= out.size) return false;
    std::swap(out, trial_);
    return true;
}

}  // namespace bpm::detail
