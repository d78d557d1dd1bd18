#pragma once
// Editing a .bpm file image with the HDF5 C API, to make malformed files for the reader
// tests (bpm_file_test.cpp, simplification_steps_test.cpp).

#include <hdf5.h>

#include <catch2/catch.hpp>
#include <functional>
#include <string>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/errors.h"

namespace bpm::test {

// The bytes of a .bpm file opened read-write in memory (HDF5 core driver).
struct Hdf5Image {
    hid_t file = -1;
    explicit Hdf5Image(const std::string& bytes) {
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
        hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
        H5Pset_fapl_core(fapl, 1 << 16, false);
        H5Pset_file_image(fapl, const_cast<char*>(bytes.data()), bytes.size());
        static int counter = 0;  // the core driver still wants a unique name
        const std::string name = "mutate-" + std::to_string(counter++) + ".h5";
        file = H5Fopen(name.c_str(), H5F_ACC_RDWR, fapl);
        H5Pclose(fapl);
        REQUIRE(file >= 0);
    }
    ~Hdf5Image() {
        if (file >= 0) H5Fclose(file);
    }
    Hdf5Image(const Hdf5Image&) = delete;
    Hdf5Image& operator=(const Hdf5Image&) = delete;

    // The edited file.
    std::string bytes() {
        REQUIRE(H5Fflush(file, H5F_SCOPE_GLOBAL) >= 0);
        const ssize_t n = H5Fget_file_image(file, nullptr, 0);
        std::string out(static_cast<size_t>(n), '\0');
        REQUIRE(H5Fget_file_image(file, out.data(), out.size()) == n);
        return out;
    }
    bool exists(const char* path) const { return H5Lexists(file, path, H5P_DEFAULT) > 0; }
    void remove(const char* path) { REQUIRE(H5Ldelete(file, path, H5P_DEFAULT) >= 0); }
    // Replaces a dataset by one of the given type, shape and (raw, memory-typed) data;
    // allocate = false leaves it unwritten.
    void replace(const char* path, hid_t type, std::vector<hsize_t> dims, const void* data, bool allocate = true) {
        remove(path);
        create(path, type, dims, data, allocate);
    }
    // Adds a dataset (contiguous, uncompressed) where there was none.
    void create(const char* path, hid_t type, std::vector<hsize_t> dims, const void* data, bool allocate = true) {
        hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
        hid_t ds = H5Dcreate2(file, path, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        REQUIRE(ds >= 0);
        if (allocate) REQUIRE(H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0);
        H5Dclose(ds);
        H5Sclose(space);
    }
    // Reads the whole dataset as `mem_type`, lets `edit` change it, writes it back.
    template <typename T>
    void edit(const char* path, hid_t mem_type, const std::function<void(std::vector<T>&)>& edit) {
        hid_t ds = H5Dopen2(file, path, H5P_DEFAULT);
        REQUIRE(ds >= 0);
        hid_t space = H5Dget_space(ds);
        std::vector<T> values(static_cast<size_t>(H5Sget_simple_extent_npoints(space)));
        REQUIRE(H5Dread(ds, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) >= 0);
        edit(values);
        REQUIRE(H5Dwrite(ds, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) >= 0);
        H5Sclose(space);
        H5Dclose(ds);
    }
    // Replaces an int32 attribute of the root group (e.g. format_version).
    void set_root_ints(const char* name, std::vector<int32_t> values) {
        REQUIRE(H5Adelete(file, name) >= 0);
        hsize_t n = values.size();
        hid_t space = H5Screate_simple(1, &n, nullptr);
        hid_t a = H5Acreate2(file, name, H5T_STD_I32LE, space, H5P_DEFAULT, H5P_DEFAULT);
        REQUIRE(H5Awrite(a, H5T_NATIVE_INT32, values.data()) >= 0);
        H5Aclose(a);
        H5Sclose(space);
    }
};

// Expects reading `bytes` to throw an InputError naming "bad.bpm" whose message contains
// every one of `parts`.
inline void require_input_error(const std::string& bytes, const std::vector<std::string>& parts) {
    try {
        read_bpm_from_memory(bytes, "bad.bpm");
        FAIL("no InputError; expected one mentioning " << parts.front());
    } catch (const InputError& e) {
        INFO("message: " << e.what());
        CHECK(e.where() == "bad.bpm");
        for (const auto& part : parts) CHECK(std::string(e.what()).find(part) != std::string::npos);
    }
}

}  // namespace bpm::test
