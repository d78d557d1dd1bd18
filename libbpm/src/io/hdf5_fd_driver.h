#pragma once
// An HDF5 file driver that writes to a descriptor the caller has opened (internal to
// libbpm's io/). It lets the .bpm writer stream a file straight into the unnamed
// temporary of detail::write_file_atomically (core/file_util.h): HDF5's own drivers open
// files by name, and HDF5 refuses /proc/self/fd names (it resolves them to a path that
// does not exist).
//
// A failed write or read does not fail the HDF5 call: the driver records the operating
// system's error, skips every later write, and the caller checks the record after closing
// the file. HDF5 1.10.8 frees a file whose close failed (its final flush hit a full disk)
// but keeps its identifier, and crashes on that identifier at exit; with this driver the
// close does not fail.
//
// The driver declares the same allocation features as HDF5's sec2 and core drivers
// (metadata and small-data aggregation, metadata accumulation, data sieving), so a file
// written through it has the same bytes as one written through either.

#include <hdf5.h>

namespace bpm::detail {

// What happened to the descriptor's file: 0, or errno of the first failed write or read.
struct FdDriverStatus {
    int error = 0;
};

// Whether HDF5 accepts the driver (registered on the first call). A build against an
// HDF5 whose driver interface this file does not know gets false, and the writer falls
// back to its in-memory image.
bool fd_driver_available();

// A new file access property list (the caller closes it) whose files are read and
// written through `fd`, which must be open for reading and writing and stay open until
// the file is closed; it is never closed by the driver. Failures are recorded in
// `*status`, which must outlive the file. Returns a negative id on failure (HDF5's error
// stack says why).
hid_t fd_driver_access_plist(int fd, FdDriverStatus* status);

}  // namespace bpm::detail
