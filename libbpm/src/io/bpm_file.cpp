// The bpm file format v1 on top of the HDF5 C API. spec/bpm-format.md is normative;
// this file is one implementation of it.
//
// Files are written by HDF5 straight into an unnamed temporary file next to the output
// (io/hdf5_fd_driver.h), which is named and renamed into place when complete
// (detail::write_file_atomically), so a reader never sees a half written file and no
// image of the whole file is held in memory.
// Standard output ("-") and write_bpm_to_memory get an image built in memory (core
// driver); both ways give the same bytes. Reading goes through a file image, which makes
// standard input and memory buffers the same case as files.
//
// The chunks of compressed datasets are shuffled (or not) and deflated here, not by HDF5's
// filters (io/chunk_compressor.h); whether a dataset is shuffled is decided on a sample of
// its first chunk, or on the whole chunk when it is small. A surface dataset that repeats
// one written before (/VTKHDF's copy of the coarse surface; the coarse surface at
// --ratio 1) gets that one's stored chunks, read back, instead of a second compression.
//
// Writing is deterministic: no object timestamps, chunk sizes and filters that depend on
// the data only (ChunkCompressor::compress_first_chunk; a copied dataset has the bytes its
// own compression would give), and nothing that depends on the time or the file name, so
// the same BpmFile always gives the same bytes.

#include "bpm/bpm_file.h"

#include <hdf5.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <locale>
#include <memory>
#include <optional>
#include <sstream>
#include <type_traits>
#include <vector>

#include "bpm/errors.h"
#include "bpm/tetmesh_materials.h"
#include "bpm/version.h"
#include "check/image_tolerance.h"
#include "core/file_util.h"
#include "core/gzip.h"
#include "core/huge_pages.h"
#include "io/bpm_outline.h"
#include "io/chunk_compressor.h"
#include "io/hdf5_fd_driver.h"
#include "phi/phi_layout.h"

namespace bpm {

BpmFormatVersion bpm_format_version() { return {BPM_FORMAT_VERSION_MAJOR, BPM_FORMAT_VERSION_MINOR}; }

namespace {

using detail::ChunkCompressor;
using detail::kDeflateLevel;

// ---------------------------------------------------------------------------
// Small HDF5 helpers
// ---------------------------------------------------------------------------

// Owns one HDF5 identifier and closes it with the right function.
class Handle {
public:
    using Closer = herr_t (*)(hid_t);
    Handle() = default;
    Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    Handle(Handle&& o) noexcept : id_(o.id_), closer_(o.closer_) { o.id_ = -1; }
    Handle& operator=(Handle&& o) noexcept {
        if (this != &o) {
            reset();
            id_ = o.id_;
            closer_ = o.closer_;
            o.id_ = -1;
        }
        return *this;
    }
    ~Handle() { reset(); }
    void reset() {
        if (id_ >= 0 && closer_) closer_(id_);
        id_ = -1;
    }
    // Closes now and says whether that succeeded (closing a file writes what is cached).
    herr_t close() {
        const herr_t status = id_ >= 0 && closer_ ? closer_(id_) : 0;
        id_ = -1;
        return status;
    }
    hid_t get() const { return id_; }
    bool valid() const { return id_ >= 0; }
    operator hid_t() const { return id_; }

private:
    hid_t id_ = -1;
    Closer closer_ = nullptr;
};

// HDF5 prints its error stack to stderr by default; the library never prints, and
// every failure becomes an exception with our own message instead.
void silence_hdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

// The innermost HDF5 error description, appended to messages for diagnosis.
std::string hdf5_error_text() {
    std::string text;
    H5Ewalk2(
        H5E_DEFAULT, H5E_WALK_DOWNWARD,
        [](unsigned n, const H5E_error2_t* err, void* data) -> herr_t {
            auto* out = static_cast<std::string*>(data);
            if (n == 0 && err && err->desc) *out = err->desc;
            return 0;
        },
        &text);
    H5Eclear2(H5E_DEFAULT);
    return text;
}

// ---------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------

constexpr hsize_t kChunkRows = 65536;  // rows per chunk of a compressed dataset
// Datasets of at least this many bytes are chunked and deflated; smaller ones stay
// contiguous. Earlier writers compressed only datasets of more than 16384 rows, which left
// the whole file of a small input raw: elephant (2775 vertices) at --ratio 0.1 had 1.29 MB
// of data that deflate makes 0.58 MB. That costs about 0.05 s CPU on small inputs
// (bpm-simplify femur --vertices 1000: 0.32 -> 0.37 s, elephant --ratio 0.1: 0.27 ->
// 0.32 s, most of it the shuffle trials); reading takes no measurably longer. Below about
// 512 bytes the chunk index and filter message cost more than deflate saves (two_cubes:
// 1024 -> 512 bytes made the file 7 % smaller, 256 no smaller again).
constexpr size_t kCompressMinBytes = 512;

class Writer {
public:
    explicit Writer(std::string where) : where_(std::move(where)) {}

    [[noreturn]] void fail(const std::string& what) const {
        const std::string detail = hdf5_error_text();
        throw OutputError(where_, what + (detail.empty() ? "" : " (HDF5: " + detail + ")"));
    }
    void check(herr_t status, const std::string& what) const {
        if (status < 0) fail(what);
    }
    hid_t check_id(hid_t id, const std::string& what) const {
        if (id < 0) fail(what);
        return id;
    }

    // Object creation property list without timestamps: timestamps would make two
    // runs on the same input give different bytes.
    Handle untimed_plist(hid_t cls) const {
        Handle p(check_id(H5Pcreate(cls), "cannot create a property list"), H5Pclose);
        check(H5Pset_obj_track_times(p, false), "cannot disable object timestamps");
        return p;
    }

    Handle create_group(hid_t parent, const char* name) const {
        Handle gcpl = untimed_plist(H5P_GROUP_CREATE);
        return Handle(check_id(H5Gcreate2(parent, name, H5P_DEFAULT, gcpl, H5P_DEFAULT),
                               std::string("cannot create group ") + name),
                      H5Gclose);
    }

    // A fixed-length string type: VTK 9.1 reads only fixed-length string attributes,
    // and fixed-length strings are the simplest to read with any HDF5 binding.
    Handle string_type(size_t length, H5T_cset_t cset) const {
        Handle t(check_id(H5Tcopy(H5T_C_S1), "cannot create a string type"), H5Tclose);
        check(H5Tset_size(t, std::max<size_t>(length, 1)), "cannot size a string type");
        check(H5Tset_strpad(t, H5T_STR_NULLTERM), "cannot set string padding");
        check(H5Tset_cset(t, cset), "cannot set string character set");
        return t;
    }

    void write_string_attribute(hid_t loc, const char* name, const std::string& value, H5T_cset_t cset) const {
        Handle type = string_type(value.size() + 1, cset);
        Handle space(check_id(H5Screate(H5S_SCALAR), "cannot create a dataspace"), H5Sclose);
        Handle attr(check_id(H5Acreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT),
                             std::string("cannot create attribute ") + name),
                    H5Aclose);
        std::vector<char> buffer(value.size() + 1, '\0');
        std::memcpy(buffer.data(), value.data(), value.size());
        check(H5Awrite(attr, type, buffer.data()), std::string("cannot write attribute ") + name);
    }

    template <typename T>
    void write_int_attribute(hid_t loc, const char* name, const std::vector<T>& values, hid_t file_type,
                             hid_t mem_type) const {
        hsize_t dims[1] = {values.size()};
        Handle space(check_id(H5Screate_simple(1, dims, nullptr), "cannot create a dataspace"), H5Sclose);
        Handle attr(check_id(H5Acreate2(loc, name, file_type, space, H5P_DEFAULT, H5P_DEFAULT),
                             std::string("cannot create attribute ") + name),
                    H5Aclose);
        check(H5Awrite(attr, mem_type, values.data()), std::string("cannot write attribute ") + name);
    }

    // Whether the array given to write_dataset stays in memory, unchanged, until the file
    // is written (the BpmFile's own arrays), or may be gone after the call (a buffer
    // made for it).
    enum class Source { Temporary, Lasting };

