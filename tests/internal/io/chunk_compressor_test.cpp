// The .bpm writer's shuffle choice (io/chunk_compressor.h), tested directly: a dataset is
// shuffled when that makes its chunks smaller, decided on a sample of the first chunk for
// large chunks (deflating a whole chunk both ways cost a second compression of every small
// file), so the sample must choose as the whole chunk does on the kinds of arrays a .bpm holds.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "io/chunk_compressor.h"

using bpm::detail::ChunkCompressor;

namespace {

// 65536 rows of 3 entries, as a full chunk of the writer.
constexpr size_t kRows = 65536;

template <typename T>
const unsigned char* bytes_of(const std::vector<T>& v) {
    return reinterpret_cast<const unsigned char*>(v.data());
}

// Whether shuffling makes the whole chunk smaller (what earlier writers decided on).
template <typename T>
bool shuffle_pays_on_whole(const std::vector<T>& v) {
    ChunkCompressor c;
    ChunkCompressor::Stored plain, shuffled;
    c.compress(bytes_of(v), v.size() * sizeof(T), sizeof(T), false, false, plain);
    c.compress(bytes_of(v), v.size() * sizeof(T), sizeof(T), true, true, shuffled);
    return shuffled.size < plain.size;
}

// Triangles of pieces: node ids local to a slowly advancing window (phi/pieces).
std::vector<int32_t> piece_like(std::mt19937& rng, size_t rows) {
    std::vector<int32_t> v;
    std::uniform_int_distribution<int32_t> near(0, 40);
    for (size_t i = 0; i < rows; ++i)
        for (int k = 0; k < 3; ++k) v.push_back(int32_t(i / 2) + near(rng));
    return v;
}

// Barycentric coordinates of nodes: many exact 0 and 1 (vertex and edge nodes), the rest
// rationals (phi/node_barycentric).
std::vector<double> barycentric_like(std::mt19937& rng, size_t rows) {
    std::vector<double> v;
    std::uniform_int_distribution<int> kind(0, 3);
    std::uniform_real_distribution<double> u(0, 1);
    for (size_t i = 0; i < rows; ++i) {
        switch (kind(rng)) {
            case 0: v.insert(v.end(), {1.0, 0.0, 0.0}); break;
            case 1: v.insert(v.end(), {0.0, 1.0, 0.0}); break;
            case 2: {
                const double t = u(rng);
                v.insert(v.end(), {t, 1 - t, 0.0});
                break;
            }
            default: {
                const double a = u(rng), b = u(rng) * (1 - a);
                v.insert(v.end(), {a, b, 1 - a - b});
            }
        }
    }
    return v;
}

}  // namespace

TEST_CASE("shuffle choice: a sample chooses as the whole chunk on index and barycentric arrays", "[internal][io]") {
    std::mt19937 rng(21);
    ChunkCompressor c;
    const std::vector<int32_t> pieces = piece_like(rng, kRows);
    REQUIRE(shuffle_pays_on_whole(pieces));
    CHECK(c.shuffle_pays(bytes_of(pieces), pieces.size() * 4, 4));
    const std::vector<double> bary = barycentric_like(rng, kRows);
    REQUIRE(!shuffle_pays_on_whole(bary));
    CHECK(!c.shuffle_pays(bytes_of(bary), bary.size() * 8, 8));
}

TEST_CASE("shuffle choice: the sample is spread over the chunk, not its start", "[internal][io]") {
    // A chunk that starts with a few kB of index-like doubles (small integers: shuffling
    // pays) and goes on with barycentric coordinates: the whole chunk, and a sample spread
    // over it, say no.
    std::mt19937 rng(7);
    std::vector<double> v;
    for (int i = 0; i < 2048; ++i) v.push_back(double(i / 4));
    const std::vector<double> bary = barycentric_like(rng, kRows);
    v.insert(v.end(), bary.begin(), bary.end() - 2048);
    REQUIRE(!shuffle_pays_on_whole(v));
    ChunkCompressor c;
    CHECK(!c.shuffle_pays(bytes_of(v), v.size() * 8, 8));
}

TEST_CASE("compress_first_chunk keeps the smaller way for small chunks and sets the filter mask", "[internal][io]") {
    std::mt19937 rng(3);
    ChunkCompressor c;
    ChunkCompressor::Stored out;
    // 1000 rows (12 kB): both ways deflated, the smaller kept.
    const std::vector<int32_t> pieces = piece_like(rng, 1000);
    ChunkCompressor::Stored plain, shuffled;
    c.compress(bytes_of(pieces), pieces.size() * 4, 4, false, false, plain);
    c.compress(bytes_of(pieces), pieces.size() * 4, 4, true, true, shuffled);
    REQUIRE(shuffled.size < plain.size);
    CHECK(c.compress_first_chunk(bytes_of(pieces), pieces.size() * 4, 4, out));
    CHECK(out.size == shuffled.size);
    CHECK(out.filter_mask == 0u);
    CHECK(std::memcmp(out.buffer.data(), shuffled.buffer.data(), out.size) == 0);
    // Bytes are never shuffled; random bits are stored raw, deflate (filter 0) skipped.
    std::vector<uint8_t> noise(4096);
    for (auto& b : noise) b = uint8_t(rng());
    CHECK(!c.compress_first_chunk(noise.data(), noise.size(), 1, out));
    CHECK(out.size == noise.size());
    CHECK(out.filter_mask == 1u);
}

TEST_CASE("a last chunk given in part compresses as the chunk padded with zeros", "[internal][io]") {
    // The writer hands the last chunk of a dataset without its zero padding; the stored
    // bytes must be those of the padded chunk, shuffled or not, for every element size.
    std::mt19937 rng(9);
    for (size_t element_size : {size_t(1), size_t(4), size_t(8), size_t(12)}) {
        const size_t elements = 3000, given_elements = 1234;
        std::vector<unsigned char> padded(elements * element_size, 0);
        std::uniform_int_distribution<int> byte(0, 40);  // compressible
        for (size_t i = 0; i < given_elements * element_size; ++i) padded[i] = static_cast<unsigned char>(byte(rng));
        // The given part alone, in a buffer that ends where it ends.
        const std::vector<unsigned char> given(padded.begin(), padded.begin() + long(given_elements * element_size));
        for (bool shuffle : {false, true}) {
            ChunkCompressor c;
            ChunkCompressor::Stored whole, part;
            c.compress(padded.data(), padded.size(), element_size, shuffle, shuffle, whole);
            // Its buffers hold other bytes before the part (as after an earlier dataset).
            const std::vector<unsigned char> other(padded.size(), 0xA5);
            ChunkCompressor::Stored scratch;
            c.compress(other.data(), other.size(), element_size, true, true, scratch);
            c.compress(given.data(), given.size(), padded.size(), element_size, shuffle, shuffle, part);
            REQUIRE(part.size == whole.size);
            CHECK(part.filter_mask == whole.filter_mask);
            CHECK(std::memcmp(part.buffer.data(), whole.buffer.data(), whole.size) == 0);
        }
    }
}
