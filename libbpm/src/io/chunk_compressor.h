// The .bpm writer's chunk compression (io/bpm_write.cpp): HDF5's shuffle + deflate
// pipeline done by the writer itself, chunk by chunk, with libdeflate, and the choice of
// whether a dataset's pipeline has the shuffle filter.
//
// The chunks go to HDF5 as they are stored (H5Dwrite_chunk, "direct chunk write"). They
// are ordinary shuffle + deflate chunks (zlib streams, made by libdeflate, which is about
// twice as fast as zlib), so every HDF5 reads them with its own filters.
//
// Everything here depends on the bytes given only, so the writer stays deterministic.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

struct libdeflate_compressor;

namespace bpm::detail {

// libdeflate's level (HDF5's filter message records it; inflating costs the same at every
// level). With zlib, level 1 was the choice (4/6 made armadillo + 1x Loop 1.9/2.4 %
// smaller for 0.5/0.8 s more of bpm-simplify's 11 s). libdeflate at level 2 writes files
// 1-3 % smaller than zlib at level 1, in about 60 % of the time (elephant --vertices
// 1000: writer 0.060 -> 0.038 s CPU, 661 -> 647 kB; armadillo + 2x Loop, 832k triangles,
// --ratio 1: 2.9 -> 1.8-2.2 s, 95.5 -> 94.3 MB); its level 1 is as fast on small files
// but 1-4 % larger than level 2, level 4 as fast on large files and slower on small ones.
constexpr unsigned kDeflateLevel = 2;

// The bytes on which the shuffle choice of a larger first chunk is made (see
// ChunkCompressor::shuffle_pays): 8 blocks of 2 kB spread over the chunk.
constexpr size_t kShuffleSampleBytes = 16384;
constexpr size_t kShuffleSampleBlocks = 8;

class ChunkCompressor {
public:
    ChunkCompressor();
    ChunkCompressor(const ChunkCompressor&) = delete;
    ChunkCompressor& operator=(const ChunkCompressor&) = delete;
    ~ChunkCompressor();

    // Room for bytes that are all written before they are read: unlike a
    // std::vector<unsigned char>, growing it does not zero the new bytes first.
    class Buffer {
    public:
        unsigned char* room(size_t bytes) {
            if (bytes > capacity_) {
                data_.reset(new unsigned char[bytes]);
                capacity_ = bytes;
            }
            return data_.get();
        }
        const unsigned char* data() const { return data_.get(); }

    private:
        std::unique_ptr<unsigned char[]> data_;
        size_t capacity_ = 0;
    };

    // The stored bytes of one chunk and the HDF5 filter mask that says which filters of
    // the pipeline (shuffle, deflate) were skipped. The buffers are reused from chunk to
    // chunk and from dataset to dataset (the writer's): a fresh 1.5 MB buffer per chunk
    // cost page faults, and fresh zeroed buffers per dataset were 2.5 % of
    // bpm-simplify elephant --vertices 1000 --threads 1.
    struct Stored {
        Buffer buffer;
        size_t size = 0;
        uint32_t filter_mask = 0;
    };

    // Compresses one chunk of `bytes` bytes of elements of `element_size` bytes into
    // `out`, shuffled or not; the pipeline of the dataset has the shuffle filter when
    // `shuffle_in_pipeline`.
    void compress(const unsigned char* data, size_t bytes, size_t element_size, bool shuffle, bool shuffle_in_pipeline,
                  Stored& out);
    // The same for a chunk of `bytes` bytes whose first `given` bytes are at `data` and the
    // rest zero (the last chunk of a dataset, which HDF5 pads with the zero fill value):
    // the same stored bytes as compressing the padded chunk, without the caller's copy.
    void compress(const unsigned char* data, size_t given, size_t bytes, size_t element_size, bool shuffle,
                  bool shuffle_in_pipeline, Stored& out);

    // Compresses the first chunk of a dataset into `out` and returns whether the
    // dataset's pipeline has the shuffle filter (then its other chunks are shuffled too).
    // Elements of one byte are never shuffled; a chunk of at most twice
    // kShuffleSampleBytes is compressed both ways and the smaller kept; a larger one is
    // compressed once, the way shuffle_pays chooses.
    bool compress_first_chunk(const unsigned char* data, size_t bytes, size_t element_size, Stored& out);

    // Whether the shuffle filter (bytes regrouped by significance) before deflate makes
    // the chunk smaller, judged on a sample: kShuffleSampleBlocks blocks of whole elements
    // at even steps from the chunk's start to its end, kShuffleSampleBytes in all,
    // deflated both ways.
    bool shuffle_pays(const unsigned char* data, size_t bytes, size_t element_size);

private:
    libdeflate_compressor* deflate_;
    Buffer shuffled_;  // a chunk's (or sample's) bytes shuffled, or a last chunk padded
    Buffer sample_;    // shuffle_pays's sample
    Stored trial_;     // the way not taken, or a sample deflated
};

}  // namespace bpm::detail