    // A 1-D (cols == 0) or 2-D (rows x cols) dataset: chunked and deflated from
    // kCompressMinBytes on (one chunk up to kChunkRows rows), shuffled where that pays;
    // smaller ones contiguous. A Lasting dataset with the same type, shape and bytes as a
    // Lasting one written before is stored as a copy of that one's chunks, read back as
    // stored instead of compressed again: /VTKHDF/Points and /VTKHDF/CellData/patch are
    // /coarse/vertices and /coarse/patches, and at --ratio 1 the coarse surface is the
    // original (bpm-simplify armadillo + 1x Loop --ratio 1: three deflates of 2.5 MB of
    // vertices, ~30 ms each, became one). The bytes of the file are those of compressing
    // them again: the same chunks, filters and order.
    void write_dataset(hid_t group, const char* name, const void* data, hsize_t rows, hsize_t cols,
                       hid_t file_type, hid_t mem_type, Source source = Source::Temporary) const {
        const int rank = cols == 0 ? 1 : 2;
        hsize_t dims[2] = {rows, cols};
        Handle space(check_id(H5Screate_simple(rank, dims, nullptr), "cannot create a dataspace"), H5Sclose);
        Handle dcpl = untimed_plist(H5P_DATASET_CREATE);
#if H5_VERSION_GE(1, 10, 5)
        // No dataset has attributes: without the hint every dataset's object header
        // reserves room for some (about 130 bytes each, a tenth of a small file's metadata).
        check(H5Pset_dset_no_attrs_hint(dcpl, true), std::string("cannot size the object header of ") + name);
#endif
        const size_t element_size = H5Tget_size(mem_type);
        const size_t row_bytes = size_t(std::max<hsize_t>(cols, 1)) * element_size;
        const size_t bytes = size_t(rows) * row_bytes;
        const bool compressed = bytes >= kCompressMinBytes;
        hsize_t chunk[2] = {std::min(rows, kChunkRows), cols};
        const size_t chunk_bytes = size_t(chunk[0]) * row_bytes;
        // The chunks go to the file as compressed here when the bytes in memory are those
        // of the file type (little-endian hosts); otherwise HDF5 converts and filters them.
        bool direct = false;
#if H5_VERSION_GE(1, 10, 3)
        direct = compressed && H5Tequal(file_type, mem_type) > 0;
#endif
        ChunkCompressor::Stored& stored = stored_;
        bool shuffle = false;
        const Written* same = nullptr;  // a Lasting dataset with these bytes, if any
        if (direct && source == Source::Lasting)
            for (const Written& w : lasting_)
                if (w.bytes == bytes && w.rows == rows && w.cols == cols && H5Tequal(w.file_type, file_type) > 0 &&
                    std::memcmp(w.data, data, bytes) == 0) {
                    same = &w;
                    break;
                }
        if (compressed) {
            check(H5Pset_chunk(dcpl, rank, chunk), std::string("cannot set chunking of ") + name);
            // The first chunk is always full (chunk rows = min(rows, kChunkRows)).
            if (same) shuffle = same->shuffle;
            else
                shuffle = compressor_.compress_first_chunk(static_cast<const unsigned char*>(data), chunk_bytes,
                                                           element_size, stored);
            if (shuffle) check(H5Pset_shuffle(dcpl), std::string("cannot set shuffle filter of ") + name);
            check(H5Pset_deflate(dcpl, kDeflateLevel), std::string("cannot set deflate filter of ") + name);
        }
        Handle ds(check_id(H5Dcreate2(group, name, file_type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT),
                           std::string("cannot create dataset ") + name),
                  H5Dclose);
        if (rows == 0 || (cols == 0 && rank == 2)) return;
        if (!direct) {
            check(H5Dwrite(ds, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
                  std::string("cannot write dataset ") + name);
            return;
        }
#if H5_VERSION_GE(1, 10, 3)
        if (same) {
            copy_chunks(same->path, ds, rows, chunk[0], name);
            return;
        }
        if (source == Source::Lasting) {
            std::string path(size_t(std::max<ssize_t>(H5Iget_name(ds, nullptr, 0), 0)), '\0');
            H5Iget_name(ds, path.data(), path.size() + 1);
            lasting_.push_back({data, bytes, rows, cols, file_type, shuffle, std::move(path)});
        }
        // The first chunk is in `stored` already; each chunk is written before the next is
        // compressed into the same buffer. The last chunk of several is padded with zeros to
        // a whole chunk, as HDF5 pads it with the (default, zero) fill value before filtering.
        for (hsize_t row = 0; row < rows; row += chunk[0]) {
            if (row > 0) {
                const auto* in = static_cast<const unsigned char*>(data) + size_t(row) * row_bytes;
                const size_t have = size_t(std::min(rows - row, chunk[0])) * row_bytes;
                compressor_.compress(in, have, chunk_bytes, element_size, shuffle, shuffle, stored);
            }
            const hsize_t offset[2] = {row, 0};
            check(H5Dwrite_chunk(ds, H5P_DEFAULT, stored.filter_mask, offset, stored.size, stored.buffer.data()),
                  std::string("cannot write dataset ") + name);
        }
#endif
    }

#if H5_VERSION_GE(1, 10, 3)
    // Writes the stored chunks of the dataset at `path` into `ds` as they are.
    void copy_chunks(const std::string& path, hid_t ds, hsize_t rows, hsize_t chunk_rows, const char* name) const {
        Handle from(check_id(H5Dopen2(ds, path.c_str(), H5P_DEFAULT), std::string("cannot reopen ") + path), H5Dclose);
        for (hsize_t row = 0; row < rows; row += chunk_rows) {
            const hsize_t offset[2] = {row, 0};
            hsize_t size = 0;
            check(H5Dget_chunk_storage_size(from, offset, &size), std::string("cannot read back ") + path);
            uint32_t mask = 0;
            unsigned char* buffer = stored_.buffer.room(size_t(size));
            check(H5Dread_chunk(from, H5P_DEFAULT, offset, &mask, buffer), std::string("cannot read back ") + path);
            check(H5Dwrite_chunk(ds, H5P_DEFAULT, mask, offset, size_t(size), buffer),
                  std::string("cannot write dataset ") + name);
        }
    }
#endif

    void write_strings(hid_t group, const char* name, const std::vector<std::string>& values) const {
        size_t width = 1;
        for (const auto& s : values) width = std::max(width, s.size() + 1);
        Handle type = string_type(width, H5T_CSET_UTF8);
        std::vector<char> buffer(values.size() * width, '\0');
        for (size_t i = 0; i < values.size(); ++i) std::memcpy(&buffer[i * width], values[i].data(), values[i].size());
        write_dataset(group, name, buffer.data(), values.size(), 0, type, type);
    }

private:
    std::string where_;
    mutable ChunkCompressor compressor_;  // its buffers and deflate state serve every dataset
    // write_dataset's and copy_chunks's: the chunk being written (one buffer for all: each
    // chunk goes to the file before the next is made; a second buffer for the chunks after
    // the first held up to another 1.5 MB at the end of a run, its peak on small inputs).
    mutable ChunkCompressor::Stored stored_;
    // The Lasting datasets written so far (a handful per file: the surfaces').
    struct Written {
        const void* data;
        size_t bytes;
        hsize_t rows, cols;
        hid_t file_type;  // a predefined type: valid as long as the library
        bool shuffle;
        std::string path;
    };
    mutable std::vector<Written> lasting_;
};

// ---------------------------------------------------------------------------
// Semantic checks shared by the writer (refuse to write nonsense) and the reader
// ---------------------------------------------------------------------------

template <typename T>
std::string num(T v) {
    std::ostringstream s;
    s.imbue(std::locale::classic());  // not a host's global locale: no "12.345", no "0,5"
    s.precision(17);
    s << v;
    return s.str();
}

// The file-format wording of a layout problem: the dataset path first, then the entry.
std::string layout_message(const Parametrization& p, const detail::LayoutProblem& pr) {
    using detail::LayoutRule;
    using detail::PhiArray;
    const bool on_surface = pr.array == PhiArray::Vertices || pr.array == PhiArray::Triangles ||
                            pr.array == PhiArray::Patches;
    const Surface& s = pr.surface == detail::SurfaceRole::Original ? p.original : p.coarse;
    const std::string group = pr.surface == detail::SurfaceRole::Original ? "/original" : "/coarse";
    const std::string path = on_surface                          ? group + "/" + detail::phi_array_name(pr.array)
                             : pr.array == PhiArray::VertexOrigin ? std::string("/coarse/vertex_origin")
                                                                  : std::string("/phi/") + detail::phi_array_name(pr.array);
    const size_t e = static_cast<size_t>(pr.element);
    switch (pr.rule) {
        case LayoutRule::NotFinite:
            if (pr.array == PhiArray::Vertices)
                return path + ": entry [" + num(pr.element) + ", " + num(pr.component) + "] is not finite (" +
                       num(s.vertices[e][pr.component]) + ")";
            if (pr.array == PhiArray::NodeEdgeParameter)
                return path + ": entry " + num(pr.element) + " = " + num(p.node_edge_parameter[e]) +
                       " is not in [0, 1] for an edge crossing";
            return path + ": entry [" + num(pr.element) + ", " + num(pr.component) + "] is not finite";
        case LayoutRule::CountMismatch:
            if (pr.array == PhiArray::Patches)
                return path + ": has " + num(pr.value) + " entries but " + group + "/triangles has " + num(pr.limit) +
                       " rows";
            if (pr.array == PhiArray::VertexOrigin)
                return path + ": has " + num(pr.value) + " entries but /coarse/vertices has " + num(pr.limit) + " rows";
            if (pr.array == PhiArray::PieceOriginalTriangle)
                return path + ": has " + num(pr.value) + " entries but /phi/pieces has " + num(pr.limit) + " rows";
            return path + ": has " + num(pr.value) + " rows but /phi/node_kind has " + num(pr.limit);
        case LayoutRule::OutOfRange: {
            const std::string range = " is out of range [0, " + num(pr.limit) + ")";
            if (pr.array == PhiArray::Triangles)
                return path + ": entry [" + num(pr.element) + ", " + num(pr.component) + "] = " + num(pr.value) + range +
                       " (number of rows of " + group + "/vertices)";
            if (pr.array == PhiArray::Pieces)
                return path + ": entry [" + num(pr.element) + ", " + num(pr.component) + "] = " + num(pr.value) + range +
                       " (the nodes of coarse triangle " + num(pr.coarse_triangle) + ")";
            const std::string entry = path + ": entry " + num(pr.element) + " = " + num(pr.value) + range;
            if (pr.array == PhiArray::VertexOrigin) return entry + " (number of rows of /original/vertices)";
            if (pr.array == PhiArray::PieceOriginalTriangle) return entry + " (number of rows of /original/triangles)";
            return entry + " for a node of kind " + num(static_cast<int>(p.node_kind[e]));
        }
        case LayoutRule::OffsetsCount:
            return path + ": has " + num(pr.value) + " entries, expected " + num(pr.limit) +
                   " (number of rows of /coarse/triangles + 1)";
        case LayoutRule::OffsetsStart: return path + ": entry 0 is " + num(pr.value) + ", must be 0";
        case LayoutRule::OffsetsDecreasing:
            return path + ": entry " + num(pr.element) + " = " + num(pr.value) + " is smaller than entry " +
                   num(pr.element - 1) + " = " + num(pr.limit) + "; offsets must be non-decreasing";
        case LayoutRule::OffsetsEnd:
            return path + ": last entry is " + num(pr.value) + " but " +
                   (pr.array == PhiArray::NodeOffsets ? "/phi/node_kind" : "/phi/pieces") + " has " + num(pr.limit) +
                   " rows";
        case LayoutRule::InvalidNodeKind:
            return path + ": entry " + num(pr.element) + " = " + num(pr.value) + " is not a valid node kind (0, 1 or 2)";
        case LayoutRule::NotAnEdge: {
            const auto& oe = p.node_original_edge[e];
            return path + ": row " + num(pr.element) + " = (" + num(oe[0]) + ", " + num(oe[1]) +
                   ") is not an edge (u, w) with 0 <= u < w < " + num(pr.limit);
        }
    }
    return path + ": invalid";
}

// Returns an empty string if `file` satisfies every rule of the spec that the format
// itself can check, otherwise the first violation, beginning with the dataset path.
// The layout (sizes, offsets, index ranges, kinds, finite numbers) is checked by
// detail::visit_phi_layout, shared with bpm-check; the value rules below it are the
// reader's own (bpm-check applies stricter ones in check_format.cpp).
std::string find_inconsistency(const BpmFile& file) {
    const Parametrization& p = file.param;
    std::string first;
    detail::visit_phi_layout(p, [&](const detail::LayoutProblem& pr) {
        first = layout_message(p, pr);
        return false;
    });
    if (!first.empty()) return first;
    if (const auto bad = vertex_data_problems(p.original); !bad.empty()) return "/original/point_data: " + bad[0];
    for (const VertexArray& a : p.original.vertex_data)
        for (size_t i = 0; i < a.values.size(); ++i)
            if (!std::isfinite(a.values[i]))
                return "/original/point_data/" + a.name + ": entry [" + num(i / size_t(a.components)) + ", " +
                       num(i % size_t(a.components)) + "] is not finite (" + num(a.values[i]) + ")";
    if (p.original.vertices.size() > size_t(std::numeric_limits<int32_t>::max()) ||
        p.original.triangles.size() > size_t(std::numeric_limits<int32_t>::max()) ||
        p.coarse.vertices.size() > size_t(std::numeric_limits<int32_t>::max()) ||
        p.coarse.triangles.size() > size_t(std::numeric_limits<int32_t>::max()))
        return "/original or /coarse: more than 2^31-1 vertices or triangles";

    // Value rules; the layout above makes every index safe.
    const int64_t ntc = p.coarse.num_triangles();
    for (int64_t t = 0; t < ntc; ++t) {
        const Tri& tri = p.coarse.triangles[static_cast<size_t>(t)];
        for (int64_t i = p.node_offsets[static_cast<size_t>(t)]; i < p.node_offsets[static_cast<size_t>(t) + 1]; ++i) {
            const size_t n = static_cast<size_t>(i);
            const Vec3& b = p.node_barycentric[n];
            for (int c = 0; c < 3; ++c)
                if (b[c] < 0)
                    return "/phi/node_barycentric: entry [" + num(i) + ", " + num(c) + "] = " + num(b[c]) +
                           " is negative";
            if (std::fabs(b[0] + b[1] + b[2] - 1) > 1e-9)
                return "/phi/node_barycentric: row " + num(i) + " sums to " + num(b[0] + b[1] + b[2]) + ", not 1";
            const int kind = static_cast<int>(p.node_kind[n]);
            const int32_t ov = p.node_original_vertex[n];
            const auto& oe = p.node_original_edge[n];
            const double s = p.node_edge_parameter[n];
            if (kind == int(NodeKind::OriginalVertex) || kind == int(NodeKind::CoarseCorner)) {
                if (oe[0] != -1 || oe[1] != -1)
                    return "/phi/node_original_edge: row " + num(i) + " must be (-1, -1) for a node of kind " + num(kind);
                if (kind == int(NodeKind::CoarseCorner)) {
                    int corner = -1;
                    for (int c = 0; c < 3; ++c)
                        if (b[c] == 1) corner = c;
                    if (corner < 0)
                        return "/phi/node_barycentric: row " + num(i) +
                               " is a coarse corner (kind 2) but not a unit vector";
                    const int32_t expected = p.coarse_vertex_origin[static_cast<size_t>(tri[corner])];
                    if (ov != expected)
                        return "/phi/node_original_vertex: entry " + num(i) + " = " + num(ov) + " is corner " +
                               num(corner) + " of coarse triangle " + num(t) + ", whose /coarse/vertex_origin is " +
                               num(expected);
                }
            } else {  // EdgeCrossing: the layout admits no other kind
                if (ov != -1)
                    return "/phi/node_original_vertex: entry " + num(i) + " must be -1 for an edge crossing (kind 1)";
                if (!(s >= 0 && s <= 1))
                    return "/phi/node_edge_parameter: entry " + num(i) + " = " + num(s) +
                           " is not in [0, 1] for an edge crossing";
                if (b[0] != 0 && b[1] != 0 && b[2] != 0)
                    return "/phi/node_barycentric: row " + num(i) +
                           " is an edge crossing (kind 1) but has no coordinate exactly 0 (not on a coarse edge)";
            }
        }
    }
    return {};
}

// The rows of a vector of fixed-size arrays as the flat buffer HDF5 writes: std::array
// holds its elements without padding, so no copy is needed (copies of every φ array
// were a third of the writer's peak memory).
static_assert(sizeof(Vec3) == 3 * sizeof(double) && sizeof(Tri) == 3 * sizeof(int32_t) &&
              sizeof(std::array<int32_t, 2>) == 2 * sizeof(int32_t) && sizeof(NodeKind) == sizeof(uint8_t));
template <typename T, size_t N>
const T* flat(const std::vector<std::array<T, N>>& v) {
    return v.empty() ? nullptr : v.front().data();
}

void write_surface(const Writer& w, hid_t group, const Surface& s) {
    const double* xyz = flat(s.vertices);
    const int32_t* tri = flat(s.triangles);
    constexpr auto lasting = Writer::Source::Lasting;  // the BpmFile's arrays
    w.write_dataset(group, "vertices", xyz, s.vertices.size(), 3, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, lasting);
    w.write_dataset(group, "triangles", tri, s.triangles.size(), 3, H5T_STD_I32LE, H5T_NATIVE_INT32, lasting);
    w.write_dataset(group, "patches", s.patches.data(), s.patches.size(), 0, H5T_STD_I32LE, H5T_NATIVE_INT32,
                    lasting);
}

std::atomic<unsigned> g_image_counter{0};

// The optional /tetmesh group (spec/tetmesh.md); written only when the file has a mesh,
// so files without one keep their exact bytes.
void write_tetmesh_group(const Writer& w, hid_t f, const TetMesh& m) {
    Handle g = w.create_group(f, "tetmesh");
    w.write_int_attribute(g, "level", std::vector<int32_t>{m.level}, H5T_STD_I32LE, H5T_NATIVE_INT32);
    const double* xyz = flat(m.vertices);
    w.write_dataset(g, "vertices", xyz, m.vertices.size(), 3, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE);
    std::vector<int32_t> tets;
    tets.reserve(4 * m.tetrahedra.size());
    for (const auto& t : m.tetrahedra) tets.insert(tets.end(), t.begin(), t.end());
    w.write_dataset(g, "tetrahedra", tets.data(), m.tetrahedra.size(), 4, H5T_STD_I32LE, H5T_NATIVE_INT32);
    w.write_dataset(g, "regions", m.regions.data(), m.regions.size(), 0, H5T_STD_I32LE, H5T_NATIVE_INT32);
    const int32_t* faces = flat(m.faces);
    w.write_dataset(g, "faces", faces, m.faces.size(), 3, H5T_STD_I32LE, H5T_NATIVE_INT32);
    w.write_dataset(g, "face_coarse_triangle", m.face_coarse_triangle.data(), m.face_coarse_triangle.size(), 0,
                    H5T_STD_I32LE, H5T_NATIVE_INT32);
    w.write_dataset(g, "face_patches", m.face_patches.data(), m.face_patches.size(), 0, H5T_STD_I32LE,
                    H5T_NATIVE_INT32);
    w.write_dataset(g, "vertex_coarse_vertex", m.vertex_coarse_vertex.data(), m.vertex_coarse_vertex.size(), 0,
                    H5T_STD_I32LE, H5T_NATIVE_INT32);
    // The parameter points as two datasets (spec/tetmesh.md): triangles, barycentrics.
    std::vector<int32_t> parameter_triangles(m.vertex_parameter_points.size());
    std::vector<double> bary(3 * m.vertex_parameter_points.size());
    for (size_t v = 0; v < m.vertex_parameter_points.size(); ++v) {
        parameter_triangles[v] = m.vertex_parameter_points[v].triangle;
        for (int c = 0; c < 3; ++c) bary[3 * v + c] = m.vertex_parameter_points[v].barycentric[c];
    }
    w.write_dataset(g, "vertex_parameter_triangle", parameter_triangles.data(), parameter_triangles.size(), 0,
                    H5T_STD_I32LE, H5T_NATIVE_INT32);
    w.write_dataset(g, "vertex_parameter_barycentric", bary.data(), m.vertex_parameter_points.size(), 3,
                    H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE);
    if (!m.tet_ancestor.empty())
        w.write_dataset(g, "tet_ancestor", m.tet_ancestor.data(), m.tet_ancestor.size(), 0, H5T_STD_I32LE,
                        H5T_NATIVE_INT32);
    // Materials (format 1.3): only when assigned, so meshes without keep their bytes.
    if (!m.material_names.empty()) {
        w.write_dataset(g, "region_material", m.region_material.data(), m.region_material.size(), 0, H5T_STD_I32LE,
                        H5T_NATIVE_INT32);
        w.write_strings(g, "material_names", m.material_names);
    }
}

// The optional /patch_info group (format 1.3, spec/bpm-format.md §5.2); written only when
// something is known, so files without keep their layout.
void write_patch_info_group(const Writer& w, hid_t f, const std::vector<PatchInfo>& infos) {
    Handle g = w.create_group(f, "patch_info");
    std::vector<int32_t> patch;
    std::vector<int8_t> oriented;
    std::vector<std::string> name, front, back;
    for (const PatchInfo& i : infos) {
        patch.push_back(i.patch);
        oriented.push_back(i.oriented ? 1 : 0);
        name.push_back(i.name);
        front.push_back(i.front);
        back.push_back(i.back);
    }
    w.write_dataset(g, "patch", patch.data(), patch.size(), 0, H5T_STD_I32LE, H5T_NATIVE_INT32);
    w.write_strings(g, "name", name);
    w.write_strings(g, "front_material", front);
    w.write_strings(g, "back_material", back);
    w.write_dataset(g, "oriented", oriented.data(), oriented.size(), 0, H5T_STD_I8LE, H5T_NATIVE_INT8);
}

// ---------------------------------------------------------------------------
// The optional /simplification_steps group (format 1.1, spec/bpm-format.md §10.1):
// the record of bpm-simplify --record-steps. Self-contained: the checks, the writer
// and (below, after Reader) the reader of this group.
// ---------------------------------------------------------------------------

// The first violation of the rules of §10.1 that the format itself can check (sizes,
// CSR offsets, index ranges), beginning with the dataset path; empty if none. What the
// steps mean (is each a valid point removal?) is bpm-check --replay's business.
std::string find_steps_inconsistency(const SimplificationSteps& s, int64_t nv0) {
    const std::string g = "/simplification_steps";
    const int64_t ns = s.num_steps(), nr = s.num_triangles();
    if (static_cast<int64_t>(s.triangle_offsets.size()) != ns + 1)
        return g + "/triangle_offsets: has " + num(s.triangle_offsets.size()) + " entries, expected " + num(ns + 1) +
               " (entries of " + g + "/vertex + 1)";
    if (static_cast<int64_t>(s.triangle_patches.size()) != nr)
        return g + "/triangle_patches: has " + num(s.triangle_patches.size()) + " entries but " + g +
               "/triangles has " + num(nr) + " rows";
    for (int64_t i = 0; i < ns; ++i) {
        const int64_t v = s.vertex[static_cast<size_t>(i)];
        if (v < 0 || v >= nv0)
            return g + "/vertex: entry " + num(i) + " = " + num(v) + " is out of range [0, " + num(nv0) +
                   ") (number of rows of /original/vertices)";
    }
    if (s.triangle_offsets[0] != 0)
        return g + "/triangle_offsets: entry 0 is " + num(s.triangle_offsets[0]) + ", must be 0";
    for (size_t i = 1; i < s.triangle_offsets.size(); ++i)
        if (s.triangle_offsets[i] < s.triangle_offsets[i - 1])
            return g + "/triangle_offsets: entry " + num(i) + " = " + num(s.triangle_offsets[i]) +
                   " is smaller than entry " + num(i - 1) + " = " + num(s.triangle_offsets[i - 1]) +
                   "; offsets must be non-decreasing";
    if (s.triangle_offsets.back() != nr)
        return g + "/triangle_offsets: last entry is " + num(s.triangle_offsets.back()) + " but " + g +
               "/triangles has " + num(nr) + " rows";
    for (int64_t t = 0; t < nr; ++t)
        for (int c = 0; c < 3; ++c) {
            const int64_t v = s.triangles[static_cast<size_t>(t)][c];
            if (v < 0 || v >= nv0)
                return g + "/triangles: entry [" + num(t) + ", " + num(c) + "] = " + num(v) + " is out of range [0, " +
                       num(nv0) + ") (number of rows of /original/vertices)";
        }
    return {};
}

// Written only when the file has a record, so files without one keep their exact bytes.
void write_simplification_steps_group(const Writer& w, hid_t f, const SimplificationSteps& s) {
    Handle g = w.create_group(f, "simplification_steps");
    w.write_dataset(g, "vertex", s.vertex.data(), s.vertex.size(), 0, H5T_STD_I32LE, H5T_NATIVE_INT32);
    w.write_dataset(g, "triangle_offsets", s.triangle_offsets.data(), s.triangle_offsets.size(), 0, H5T_STD_I64LE,
                    H5T_NATIVE_INT64);
    const int32_t* tri = flat(s.triangles);
    w.write_dataset(g, "triangles", tri, s.triangles.size(), 3, H5T_STD_I32LE, H5T_NATIVE_INT32);
    w.write_dataset(g, "triangle_patches", s.triangle_patches.data(), s.triangle_patches.size(), 0, H5T_STD_I32LE,
                    H5T_NATIVE_INT32);
}

// The first node whose image (Parametrization::node_image) is not the point the node names,
// or "". Files store no images since format 2.0 and readers compute each from its node
// (spec §6.2), so a caller's image that is not that point would be replaced silently when
// the file is read; within bpm-check's tolerance (check/image_tolerance.h) it is the same
// point. Only for a parametrization find_inconsistency accepts (every index is safe).
std::string image_problem(const Parametrization& p) {
    const double tolerance = detail::kImageToleranceRelativeToDiagonal * bounding_box_diagonal(p.original);
    for (int64_t i = 0; i < p.num_nodes(); ++i) {
        const Vec3 named = node_image_from_kind(p, i);
        const Vec3& image = p.node_image[static_cast<size_t>(i)];
        if (const double d = distance(named, image); !(d <= tolerance)) {
            const auto point = [](const Vec3& x) { return "(" + num(x[0]) + ", " + num(x[1]) + ", " + num(x[2]) + ")"; };
            return "node_image[" + num(i) + "] = " + point(image) + " is not the point its node names, " + point(named) +
                   " (distance " + num(d) +
                   "): files store no images since format 2.0, readers compute them from the node kinds "
                   "(bpm::node_images_from_kinds)";
        }
    }
    return {};
}

// Throws OutputError if `file` breaks a rule of the format: nothing inconsistent is written.
void check_writable(const BpmFile& file, const std::string& where) {
    if (auto problem = find_inconsistency(file); !problem.empty())
        throw OutputError(where, "refusing to write an inconsistent parametrization: " + problem);
    if (auto problem = image_problem(file.param); !problem.empty())
        throw OutputError(where, "refusing to write an inconsistent parametrization: " + problem);
    if (auto problem = patch_info_problem(file.patch_info); !problem.empty())
        throw OutputError(where, "refusing to write inconsistent patch information: /patch_info: " + problem);
    if (file.tetmesh)
        if (auto problem = find_tetmesh_inconsistency(*file.tetmesh, file.param.coarse); !problem.empty())
            throw OutputError(where, "refusing to write an inconsistent tetrahedral mesh: " + problem);
    if (file.tetmesh)
        if (auto problem = find_material_inconsistency(*file.tetmesh); !problem.empty())
            throw OutputError(where, "refusing to write an inconsistent tetrahedral mesh: " + problem);
    if (file.simplification_steps)
        if (auto problem = find_steps_inconsistency(*file.simplification_steps, file.param.original.num_vertices());
            !problem.empty())
            throw OutputError(where, "refusing to write an inconsistent record of simplification steps: " + problem);
}

// Creates the HDF5 file `name` through the driver of `fapl`. The library's default
// (earliest) object formats on purpose: with the 1.8 formats the superblock carries a
// checksum that H5Fget_file_image (HDF5 1.10.8) leaves stale for images of files still
// open, and other readers then reject the file (and the 1.8 formats made the files of
// the benchmark meshes 3-7 % larger, not smaller). Both drivers give the same bytes.
//
// Metadata settings that every HDF5 reader since 1.6 reads (superblock version 1): with
// the default B-tree sizes (K = 32 and 16) every chunked dataset's chunk index is a 2.6 kB
// node with room for 64 chunks, and every group's a 0.9 kB node for 32 symbol-table
// leaves, while a dataset of a small file has one chunk and a group at most a dozen links.
// K = 2 gives nodes of 4 entries (deeper trees for the large datasets cost a few lookups);
// K = 1, the smallest HDF5 allows, saved another 1.5 kB on small files but made the chunk
// indexes of armadillo + 2x Loop (19 chunks per large dataset) 219 kB instead of 20 kB.
// Without the metadata and small-data aggregation blocks (2 kB each by default) objects
// are allocated where they end rather than in blocks whose unused tails stay in the file.
// Together with compressing datasets from 512 bytes on: two_cubes (the smallest
// benchmark file) 106 -> 29 kB, of which 15 kB is data.
Handle create_file(const Writer& w, const std::string& name, hid_t fapl) {
    Handle fcpl = w.untimed_plist(H5P_FILE_CREATE);
    w.check(H5Pset_istore_k(fcpl, 2), "cannot set the chunk index node size");
    w.check(H5Pset_sym_k(fcpl, 2, 4), "cannot set the group node size");
    w.check(H5Pset_meta_block_size(fapl, 0), "cannot set the metadata block size");
    w.check(H5Pset_small_data_block_size(fapl, 0), "cannot set the small data block size");
    return Handle(w.check_id(H5Fcreate(name.c_str(), H5F_ACC_TRUNC, fcpl, fapl), "cannot create the HDF5 file"),
                  H5Fclose);
}

// Writes every group and dataset of `file` into the new, empty HDF5 file `f`.
void write_contents(const Writer& w, hid_t f, const BpmFile& file) {
    const Parametrization& p = file.param;

    // Root identification.
    w.write_string_attribute(f, "format", "bpm", H5T_CSET_ASCII);
    const std::vector<int32_t> version{BPM_FORMAT_VERSION_MAJOR, BPM_FORMAT_VERSION_MINOR};
    w.write_int_attribute(f, "format_version", version, H5T_STD_I32LE, H5T_NATIVE_INT32);
    w.write_string_attribute(f, "units", file.units, H5T_CSET_UTF8);

    {
        Handle g = w.create_group(f, "original");
        write_surface(w, g, p.original);
        if (!p.original.vertex_data.empty()) {
            Handle pd = w.create_group(g, "point_data");
            for (const VertexArray& a : p.original.vertex_data)
                w.write_dataset(pd, a.name.c_str(), a.values.data(), p.original.vertices.size(),
                                static_cast<hsize_t>(a.components), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE);
        }
    }
    {
        Handle g = w.create_group(f, "coarse");
        write_surface(w, g, p.coarse);
        w.write_dataset(g, "vertex_origin", p.coarse_vertex_origin.data(), p.coarse_vertex_origin.size(), 0,
                        H5T_STD_I32LE, H5T_NATIVE_INT32);
    }
    {
        Handle g = w.create_group(f, "phi");
        const hsize_t nn = static_cast<hsize_t>(p.num_nodes());
        w.write_dataset(g, "node_offsets", p.node_offsets.data(), p.node_offsets.size(), 0, H5T_STD_I64LE,
                        H5T_NATIVE_INT64);
        const double* bary = flat(p.node_barycentric);
        w.write_dataset(g, "node_barycentric", bary, nn, 3, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE);
        // No node_image since format 2.0: it was a third of a simplified file (armadillo
        // 10 %: 1.84 of 5.40 MB) and readers compute it from the node kinds
        // (node_images_from_kinds, spec §6.2) to the same bits.
        w.write_dataset(g, "node_kind", p.node_kind.data(), nn, 0, H5T_STD_U8LE, H5T_NATIVE_UINT8);
        w.write_dataset(g, "node_original_vertex", p.node_original_vertex.data(), nn, 0, H5T_STD_I32LE,
                        H5T_NATIVE_INT32);
        w.write_dataset(g, "node_original_edge", flat(p.node_original_edge), nn, 2, H5T_STD_I32LE, H5T_NATIVE_INT32);
        // NaN for non-crossings is written as the one canonical quiet NaN so that the
        // bytes do not depend on how the caller produced its NaNs.
        // (A copy only when some entry is not that NaN already.)
        const auto canonical = [](double x) {
            const double nan = std::numeric_limits<double>::quiet_NaN();
            return std::memcmp(&x, &nan, sizeof x) == 0;
        };
        std::vector<double> params;
        for (size_t i = 0; i < p.node_edge_parameter.size() && params.empty(); ++i)
            if (p.node_kind[i] != NodeKind::EdgeCrossing && !canonical(p.node_edge_parameter[i]))
                params = p.node_edge_parameter;
        for (size_t i = 0; i < params.size(); ++i)
            if (p.node_kind[i] != NodeKind::EdgeCrossing) params[i] = std::numeric_limits<double>::quiet_NaN();
        w.write_dataset(g, "node_edge_parameter", params.empty() ? p.node_edge_parameter.data() : params.data(), nn, 0, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE);
        w.write_dataset(g, "piece_offsets", p.piece_offsets.data(), p.piece_offsets.size(), 0, H5T_STD_I64LE,
                        H5T_NATIVE_INT64);
        const int32_t* pieces = flat(p.pieces);
        w.write_dataset(g, "pieces", pieces, p.pieces.size(), 3, H5T_STD_I32LE, H5T_NATIVE_INT32);
        w.write_dataset(g, "piece_original_triangle", p.piece_original_triangle.data(),
                        p.piece_original_triangle.size(), 0, H5T_STD_I32LE, H5T_NATIVE_INT32);
    }
    {
        Handle g = w.create_group(f, "provenance");
        std::vector<std::string> tool, version_, arguments, timestamp;
        for (const auto& step : file.provenance) {
            tool.push_back(step.tool);
            version_.push_back(step.version);
            arguments.push_back(step.arguments);
            timestamp.push_back(step.timestamp);
        }
        w.write_strings(g, "tool", tool);
        w.write_strings(g, "version", version_);
        w.write_strings(g, "arguments", arguments);
        w.write_strings(g, "timestamp", timestamp);
    }
    {
        // The coarse surface as a VTKHDF 1.0 UnstructuredGrid, so that ParaView opens the
        // file directly. Derived data: bpm readers ignore it.
        Handle g = w.create_group(f, "VTKHDF");
        w.write_int_attribute(g, "Version", std::vector<int64_t>{1, 0}, H5T_STD_I64LE, H5T_NATIVE_INT64);
        w.write_string_attribute(g, "Type", "UnstructuredGrid", H5T_CSET_ASCII);
        const Surface& s = p.coarse;
        const int64_t nv = s.num_vertices(), nt = s.num_triangles();
        const std::vector<int64_t> npoints{nv}, ncells{nt}, nconn{3 * nt};
        w.write_dataset(g, "NumberOfPoints", npoints.data(), 1, 0, H5T_STD_I64LE, H5T_NATIVE_INT64);
        w.write_dataset(g, "NumberOfCells", ncells.data(), 1, 0, H5T_STD_I64LE, H5T_NATIVE_INT64);
        w.write_dataset(g, "NumberOfConnectivityIds", nconn.data(), 1, 0, H5T_STD_I64LE, H5T_NATIVE_INT64);
        const double* xyz = flat(s.vertices);
        w.write_dataset(g, "Points", xyz, s.vertices.size(), 3, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                        Writer::Source::Lasting);
        std::vector<int64_t> connectivity;
        detail::reserve_huge_pages(connectivity, 3 * s.triangles.size());
        for (const auto& t : s.triangles) connectivity.insert(connectivity.end(), t.begin(), t.end());
        w.write_dataset(g, "Connectivity", connectivity.data(), connectivity.size(), 0, H5T_STD_I64LE,
                        H5T_NATIVE_INT64);
        std::vector<int64_t> offsets(s.triangles.size() + 1);
        for (size_t i = 0; i < offsets.size(); ++i) offsets[i] = 3 * static_cast<int64_t>(i);
        w.write_dataset(g, "Offsets", offsets.data(), offsets.size(), 0, H5T_STD_I64LE, H5T_NATIVE_INT64);
        const std::vector<uint8_t> types(s.triangles.size(), 5);  // VTK_TRIANGLE
        w.write_dataset(g, "Types", types.data(), types.size(), 0, H5T_STD_U8LE, H5T_NATIVE_UINT8);
        Handle cd = w.create_group(g, "CellData");
        w.write_dataset(cd, "patch", s.patches.data(), s.patches.size(), 0, H5T_STD_I32LE, H5T_NATIVE_INT32,
                        Writer::Source::Lasting);
        Handle pd = w.create_group(g, "PointData");
        Handle fd = w.create_group(g, "FieldData");
    }
    if (file.tetmesh) write_tetmesh_group(w, f, *file.tetmesh);
    if (file.simplification_steps) write_simplification_steps_group(w, f, *file.simplification_steps);
    if (!file.patch_info.empty()) write_patch_info_group(w, f, file.patch_info);
}

// The whole file as bytes, built in memory (core driver, no backing store): for standard
// output and write_bpm_to_memory.
std::string build_image(const BpmFile& file, const std::string& where) {
    silence_hdf5();
    check_writable(file, where);
    const Parametrization& p = file.param;
    Writer w(where);
    // In-memory file; the name only has to be unique among files open in this process.
    // The driver grows its buffer by a fixed increment, and every growth copies the whole
    // image (realloc) and zeroes the new part: 1 MB steps made writing quadratic in the
    // file size (23 growths for the 23.8 MB .bpm of a 208k-triangle input). An eighth of the
    // uncompressed size of phi and the surfaces bounds the copies to about eight, and the
    // zeroed overshoot to an eighth of that.
    const size_t raw_bytes = p.node_kind.size() * (2 * sizeof(Vec3) + 1 + 4 + 8 + 8) +
                             p.pieces.size() * (sizeof(Tri) + 4) + p.node_offsets.size() * 16 +
                             p.original.vertices.size() * sizeof(Vec3) + p.original.triangles.size() * 16 +
                             p.coarse.vertices.size() * 2 * sizeof(Vec3) + p.coarse.triangles.size() * 64;
    const size_t increment = std::min(size_t(64) << 20, std::max(size_t(1) << 20, raw_bytes / 8));
    Handle fapl(w.check_id(H5Pcreate(H5P_FILE_ACCESS), "cannot create file access properties"), H5Pclose);
    w.check(H5Pset_fapl_core(fapl, increment, false), "cannot select the in-memory driver");
    Handle f = create_file(w, "bpm-write-" + std::to_string(g_image_counter++) + ".h5", fapl);
    write_contents(w, f, file);
    w.check(H5Fflush(f, H5F_SCOPE_GLOBAL), "cannot flush the in-memory file");
    const ssize_t size = H5Fget_file_image(f, nullptr, 0);
    if (size <= 0) w.fail("cannot get the size of the in-memory file image");
    std::string bytes(static_cast<size_t>(size), '\0');
    if (H5Fget_file_image(f, bytes.data(), bytes.size()) != size) w.fail("cannot copy the in-memory file image");
    return bytes;
}

// Writes `file` to `path` directly: HDF5 writes each chunk and the metadata as it goes,
// into the unnamed temporary file of detail::write_file_atomically, renamed into place
// when complete. Building the image in memory first held the whole file twice beside phi
// (the core driver's buffer and the copy handed to the writer): ~48 MB for the 24 MB
// .bpm of a 208k-triangle input, the largest item at the end of a run.
void write_file(const BpmFile& file, const std::string& path) {
    silence_hdf5();
    check_writable(file, path);
    detail::write_file_atomically(path, [&](int fd) {
        const Writer w(path);
        detail::FdDriverStatus status;
        Handle fapl(w.check_id(detail::fd_driver_access_plist(fd, &status), "cannot set up the file driver"),
                    H5Pclose);
        {
            Handle f = create_file(w, "bpm-write-" + std::to_string(g_image_counter++) + ".h5", fapl);
            write_contents(w, f, file);
            w.check(f.close(), "cannot close the file");
        }
        if (status.error != 0) throw OutputError(path, std::string("cannot write: ") + std::strerror(status.error));
    });
}

// ---------------------------------------------------------------------------
// Reading
// ---------------------------------------------------------------------------

// Storage limits: a dataset's logical size may not exceed what the file can hold.
// Compressed data can be up to ~1032x smaller than its content (deflate's limit), so
// filtered datasets get that much room; unfiltered ones must fit in the file. This keeps
// a small hostile file from making us allocate gigabytes.
constexpr double kMaxCompressionRatio = 1100;
constexpr hsize_t kMaxRows = hsize_t(1) << 40;

// The results of a Reader's calls, in call order. The isolated child records them
// while it parses with HDF5 (read_checked); the parent replays them, so that it runs
// our parsing and validation on exactly what the child saw without calling HDF5 on
// the bytes itself (once per file instead of twice, and never in-process).
class Tape {
public:
    Tape() = default;
    explicit Tape(std::string bytes) : bytes_(std::move(bytes)) {}
    std::string& bytes() { return bytes_; }
    bool finished() const { return pos_ == bytes_.size(); }

