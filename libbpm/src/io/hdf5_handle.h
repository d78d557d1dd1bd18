#pragma once
// Small helpers of the HDF5 C API shared by the .bpm writer (io/bpm_write.cpp) and reader
// (io/bpm_read.cpp). Internal to libbpm: HDF5 never appears in a public header.

#include <hdf5.h>

#include <string>

namespace bpm::detail {

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
void silence_hdf5();

// The innermost HDF5 error description, appended to messages for diagnosis; clears the
// error stack.
std::string hdf5_error_text();

// A number for the name of an in-memory HDF5 file (core driver), unique in this process:
// files open at the same time must have different names, whether written or read.
unsigned next_image_number();

}  // namespace bpm::detail
