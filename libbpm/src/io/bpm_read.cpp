// Reading the bpm file format on top of the HDF5 C API. spec/bpm-format.md is normative;
// this file is one implementation of it (the writer is io/bpm_write.cpp, the rules both
// check io/bpm_file_rules.cpp). Reading goes through a file image, which makes standard
// input and memory buffers the same case as files; bpm-info's outline of a plain file is
// read in place.

#include "bpm/bpm_file.h"

#include <hdf5.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "bpm/errors.h"
#include "bpm/tetmesh_materials.h"
#include "bpm/version.h"
#include "core/file_util.h"
#include "core/gzip.h"
#include "io/bpm_file_rules.h"
#include "io/bpm_outline.h"
#include "io/hdf5_handle.h"

namespace bpm {

namespace {

using detail::find_inconsistency;
using detail::find_steps_inconsistency;
using detail::Handle;
using detail::hdf5_error_text;
using detail::num_text;
using detail::silence_hdf5;

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
        for (int i = 0; i < rank; ++i) found += (i ? ", " : "") + num_text(dims[i]);
        found += rank == 1 ? ",)" : ")";
        if (rank != expected_rank || (cols != 0 && dims[1] != cols))
            fail(path + ": expected shape " + shape_text + ", found shape " + found);
        if (dims[0] > kMaxRows) fail(path + ": has an absurd number of rows (" + num_text(dims[0]) + ")");

        Handle type(H5Dget_type(ds), H5Tclose);
        const size_t elem = type.valid() ? H5Tget_size(type) : 0;
        if (elem == 0) fail(path + ": cannot read its datatype");
        const double logical = double(dims[0]) * double(cols == 0 ? 1 : cols) * double(elem);
        Handle dcpl(H5Dget_create_plist(ds), H5Pclose);
        const int filters = dcpl.valid() ? H5Pget_nfilters(dcpl) : 0;
        const double limit = filters > 0 ? kMaxCompressionRatio * double(file_size_) + double(1 << 20)
                                         : double(file_size_);
        if (logical > limit)
            fail(path + ": shape " + found + " needs " + num_text(logical) + " bytes, more than a " + num_text(file_size_) +
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
        if (cols > kMaxRows) fail(path + ": has an absurd number of columns (" + num_text(cols) + ")");
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
            r.fail(path + ": element " + num_text(i) + " = " + num_text(v[i]) + " does not fit in int32");
        out[i] = static_cast<int32_t>(v[i]);
    }
    return out;
}

void check_finite(const Reader& r, const std::vector<double>& v, const std::string& path, size_t cols) {
    for (size_t i = 0; i < v.size(); ++i)
        if (!std::isfinite(v[i]))
            r.fail(path + ": entry [" + num_text(i / cols) + ", " + num_text(i % cols) + "] is not finite (" + num_text(v[i]) + ")");
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
        r.fail(path + ": has " + num_text(rows) + " rows, expected " + num_text(expected) + " (" + why + ")");
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
    if (level[0] < 0 || level[0] > 64) r.fail("/tetmesh: attribute 'level' = " + num_text(level[0]) + " is out of range");
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
            r.fail(g + "/oriented: entry " + num_text(i) + " = " + num_text(oriented[i]) + " is not 0 or 1");
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
    const std::string name = "bpm-read-" + std::to_string(detail::next_image_number()) + ".h5";
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
        r.fail("root attribute 'format_version': file has format version " + num_text(version[0]) + "." + num_text(version[1]) +
               ", this reader supports major versions 1 to " + num_text(BPM_FORMAT_VERSION_MAJOR) +
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
    out.coordinate_frame = r.read_string_attribute("coordinate_frame", false);
    // spec §2: any other value is "unknown"; kept, the tools would copy it into every file
    // they write from this one.
    if (out.coordinate_frame != "LPS" && out.coordinate_frame != "RAS") out.coordinate_frame.clear();

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
            r.fail("/phi/node_kind: entry " + num_text(i) + " = " + num_text(kinds[i]) + " is not a valid node kind (0, 1 or 2)");
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
                r.fail("/coarse/triangles: row " + num_text(t) + " has vertex " + num_text(v) + ", outside [0, " + num_text(nvc) + ")");
    out.phi_nodes = int64_t(r.read_rows("/phi/node_kind", 0, "(#N,)", false));
    out.phi_pieces = int64_t(r.read_rows("/phi/pieces", 3, "(#P, 3)", false));
    out.provenance = read_provenance(r);

    if (r.exists("/tetmesh")) {
        detail::BpmTetMeshOutline t;
        const auto level = r.read_object_int_attribute("/tetmesh", "level");
        if (level.size() != 1) r.fail("/tetmesh: attribute 'level' must hold one integer");
        if (level[0] < 0 || level[0] > 64) r.fail("/tetmesh: attribute 'level' = " + num_text(level[0]) + " is out of range");
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