    template <class T>
    void put(const T& value) {
        static_assert(std::is_trivially_copyable_v<T>);
        bytes_.append(reinterpret_cast<const char*>(&value), sizeof value);
    }
    template <class T>
    void put(const std::vector<T>& values) {
        put<uint64_t>(values.size());
        bytes_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
    }
    void put(const std::string& text) {
        put<uint64_t>(text.size());
        bytes_.append(text);
    }
    void put(const std::vector<std::string>& texts) {
        put<uint64_t>(texts.size());
        for (const std::string& t : texts) put(t);
    }
    // Integers are read as int64 but mostly stored as int32: recorded as 32-bit values
    // when they all fit, which halves the tape.
    void put_ints(const std::vector<int64_t>& values) {
        const bool narrow = std::all_of(values.begin(), values.end(), [](int64_t v) {
            return v >= std::numeric_limits<int32_t>::min() && v <= std::numeric_limits<int32_t>::max();
        });
        put<uint8_t>(narrow ? 4 : 8);
        if (!narrow) return put(values);
        put<uint64_t>(values.size());
        const size_t at = bytes_.size();
        bytes_.resize(at + values.size() * sizeof(int32_t));
        for (size_t i = 0; i < values.size(); ++i) {
            const int32_t v = static_cast<int32_t>(values[i]);
            std::memcpy(&bytes_[at + i * sizeof v], &v, sizeof v);
        }
    }

