// Writing the bpm file format on top of the HDF5 C API. spec/bpm-format.md is normative;
// this file is one implementation of it (the reader is io/bpm_read.cpp, the rules both
// check io/bpm_file_rules.cpp).
//
// Files are written by HDF5 straight into an unnamed temporary file next to the output
// (io/hdf5_fd_driver.h), which is named and renamed into place when complete
// (detail::write_file_atomically), so a reader never sees a half written file and no
// image of the whole file is held in memory.
// Standard output ("-") and write_bpm_to_memory get an image built in memory (core
// driver); both ways give the same bytes.
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
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "bpm/errors.h"
#include "bpm/tetmesh_materials.h"
#include "bpm/version.h"
#include "check/image_tolerance.h"
#include "core/file_util.h"
#include "core/huge_pages.h"
#include "io/bpm_file_rules.h"
#include "io/chunk_compressor.h"
#include "io/hdf5_fd_driver.h"
#include "io/hdf5_handle.h"

namespace bpm {

namespace {

using detail::ChunkCompressor;
using detail::find_inconsistency;
using detail::find_steps_inconsistency;
using detail::Handle;
using detail::hdf5_error_text;
using detail::kDeflateLevel;
using detail::num_text;
using detail::silence_hdf5;

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
// The optional /simplification_steps group (format 1.1, spec/bpm-format.md §10.1): the
// record of bpm-simplify --record-steps. Its rules are in io/bpm_file_rules.cpp, its
// reader in io/bpm_read.cpp.
// ---------------------------------------------------------------------------

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
            const auto point = [](const Vec3& x) { return "(" + num_text(x[0]) + ", " + num_text(x[1]) + ", " + num_text(x[2]) + ")"; };
            return "node_image[" + num_text(i) + "] = " + point(image) + " is not the point its node names, " + point(named) +
                   " (distance " + num_text(d) +
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
    if (!file.coordinate_frame.empty()) w.write_string_attribute(f, "coordinate_frame", file.coordinate_frame, H5T_CSET_ASCII);

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
    Handle f = create_file(w, "bpm-write-" + std::to_string(detail::next_image_number()) + ".h5", fapl);
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
            Handle f = create_file(w, "bpm-write-" + std::to_string(detail::next_image_number()) + ".h5", fapl);
            write_contents(w, f, file);
            w.check(f.close(), "cannot close the file");
        }
        if (status.error != 0) throw OutputError(path, std::string("cannot write: ") + std::strerror(status.error));
    });
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

}  // namespace bpm