    template <class T>
    T get() {
        static_assert(std::is_trivially_copyable_v<T>);
        T value;
        std::memcpy(&value, take(sizeof value), sizeof value);
        return value;
    }
    template <class T>
    std::vector<T> get_vector() {
        const auto n = get<uint64_t>();
        if (n > (bytes_.size() - pos_) / sizeof(T)) corrupt();
        std::vector<T> out(static_cast<size_t>(n));
        if (n) std::memcpy(out.data(), take(n * sizeof(T)), n * sizeof(T));
        return out;
    }
    std::vector<int64_t> get_ints() {
        if (get<uint8_t>() == 8) return get_vector<int64_t>();
        const std::vector<int32_t> narrow = get_vector<int32_t>();
        return std::vector<int64_t>(narrow.begin(), narrow.end());
    }
    std::string get_string() {
        const auto n = get<uint64_t>();
        if (n > bytes_.size() - pos_) corrupt();
        return std::string(take(n), static_cast<size_t>(n));
    }
    std::vector<std::string> get_strings() {
        const auto n = get<uint64_t>();
        if (n > bytes_.size() - pos_) corrupt();
        std::vector<std::string> out(static_cast<size_t>(n));
        for (auto& t : out) t = get_string();
        return out;
    }

private:
    std::string bytes_;
    size_t pos_ = 0;
    const char* take(uint64_t n) {
        if (n > bytes_.size() - pos_) corrupt();
        const char* p = bytes_.data() + pos_;
        pos_ += static_cast<size_t>(n);
        return p;
    }
    // Only a bug could get here: the tape comes from a copy of this process running the
    // same code on the same bytes.
    [[noreturn]] static void corrupt() { throw AlgorithmError("internal error: the replayed HDF5 reads ran out"); }
};

class Reader {
public:
    Reader(std::string where, size_t file_size) : where_(std::move(where)), file_size_(file_size) {}
    // At most one of the two: record every result on `record` (while reading with
    // HDF5), or take every result from `replay` instead of HDF5.
    void set_tape(Tape* record, Tape* replay) {
        record_ = record;
        replay_ = replay;
    }
    bool replaying() const { return replay_ != nullptr; }

    [[noreturn]] void fail(const std::string& what) const { throw InputError(where_, what); }

    void set_file(hid_t f) { file_ = f; }

    bool exists(const std::string& path) const {
        if (replay_) return replay_->get<uint8_t>() != 0;
        const bool result = exists_live(path);
        if (record_) record_->put<uint8_t>(result);
        return result;
    }

    std::vector<double> read_floats(const std::string& path, hsize_t cols, const char* shape_text,
                                    hsize_t& rows) const {
        if (replay_) {
            rows = replay_->get<hsize_t>();
            return replay_->get_vector<double>();
        }
        auto result = read_floats_live(path, cols, shape_text, rows);
        if (record_) {
            record_->put(rows);
            record_->put(result);
        }
        return result;
    }

    std::vector<int64_t> read_ints(const std::string& path, hsize_t cols, const char* shape_text, hsize_t& rows) const {
        if (replay_) {
            rows = replay_->get<hsize_t>();
            return replay_->get_ints();
        }
        auto result = read_ints_live(path, cols, shape_text, rows);
        if (record_) {
            record_->put(rows);
            record_->put_ints(result);
        }
        return result;
    }

    std::vector<std::string> read_strings(const std::string& path, hsize_t& rows) const {
        if (replay_) {
            rows = replay_->get<hsize_t>();
            return replay_->get_strings();
        }
        auto result = read_strings_live(path, rows);
        if (record_) {
            record_->put(rows);
            record_->put(result);
        }
        return result;
    }

    // Names of the links in the group at `path`, in increasing byte order (HDF5's name
    // index), so that the result does not depend on the order they were created in.
    std::vector<std::string> list_members(const std::string& path) const {
        if (replay_) return replay_->get_strings();
        auto result = list_members_live(path);
        if (record_) record_->put(result);
        return result;
    }

    // A 2-D float64 dataset with any number of columns (at least one).
    std::vector<double> read_float_matrix(const std::string& path, const char* shape_text, hsize_t& rows,
                                          hsize_t& cols) const {
        if (replay_) {
            rows = replay_->get<hsize_t>();
            cols = replay_->get<hsize_t>();
            return replay_->get_vector<double>();
        }
        auto result = read_float_matrix_live(path, shape_text, rows, cols);
        if (record_) {
            record_->put(rows);
            record_->put(cols);
            record_->put(result);
        }
        return result;
    }

    // The row count of a dataset, with the checks of read_ints / read_floats (datatype
    // class, rank, columns, storage bounds), without reading its data: for bpm-info,
    // which reports sizes (io/bpm_outline.h).
    hsize_t read_rows(const std::string& path, hsize_t cols, const char* shape_text, bool floats) const {
        if (replay_) return replay_->get<hsize_t>();
        const hsize_t rows = read_rows_live(path, cols, shape_text, floats);
        if (record_) record_->put(rows);
        return rows;
    }

    std::string read_string_attribute(const std::string& name, bool required) const {
        if (replay_) return replay_->get_string();
        auto result = read_string_attribute_live(name, required);
        if (record_) record_->put(result);
        return result;
    }

    std::vector<int64_t> read_object_int_attribute(const std::string& path, const std::string& name) const {
        if (replay_) return replay_->get_vector<int64_t>();
        auto result = read_object_int_attribute_live(path, name);
        if (record_) record_->put(result);
        return result;
    }

    std::vector<int64_t> read_int_attribute(const std::string& name) const {
        if (replay_) return replay_->get_vector<int64_t>();
        auto result = read_int_attribute_live(name);
        if (record_) record_->put(result);
        return result;
    }

private:
    // ---- the HDF5 side: never calls the public (recording) functions above ----
    bool exists_live(const std::string& path) const {
        // Walk the path one link at a time: H5Lexists fails on a missing parent.
        size_t pos = 1;
        while (true) {
            const size_t next = path.find('/', pos);
            const std::string prefix = path.substr(0, next);
            if (H5Lexists(file_, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
            if (next == std::string::npos) break;
            pos = next + 1;
        }
        return H5Oexists_by_name(file_, path.c_str(), H5P_DEFAULT) > 0;
    }

    Handle open_dataset(const std::string& path) const {
        if (!exists_live(path)) fail(path + ": missing dataset");
        hid_t id = H5Oopen(file_, path.c_str(), H5P_DEFAULT);
        if (id < 0) fail(path + ": cannot open (" + hdf5_error_text() + ")");
        if (H5Iget_type(id) != H5I_DATASET) {
            H5Oclose(id);
            fail(path + ": is not a dataset");
        }
        return Handle(id, H5Oclose);
    }

    // Checks rank and column count and the storage bounds; returns the row count.
    // cols == 0 means a 1-D dataset.
    hsize_t shape(hid_t ds, const std::string& path, hsize_t cols, const char* shape_text) const {
        Handle space(H5Dget_space(ds), H5Sclose);
        if (!space.valid()) fail(path + ": cannot read its dataspace");
        const int rank = H5Sget_simple_extent_ndims(space);
        hsize_t dims[H5S_MAX_RANK] = {};
        if (rank < 0 || H5Sget_simple_extent_dims(space, dims, nullptr) < 0) fail(path + ": cannot read its shape");
        const int expected_rank = cols == 0 ? 1 : 2;
        std::string found = "(";
        for (int i = 0; i < rank; ++i) found += (i ? ", " : "") + num(dims[i]);
        found += rank == 1 ? ",)" : ")";
        if (rank != expected_rank || (cols != 0 && dims[1] != cols))
            fail(path + ": expected shape " + shape_text + ", found shape " + found);
        if (dims[0] > kMaxRows) fail(path + ": has an absurd number of rows (" + num(dims[0]) + ")");

        Handle type(H5Dget_type(ds), H5Tclose);
        const size_t elem = type.valid() ? H5Tget_size(type) : 0;
        if (elem == 0) fail(path + ": cannot read its datatype");
        const double logical = double(dims[0]) * double(cols == 0 ? 1 : cols) * double(elem);
        Handle dcpl(H5Dget_create_plist(ds), H5Pclose);
        const int filters = dcpl.valid() ? H5Pget_nfilters(dcpl) : 0;
        const double limit = filters > 0 ? kMaxCompressionRatio * double(file_size_) + double(1 << 20)
                                         : double(file_size_);
        if (logical > limit)
            fail(path + ": shape " + found + " needs " + num(logical) + " bytes, more than a " + num(file_size_) +
                 "-byte file can hold");
        return dims[0];
    }

    void require_class(hid_t ds, const std::string& path, H5T_class_t cls, const char* what) const {
        Handle type(H5Dget_type(ds), H5Tclose);
        if (!type.valid() || H5Tget_class(type) != cls) fail(path + ": wrong datatype, expected " + what);
    }

    std::vector<double> read_floats_live(const std::string& path, hsize_t cols, const char* shape_text,
                                         hsize_t& rows) const {
        Handle ds = open_dataset(path);
        require_class(ds, path, H5T_FLOAT, "a floating-point type (float64)");
        rows = shape(ds, path, cols, shape_text);
        std::vector<double> out(static_cast<size_t>(rows * (cols == 0 ? 1 : cols)));
        if (!out.empty() && H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
            fail(path + ": cannot read data (" + hdf5_error_text() + ")");
        return out;
    }

    // Integers are read as int64 whatever their stored width, so that out-of-range
    // values are seen (and reported) instead of being clipped by a conversion.
    std::vector<int64_t> read_ints_live(const std::string& path, hsize_t cols, const char* shape_text,
                                        hsize_t& rows) const {
        Handle ds = open_dataset(path);
        require_class(ds, path, H5T_INTEGER, "an integer type");
        rows = shape(ds, path, cols, shape_text);
        std::vector<int64_t> out(static_cast<size_t>(rows * (cols == 0 ? 1 : cols)));
        if (!out.empty() && H5Dread(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
            fail(path + ": cannot read data (" + hdf5_error_text() + ")");
        return out;
    }

    hsize_t read_rows_live(const std::string& path, hsize_t cols, const char* shape_text, bool floats) const {
        Handle ds = open_dataset(path);
        if (floats) require_class(ds, path, H5T_FLOAT, "a floating-point type (float64)");
        else require_class(ds, path, H5T_INTEGER, "an integer type");
        return shape(ds, path, cols, shape_text);
    }

    std::vector<std::string> list_members_live(const std::string& path) const {
        if (!exists_live(path)) fail(path + ": missing group");
        Handle group(H5Oopen(file_, path.c_str(), H5P_DEFAULT), H5Oclose);
        if (!group.valid()) fail(path + ": cannot open (" + hdf5_error_text() + ")");
        if (H5Iget_type(group) != H5I_GROUP) fail(path + ": is not a group");
        struct Names {
            std::vector<std::string> names;
            size_t bytes = 0, limit = 0;
        } names;
        names.limit = file_size_;  // every name is stored in the file: more is corruption
        auto collect = [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
            auto& n = *static_cast<Names*>(data);
            n.bytes += std::strlen(name) + 1;
            if (n.bytes > n.limit) return -1;
            n.names.emplace_back(name);
            return 0;
        };
        hsize_t index = 0;
        if (H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, &index, collect, &names) < 0)
            fail(path + ": cannot list its members (" + hdf5_error_text() + ")");
        return names.names;
    }

    std::vector<double> read_float_matrix_live(const std::string& path, const char* shape_text, hsize_t& rows,
                                               hsize_t& cols) const {
        Handle ds = open_dataset(path);
        require_class(ds, path, H5T_FLOAT, "a floating-point type (float64)");
        {
            Handle space(H5Dget_space(ds), H5Sclose);
            hsize_t dims[H5S_MAX_RANK] = {};
            const int rank = space.valid() ? H5Sget_simple_extent_ndims(space) : -1;
            if (rank != 2 || H5Sget_simple_extent_dims(space, dims, nullptr) < 0 || dims[1] < 1)
                fail(path + ": expected shape " + shape_text + " with at least one column");
            cols = dims[1];
        }
        if (cols > kMaxRows) fail(path + ": has an absurd number of columns (" + num(cols) + ")");
        rows = shape(ds, path, cols, shape_text);
        std::vector<double> out(static_cast<size_t>(rows * cols));
        if (!out.empty() && H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
            fail(path + ": cannot read data (" + hdf5_error_text() + ")");
        return out;
    }

    std::vector<std::string> read_strings_live(const std::string& path, hsize_t& rows) const {
        Handle ds = open_dataset(path);
        require_class(ds, path, H5T_STRING, "a string type");
        rows = shape(ds, path, 0, "(#steps,)");
        Handle ftype(H5Dget_type(ds), H5Tclose);
        std::vector<std::string> out(static_cast<size_t>(rows));
        if (rows == 0) return out;
        if (H5Tis_variable_str(ftype) > 0) {
            Handle mtype(H5Tcopy(H5T_C_S1), H5Tclose);
            H5Tset_size(mtype, H5T_VARIABLE);
            H5Tset_cset(mtype, H5Tget_cset(ftype));
            std::vector<char*> ptrs(static_cast<size_t>(rows), nullptr);
            if (H5Dread(ds, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()) < 0)
                fail(path + ": cannot read strings (" + hdf5_error_text() + ")");
            for (size_t i = 0; i < ptrs.size(); ++i)
                if (ptrs[i]) out[i] = ptrs[i];
            Handle space(H5Dget_space(ds), H5Sclose);
            H5Dvlen_reclaim(mtype, space, H5P_DEFAULT, ptrs.data());
        } else {
            const size_t width = H5Tget_size(ftype);
            Handle mtype(H5Tcopy(ftype), H5Tclose);
            std::vector<char> buffer(static_cast<size_t>(rows) * width);
            if (H5Dread(ds, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()) < 0)
                fail(path + ": cannot read strings (" + hdf5_error_text() + ")");
            for (size_t i = 0; i < out.size(); ++i) {
                const char* s = &buffer[i * width];
                out[i].assign(s, strnlen(s, width));
            }
        }
        return out;
    }

    Handle open_attribute(const std::string& name, bool required) const {
        const htri_t e = H5Aexists(file_, name.c_str());
        if (e <= 0) {
            if (required) fail("root attribute '" + name + "': missing (is this a bpm file?)");
            return {};
        }
        hid_t id = H5Aopen(file_, name.c_str(), H5P_DEFAULT);
        if (id < 0) fail("root attribute '" + name + "': cannot open");
        return Handle(id, H5Aclose);
    }

    // A scalar (or one-element) string attribute, fixed or variable length.
    std::string read_string_attribute_live(const std::string& name, bool required) const {
        Handle attr = open_attribute(name, required);
        if (!attr.valid()) return {};
        Handle ftype(H5Aget_type(attr), H5Tclose);
        if (!ftype.valid() || H5Tget_class(ftype) != H5T_STRING)
            fail("root attribute '" + name + "': wrong datatype, expected a string");
        Handle space(H5Aget_space(attr), H5Sclose);
        if (H5Sget_simple_extent_npoints(space) != 1)
            fail("root attribute '" + name + "': expected a single string");
        if (H5Tis_variable_str(ftype) > 0) {
            Handle mtype(H5Tcopy(H5T_C_S1), H5Tclose);
            H5Tset_size(mtype, H5T_VARIABLE);
            H5Tset_cset(mtype, H5Tget_cset(ftype));
            char* value = nullptr;
            if (H5Aread(attr, mtype, &value) < 0) fail("root attribute '" + name + "': cannot read");
            std::string out = value ? value : "";
            H5Dvlen_reclaim(mtype, space, H5P_DEFAULT, &value);
            return out;
        }
        const size_t width = H5Tget_size(ftype);
        if (width > file_size_) fail("root attribute '" + name + "': absurd string length");
        std::vector<char> buffer(width + 1, '\0');
        if (H5Aread(attr, ftype, buffer.data()) < 0) fail("root attribute '" + name + "': cannot read");
        return std::string(buffer.data(), strnlen(buffer.data(), width));
    }

    // An integer attribute of the object at `path` (a group or dataset).
    std::vector<int64_t> read_object_int_attribute_live(const std::string& path, const std::string& name) const {
        const std::string what = path + ": attribute '" + name + "'";
        if (H5Aexists_by_name(file_, path.c_str(), name.c_str(), H5P_DEFAULT) <= 0) fail(what + ": missing");
        Handle attr(H5Aopen_by_name(file_, path.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
        if (!attr.valid()) fail(what + ": cannot open");
        Handle ftype(H5Aget_type(attr), H5Tclose);
        if (!ftype.valid() || H5Tget_class(ftype) != H5T_INTEGER) fail(what + ": wrong datatype, expected integers");
        Handle space(H5Aget_space(attr), H5Sclose);
        const hssize_t n = H5Sget_simple_extent_npoints(space);
        if (n < 0 || n > 16) fail(what + ": unexpected number of entries");
        std::vector<int64_t> out(static_cast<size_t>(n));
        if (n > 0 && H5Aread(attr, H5T_NATIVE_INT64, out.data()) < 0) fail(what + ": cannot read");
        return out;
    }

    std::vector<int64_t> read_int_attribute_live(const std::string& name) const {
        Handle attr = open_attribute(name, true);
        Handle ftype(H5Aget_type(attr), H5Tclose);
        if (!ftype.valid() || H5Tget_class(ftype) != H5T_INTEGER)
            fail("root attribute '" + name + "': wrong datatype, expected integers");
        Handle space(H5Aget_space(attr), H5Sclose);
        const hssize_t n = H5Sget_simple_extent_npoints(space);
        if (n < 0 || n > 16) fail("root attribute '" + name + "': unexpected number of entries");
        std::vector<int64_t> out(static_cast<size_t>(n));
        if (n > 0 && H5Aread(attr, H5T_NATIVE_INT64, out.data()) < 0)
            fail("root attribute '" + name + "': cannot read");
        return out;
    }

    std::string where_;
    size_t file_size_;
    hid_t file_ = -1;
    Tape* record_ = nullptr;
    Tape* replay_ = nullptr;
};

// Narrows checked int64 values to int32; values outside int32 are reported here (the
// semantic checks report indices that fit int32 but are out of range).
std::vector<int32_t> narrow(const Reader& r, const std::vector<int64_t>& v, const std::string& path) {
    std::vector<int32_t> out(v.size());
    for (size_t i = 0; i < v.size(); ++i) {
        if (v[i] < std::numeric_limits<int32_t>::min() || v[i] > std::numeric_limits<int32_t>::max())
            r.fail(path + ": element " + num(i) + " = " + num(v[i]) + " does not fit in int32");
        out[i] = static_cast<int32_t>(v[i]);
    }
    return out;
}

void check_finite(const Reader& r, const std::vector<double>& v, const std::string& path, size_t cols) {
    for (size_t i = 0; i < v.size(); ++i)
        if (!std::isfinite(v[i]))
            r.fail(path + ": entry [" + num(i / cols) + ", " + num(i % cols) + "] is not finite (" + num(v[i]) + ")");
}

std::vector<Vec3> to_vec3(const std::vector<double>& v) {
    std::vector<Vec3> out(v.size() / 3);
    for (size_t i = 0; i < out.size(); ++i) out[i] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    return out;
}
std::vector<Tri> to_tri(const std::vector<int32_t>& v) {
    std::vector<Tri> out(v.size() / 3);
    for (size_t i = 0; i < out.size(); ++i) out[i] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    return out;
}

void expect_rows(const Reader& r, hsize_t rows, hsize_t expected, const std::string& path, const std::string& why) {
    if (rows != expected)
        r.fail(path + ": has " + num(rows) + " rows, expected " + num(expected) + " (" + why + ")");
}

Surface read_surface(const Reader& r, const std::string& group) {
    Surface s;
    hsize_t nv = 0, nt = 0, np = 0;
    const auto xyz = r.read_floats(group + "/vertices", 3, "(#V, 3)", nv);
    check_finite(r, xyz, group + "/vertices", 3);
    if (nv > hsize_t(std::numeric_limits<int32_t>::max())) r.fail(group + "/vertices: more than 2^31-1 vertices");
    const auto tri = narrow(r, r.read_ints(group + "/triangles", 3, "(#T, 3)", nt), group + "/triangles");
    const auto patches = narrow(r, r.read_ints(group + "/patches", 0, "(#T,)", np), group + "/patches");
    expect_rows(r, np, nt, group + "/patches", "one per row of " + group + "/triangles");
    s.vertices = to_vec3(xyz);
    s.triangles = to_tri(tri);
    s.patches = patches;
    return s;
}

TetMesh read_tetmesh_group(const Reader& r, const Surface& coarse) {
    TetMesh m;
    const auto level = r.read_object_int_attribute("/tetmesh", "level");
    if (level.size() != 1) r.fail("/tetmesh: attribute 'level' must hold one integer");
    if (level[0] < 0 || level[0] > 64) r.fail("/tetmesh: attribute 'level' = " + num(level[0]) + " is out of range");
    m.level = static_cast<int32_t>(level[0]);
    hsize_t nv = 0, nt = 0, nf = 0, rows = 0;
    const auto xyz = r.read_floats("/tetmesh/vertices", 3, "(#V, 3)", nv);
    check_finite(r, xyz, "/tetmesh/vertices", 3);
    if (nv > hsize_t(std::numeric_limits<int32_t>::max())) r.fail("/tetmesh/vertices: more than 2^31-1 vertices");
    m.vertices = to_vec3(xyz);
    const auto tets = narrow(r, r.read_ints("/tetmesh/tetrahedra", 4, "(#Tet, 4)", nt), "/tetmesh/tetrahedra");
    m.tetrahedra.resize(static_cast<size_t>(nt));
    for (size_t i = 0; i < m.tetrahedra.size(); ++i)
        m.tetrahedra[i] = {tets[4 * i], tets[4 * i + 1], tets[4 * i + 2], tets[4 * i + 3]};
    m.regions = narrow(r, r.read_ints("/tetmesh/regions", 0, "(#Tet,)", rows), "/tetmesh/regions");
    expect_rows(r, rows, nt, "/tetmesh/regions", "one per row of /tetmesh/tetrahedra");
    m.faces = to_tri(narrow(r, r.read_ints("/tetmesh/faces", 3, "(#F, 3)", nf), "/tetmesh/faces"));
    m.face_coarse_triangle =
        narrow(r, r.read_ints("/tetmesh/face_coarse_triangle", 0, "(#F,)", rows), "/tetmesh/face_coarse_triangle");
    expect_rows(r, rows, nf, "/tetmesh/face_coarse_triangle", "one per row of /tetmesh/faces");
    m.face_patches = narrow(r, r.read_ints("/tetmesh/face_patches", 0, "(#F,)", rows), "/tetmesh/face_patches");
    expect_rows(r, rows, nf, "/tetmesh/face_patches", "one per row of /tetmesh/faces");
    m.vertex_coarse_vertex =
        narrow(r, r.read_ints("/tetmesh/vertex_coarse_vertex", 0, "(#V,)", rows), "/tetmesh/vertex_coarse_vertex");
    expect_rows(r, rows, nv, "/tetmesh/vertex_coarse_vertex", "one per row of /tetmesh/vertices");
    const std::vector<int32_t> parameter_triangles = narrow(
        r, r.read_ints("/tetmesh/vertex_parameter_triangle", 0, "(#V,)", rows), "/tetmesh/vertex_parameter_triangle");
    expect_rows(r, rows, nv, "/tetmesh/vertex_parameter_triangle", "one per row of /tetmesh/vertices");
    const auto bary = r.read_floats("/tetmesh/vertex_parameter_barycentric", 3, "(#V, 3)", rows);
    expect_rows(r, rows, nv, "/tetmesh/vertex_parameter_barycentric", "one per row of /tetmesh/vertices");
    check_finite(r, bary, "/tetmesh/vertex_parameter_barycentric", 3);
    const std::vector<Vec3> barycentrics = to_vec3(bary);
    m.vertex_parameter_points.resize(parameter_triangles.size());
    for (size_t v = 0; v < parameter_triangles.size(); ++v)
        m.vertex_parameter_points[v] = {parameter_triangles[v], barycentrics[v]};
    if (r.exists("/tetmesh/tet_ancestor")) {
        m.tet_ancestor = narrow(r, r.read_ints("/tetmesh/tet_ancestor", 0, "(#Tet,)", rows), "/tetmesh/tet_ancestor");
        expect_rows(r, rows, nt, "/tetmesh/tet_ancestor", "one per row of /tetmesh/tetrahedra");
    }
    if (r.exists("/tetmesh/region_material") || r.exists("/tetmesh/material_names")) {
        m.region_material =
            narrow(r, r.read_ints("/tetmesh/region_material", 0, "(#R,)", rows), "/tetmesh/region_material");
        m.material_names = r.read_strings("/tetmesh/material_names", rows);
    }
    if (auto problem = find_tetmesh_inconsistency(m, coarse); !problem.empty()) r.fail(problem);
    if (auto problem = find_material_inconsistency(m); !problem.empty()) r.fail(problem);
    return m;
}

// The optional /simplification_steps group (§10.1). Every extent is checked against
// the file size by Reader::read_ints before anything is allocated; values are checked
// by find_steps_inconsistency, the same rules the writer enforces.
SimplificationSteps read_simplification_steps_group(const Reader& r, int64_t nv0) {
    const std::string g = "/simplification_steps";
    SimplificationSteps s;
    hsize_t ns = 0, rows = 0, nr = 0;
    s.vertex = narrow(r, r.read_ints(g + "/vertex", 0, "(#S,)", ns), g + "/vertex");
    s.triangle_offsets = r.read_ints(g + "/triangle_offsets", 0, "(#S+1,)", rows);
    expect_rows(r, rows, ns + 1, g + "/triangle_offsets", "entries of " + g + "/vertex + 1");
    s.triangles = to_tri(narrow(r, r.read_ints(g + "/triangles", 3, "(#R, 3)", nr), g + "/triangles"));
    s.triangle_patches = narrow(r, r.read_ints(g + "/triangle_patches", 0, "(#R,)", rows), g + "/triangle_patches");
    expect_rows(r, rows, nr, g + "/triangle_patches", "one per row of " + g + "/triangles");
    if (auto problem = find_steps_inconsistency(s, nv0); !problem.empty()) r.fail(problem);
    return s;
}

// The optional /patch_info group (format 1.3, spec/bpm-format.md §5.2).
std::vector<PatchInfo> read_patch_info_group(const Reader& r) {
    const std::string g = "/patch_info";
    hsize_t n = 0, rows = 0;
    const auto patch = narrow(r, r.read_ints(g + "/patch", 0, "(#PI,)", n), g + "/patch");
    auto name = r.read_strings(g + "/name", rows);
    expect_rows(r, rows, n, g + "/name", "one per entry of " + g + "/patch");
    auto front = r.read_strings(g + "/front_material", rows);
    expect_rows(r, rows, n, g + "/front_material", "one per entry of " + g + "/patch");
    auto back = r.read_strings(g + "/back_material", rows);
    expect_rows(r, rows, n, g + "/back_material", "one per entry of " + g + "/patch");
    const auto oriented = r.read_ints(g + "/oriented", 0, "(#PI,)", rows);
    expect_rows(r, rows, n, g + "/oriented", "one per entry of " + g + "/patch");
    std::vector<PatchInfo> out(static_cast<size_t>(n));
    for (size_t i = 0; i < out.size(); ++i) {
        if (oriented[i] != 0 && oriented[i] != 1)
            r.fail(g + "/oriented: entry " + num(i) + " = " + num(oriented[i]) + " is not 0 or 1");
        out[i] = {patch[i], std::move(name[i]), std::move(front[i]), std::move(back[i]), oriented[i] == 1};
    }
    if (auto problem = patch_info_problem(out); !problem.empty()) r.fail(g + ": " + problem);
    return out;
}

// Opens `bytes` as an HDF5 file for `r` (unless it replays a tape): the HDF5 signature
// first, so that a file of some other kind is told as such.
Handle open_image(const std::string& bytes, const std::string& where, Reader& r) {
    silence_hdf5();
    if (bytes.empty()) throw InputError(where, "empty input, not a bpm file");
    static const char kSignature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
    // bpm writers put the HDF5 superblock at offset 0; HDF5 also allows a user block of
    // 512 * 2^k bytes in front of it.
    bool signature = false;
    for (size_t off = 0; off + 8 <= bytes.size() && !signature; off = off == 0 ? 512 : 2 * off)
        signature = std::memcmp(bytes.data() + off, kSignature, 8) == 0;
    if (!signature) throw InputError(where, "not an HDF5 file (no HDF5 signature), so not a bpm file");
    if (r.replaying()) return {};
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    if (!fapl.valid() || H5Pset_fapl_core(fapl, size_t(1) << 20, false) < 0 ||
        H5Pset_file_image(fapl, const_cast<char*>(bytes.data()), bytes.size()) < 0)
        r.fail("cannot prepare the HDF5 file image (" + hdf5_error_text() + ")");
    const std::string name = "bpm-read-" + std::to_string(g_image_counter++) + ".h5";
    hid_t fid = H5Fopen(name.c_str(), H5F_ACC_RDONLY, fapl);
    if (fid < 0) r.fail("cannot open as HDF5, file truncated or damaged (" + hdf5_error_text() + ")");
    Handle f(fid, H5Fclose);
    r.set_file(f);
    return f;
}

// Identification first, so that a file of some other kind, or from a future
// incompatible version, is reported as such rather than as a missing dataset.
BpmFormatVersion read_identification(const Reader& r) {
    const std::string format = r.read_string_attribute("format", true);
    if (format != "bpm") r.fail("root attribute 'format' is '" + format + "', expected 'bpm'");
    const auto version = r.read_int_attribute("format_version");
    if (version.size() != 2) r.fail("root attribute 'format_version': expected 2 integers [major, minor]");
    // Major 1 differs from 2 only in storing /phi/node_image (read_image).
    if (version[0] < 1 || version[0] > BPM_FORMAT_VERSION_MAJOR)
        r.fail("root attribute 'format_version': file has format version " + num(version[0]) + "." + num(version[1]) +
               ", this reader supports major versions 1 to " + num(BPM_FORMAT_VERSION_MAJOR) +
               (version[0] > BPM_FORMAT_VERSION_MAJOR ? " only; a newer bpm is needed to read it" : " only"));
    if (version[1] < 0) r.fail("root attribute 'format_version': negative minor version");
    return {static_cast<int>(version[0]), static_cast<int>(version[1])};
}

// The names of the /original/point_data arrays (§5.1), if any.
std::vector<std::string> point_data_names(const Reader& r) {
    if (!r.exists("/original/point_data")) return {};
    return r.list_members("/original/point_data");
}

std::vector<ProvenanceStep> read_provenance(const Reader& r) {
    hsize_t steps = 0, rows = 0;
    auto tool = r.read_strings("/provenance/tool", steps);
    auto ver = r.read_strings("/provenance/version", rows);
    expect_rows(r, rows, steps, "/provenance/version", "one per entry of /provenance/tool");
    auto args = r.read_strings("/provenance/arguments", rows);
    expect_rows(r, rows, steps, "/provenance/arguments", "one per entry of /provenance/tool");
    auto stamp = r.read_strings("/provenance/timestamp", rows);
    expect_rows(r, rows, steps, "/provenance/timestamp", "one per entry of /provenance/tool");
    std::vector<ProvenanceStep> out;
    for (size_t i = 0; i < tool.size(); ++i)
        out.push_back({std::move(tool[i]), std::move(ver[i]), std::move(args[i]), std::move(stamp[i])});
    return out;
}

// `record`: also record every HDF5 result there; `replay`: take them from there and
// do not call HDF5 at all (see Tape).
BpmFile read_image(const std::string& bytes, const std::string& where, Tape* record = nullptr,
                   Tape* replay = nullptr) {
    Reader r(where, bytes.size());
    r.set_tape(record, replay);
    const Handle f = open_image(bytes, where, r);

    BpmFile out;
    out.format_version = read_identification(r);
    out.units = r.read_string_attribute("units", false);

    Parametrization& p = out.param;
    p.original = read_surface(r, "/original");
    {
        for (const std::string& name : point_data_names(r)) {
            const std::string path = "/original/point_data/" + name;
            hsize_t rows = 0, cols = 0;
            VertexArray a;
            a.name = name;
            a.values = r.read_float_matrix(path, "(#V0, k)", rows, cols);
            check_finite(r, a.values, path, cols);
            expect_rows(r, rows, p.original.vertices.size(), path, "one per row of /original/vertices");
            a.components = static_cast<int>(cols);
            p.original.vertex_data.push_back(std::move(a));
        }
    }
    p.coarse = read_surface(r, "/coarse");
    const hsize_t nt0 = p.original.triangles.size();
    const hsize_t nvc = p.coarse.vertices.size(), ntc = p.coarse.triangles.size();
    hsize_t rows = 0;
    p.coarse_vertex_origin = narrow(r, r.read_ints("/coarse/vertex_origin", 0, "(#V,)", rows), "/coarse/vertex_origin");
    expect_rows(r, rows, nvc, "/coarse/vertex_origin", "one per row of /coarse/vertices");
    (void)nt0;

    p.node_offsets = r.read_ints("/phi/node_offsets", 0, "(#T+1,)", rows);
    expect_rows(r, rows, ntc + 1, "/phi/node_offsets", "rows of /coarse/triangles + 1");
    hsize_t nn = 0;
    const auto kinds = r.read_ints("/phi/node_kind", 0, "(#N,)", nn);
    const auto bary = r.read_floats("/phi/node_barycentric", 3, "(#N, 3)", rows);
    expect_rows(r, rows, nn, "/phi/node_barycentric", "one per entry of /phi/node_kind");
    // Format 1.x stored the images (required there); 2.0 does not, they are recomputed below.
    std::vector<double> image;
    if (out.format_version.major == 1) {
        image = r.read_floats("/phi/node_image", 3, "(#N, 3)", rows);
        expect_rows(r, rows, nn, "/phi/node_image", "one per entry of /phi/node_kind");
        check_finite(r, image, "/phi/node_image", 3);
    }
    const auto ov = narrow(r, r.read_ints("/phi/node_original_vertex", 0, "(#N,)", rows), "/phi/node_original_vertex");
    expect_rows(r, rows, nn, "/phi/node_original_vertex", "one per entry of /phi/node_kind");
    const auto oe = narrow(r, r.read_ints("/phi/node_original_edge", 2, "(#N, 2)", rows), "/phi/node_original_edge");
    expect_rows(r, rows, nn, "/phi/node_original_edge", "one per entry of /phi/node_kind");
    const auto params = r.read_floats("/phi/node_edge_parameter", 0, "(#N,)", rows);
    expect_rows(r, rows, nn, "/phi/node_edge_parameter", "one per entry of /phi/node_kind");
    p.piece_offsets = r.read_ints("/phi/piece_offsets", 0, "(#T+1,)", rows);
    expect_rows(r, rows, ntc + 1, "/phi/piece_offsets", "rows of /coarse/triangles + 1");
    hsize_t np = 0;
    const auto pieces = narrow(r, r.read_ints("/phi/pieces", 3, "(#P, 3)", np), "/phi/pieces");
    const auto pot = narrow(r, r.read_ints("/phi/piece_original_triangle", 0, "(#P,)", rows),
                            "/phi/piece_original_triangle");
    expect_rows(r, rows, np, "/phi/piece_original_triangle", "one per row of /phi/pieces");

    p.node_kind.resize(kinds.size());
    for (size_t i = 0; i < kinds.size(); ++i) {
        if (kinds[i] < 0 || kinds[i] > 2)
            r.fail("/phi/node_kind: entry " + num(i) + " = " + num(kinds[i]) + " is not a valid node kind (0, 1 or 2)");
        p.node_kind[i] = static_cast<NodeKind>(kinds[i]);
    }
    p.node_barycentric = to_vec3(bary);
    // The stored images of a 1.x file, or a placeholder of the right length until the
    // indices the recomputation follows are checked (find_inconsistency).
    p.node_image = image.empty() ? std::vector<Vec3>(static_cast<size_t>(nn)) : to_vec3(image);
    p.node_original_vertex = ov;
    p.node_original_edge.resize(static_cast<size_t>(nn));
    for (size_t i = 0; i < p.node_original_edge.size(); ++i) p.node_original_edge[i] = {oe[2 * i], oe[2 * i + 1]};
    p.node_edge_parameter = params;
    p.pieces = to_tri(pieces);
    p.piece_original_triangle = pot;

    out.provenance = read_provenance(r);

    if (auto problem = find_inconsistency(out); !problem.empty()) r.fail(problem);
    if (out.format_version.major == 1) out.stored_node_image = std::move(p.node_image);
    p.node_image = node_images_from_kinds(p);
    if (r.exists("/tetmesh")) out.tetmesh = read_tetmesh_group(r, p.coarse);
    if (r.exists("/simplification_steps"))
        out.simplification_steps = read_simplification_steps_group(r, p.original.num_vertices());
    if (r.exists("/patch_info")) out.patch_info = read_patch_info_group(r);
    if (replay && !replay->finished())
        throw AlgorithmError("internal error: the replayed HDF5 reads did not match the recorded ones");
    // Non-crossing nodes carry NaN as their edge parameter; normalise whatever the file
    // had so that a read file compares equal to what was written.
    for (size_t i = 0; i < p.node_edge_parameter.size(); ++i)
        if (p.node_kind[i] != NodeKind::EdgeCrossing)
            p.node_edge_parameter[i] = std::numeric_limits<double>::quiet_NaN();
    return out;
}

// Opens the HDF5 file at `path` where it is (the sec2 driver reads only the parts asked
// for, not the whole file as a file image does), without file locking (read only; locks
// fail on some network file systems).
Handle open_in_place(const std::string& path, Reader& r) {
    silence_hdf5();
    if (r.replaying()) return {};
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    if (!fapl.valid() || H5Pset_file_locking(fapl, false, true) < 0)
        r.fail("cannot prepare to open the file (" + hdf5_error_text() + ")");
    hid_t fid = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl);
    if (fid < 0) r.fail("cannot open as HDF5, file truncated or damaged (" + hdf5_error_text() + ")");
    Handle f(fid, H5Fclose);
    r.set_file(f);
    return f;
}

// What bpm-info reports (io/bpm_outline.h) from an open file: the datasets it only counts
// are not read, their row counts come from their dataspaces (Reader::read_rows, with
// read_ints' and read_floats' checks of datatype, shape and storage bounds).
detail::BpmOutline read_outline(const Reader& r, Tape* replay) {
    detail::BpmOutline out;
    out.format_version = read_identification(r);
    out.units = r.read_string_attribute("units", false);

    out.original_vertices = int64_t(r.read_rows("/original/vertices", 3, "(#V, 3)", true));
    const hsize_t nt0 = r.read_rows("/original/triangles", 3, "(#T, 3)", false);
    hsize_t rows = 0;
    out.original_patches = narrow(r, r.read_ints("/original/patches", 0, "(#T,)", rows), "/original/patches");
    expect_rows(r, rows, nt0, "/original/patches", "one per row of /original/triangles");
    out.original_point_data = point_data_names(r);

    out.coarse = read_surface(r, "/coarse");
    const int64_t nvc = out.coarse.num_vertices();
    for (size_t t = 0; t < out.coarse.triangles.size(); ++t)
        for (const int32_t v : out.coarse.triangles[t])
            if (v < 0 || v >= nvc)
                r.fail("/coarse/triangles: row " + num(t) + " has vertex " + num(v) + ", outside [0, " + num(nvc) + ")");
    out.phi_nodes = int64_t(r.read_rows("/phi/node_kind", 0, "(#N,)", false));
    out.phi_pieces = int64_t(r.read_rows("/phi/pieces", 3, "(#P, 3)", false));
    out.provenance = read_provenance(r);

    if (r.exists("/tetmesh")) {
        detail::BpmTetMeshOutline t;
        const auto level = r.read_object_int_attribute("/tetmesh", "level");
        if (level.size() != 1) r.fail("/tetmesh: attribute 'level' must hold one integer");
        if (level[0] < 0 || level[0] > 64) r.fail("/tetmesh: attribute 'level' = " + num(level[0]) + " is out of range");
        t.level = static_cast<int32_t>(level[0]);
        t.vertices = int64_t(r.read_rows("/tetmesh/vertices", 3, "(#V, 3)", true));
        t.tetrahedra = int64_t(r.read_rows("/tetmesh/tetrahedra", 4, "(#Tet, 4)", false));
        t.regions = narrow(r, r.read_ints("/tetmesh/regions", 0, "(#Tet,)", rows), "/tetmesh/regions");
        expect_rows(r, rows, hsize_t(t.tetrahedra), "/tetmesh/regions", "one per row of /tetmesh/tetrahedra");
        t.faces = int64_t(r.read_rows("/tetmesh/faces", 3, "(#F, 3)", false));
        if (r.exists("/tetmesh/region_material") || r.exists("/tetmesh/material_names")) {
            t.region_material =
                narrow(r, r.read_ints("/tetmesh/region_material", 0, "(#R,)", rows), "/tetmesh/region_material");
            t.material_names = r.read_strings("/tetmesh/material_names", rows);
        }
        out.tetmesh = std::move(t);
    }
    if (r.exists("/simplification_steps"))
        out.simplification_steps = int64_t(r.read_rows("/simplification_steps/vertex", 0, "(#S,)", false));
    if (r.exists("/patch_info")) out.patch_info = read_patch_info_group(r);
    if (replay && !replay->finished())
        throw AlgorithmError("internal error: the replayed HDF5 reads did not match the recorded ones");
    return out;
}

detail::BpmOutline read_outline_image(const std::string& bytes, const std::string& where, Tape* record,
                                      Tape* replay) {
    Reader r(where, bytes.size());
    r.set_tape(record, replay);
    const Handle f = open_image(bytes, where, r);
    return read_outline(r, replay);
}

}  // namespace

std::string write_bpm_to_memory(const BpmFile& file) { return build_image(file, "<memory>"); }

void write_bpm(const std::string& path, const BpmFile& file) {
    if (path == "-")
        detail::write_file_atomically(path, build_image(file, "<stdout>"));
    else if (!detail::fd_driver_available())  // another HDF5 driver interface (see hdf5_fd_driver.h)
        detail::write_file_atomically(path, build_image(file, path));
    else
        write_file(file, path);
}

namespace {

// HDF5 crashes. HDF5 1.10.8 (Debian) has memory-safety bugs on corrupt files that no
// check of ours before calling it can rule out: e.g. H5Aexists decodes an attribute
// message whose name is not NUL-terminated with strdup() and reads past the object-header
// buffer (heap over-read, occasionally a SIGSEGV; found by tests/fuzz/fuzz_read_bpm).
// Validating the HDF5 structures ourselves would mean re-implementing much of HDF5 and
// would still miss bugs in the parts we did not re-implement, and catching SIGSEGV
// in-process cannot undo a corrupted heap. So, when isolation is on (the tools turn it
// on), the bytes are parsed in a forked child process: a crash there becomes an
// InputError. The child records the result of every HDF5 read on a Tape and sends it
// back; the parent then runs the same parsing and validation on the replayed results,
// without calling HDF5 on the bytes (the child was an exact copy of this process, so
// the parent asks for the same reads in the same order).
std::atomic<bool> g_hdf5_isolation{false};

// `parse(bytes, where, record, replay)` is read_image or read_outline_image.
template <class Parse>
auto read_checked(const std::string& bytes, const std::string& where, Parse parse) {
    if (g_hdf5_isolation) {
        std::optional<std::string> recorded = detail::run_isolated(where, "HDF5", [&] {
            Tape tape;
            (void)parse(bytes, where, &tape, nullptr);
            return std::move(tape.bytes());
        });
        if (recorded) {
            Tape tape(std::move(*recorded));
            return parse(bytes, where, nullptr, &tape);
        }
    }
    return parse(bytes, where, nullptr, nullptr);
}

BpmFile read_checked(const std::string& bytes, const std::string& where) {
    return read_checked(bytes, where, read_image);
}

}  // namespace

void set_hdf5_isolation(bool enabled) { g_hdf5_isolation = enabled; }

BpmFile read_bpm(const std::string& path) {
    const std::string bytes = detail::read_whole_input(path);
    return read_checked(bytes, detail::display_name(path));
}

BpmFile read_bpm_from_memory(const std::string& bytes, const std::string& name) {
    if (detail::looks_like_gzip(bytes)) return read_checked(detail::decompress_if_gzip(bytes, name, false), name);
    return read_checked(bytes, name);
}

namespace detail {

namespace {

// The size of `path` if it is a regular file that starts with the HDF5 signature (as bpm
// writes them: no user block, not gzip-compressed), which can be opened in place.
std::optional<size_t> plain_hdf5_file(const std::string& path) {
    // A .gz name must hold gzip data (read_whole_input says so when it does not).
    if (path == "-" || without_gz_suffix(path) != path) return std::nullopt;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) return std::nullopt;
    char head[8] = {};
    std::ifstream in(path, std::ios::binary);
    if (!in.read(head, sizeof head)) return std::nullopt;
    static const char kSignature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
    if (std::memcmp(head, kSignature, sizeof head) != 0) return std::nullopt;
    return static_cast<size_t>(size);
}

}  // namespace

BpmOutline read_bpm_outline(const std::string& path) {
    // A plain .bpm is read in place: only the datasets bpm-info reports are read from
    // disk (armadillo subdivided twice, 93.5 MB at 10 %: peak RSS 23 MB in place, 279 MB
    // through memory, spec/info-report.md "Cost"). Standard input, .gz and anything else go
    // through memory as in read_bpm, which also says what is wrong with a non-HDF5 file.
    if (const std::optional<size_t> size = plain_hdf5_file(path)) {
        auto parse = [&](const std::string&, const std::string& where, Tape* record, Tape* replay) {
            Reader r(where, *size);
            r.set_tape(record, replay);
            const Handle f = open_in_place(path, r);
            return read_outline(r, replay);
        };
        return read_checked(std::string(), display_name(path), parse);
    }
    const std::string bytes = read_whole_input(path);
    return read_checked(bytes, display_name(path), read_outline_image);
}

BpmOutline outline_of(const BpmFile& file) {
    BpmOutline out;
    const Parametrization& p = file.param;
    out.format_version = file.format_version;
    out.units = file.units;
    out.original_vertices = p.original.num_vertices();
    out.original_patches = p.original.patches;
    for (const VertexArray& a : p.original.vertex_data) out.original_point_data.push_back(a.name);
    out.coarse = p.coarse;
    out.coarse.vertex_data.clear();
    out.phi_nodes = p.num_nodes();
    out.phi_pieces = p.num_pieces();
    if (file.tetmesh) {
        const TetMesh& m = *file.tetmesh;
        out.tetmesh = BpmTetMeshOutline{m.num_vertices(), m.num_tetrahedra(), int64_t(m.faces.size()), m.level,
                                        m.regions, m.region_material, m.material_names};
    }
    if (file.simplification_steps) out.simplification_steps = int64_t(file.simplification_steps->vertex.size());
    out.patch_info = file.patch_info;
    out.provenance = file.provenance;
    return out;
}

}  // namespace detail

}  // namespace bpm
