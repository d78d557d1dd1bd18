#include "io/hdf5_fd_driver.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <mutex>

namespace bpm::detail {

namespace {

struct Config {
    int fd;
    FdDriverStatus* status;
};

struct File {
    H5FD_t pub;  // first: HDF5 casts between H5FD_t* and the driver's struct
    Config config;
    haddr_t eoa, eof;
};

File* as_file(H5FD_t* f) { return reinterpret_cast<File*>(f); }
const File* as_file(const H5FD_t* f) { return reinterpret_cast<const File*>(f); }

void* config_copy(const void* c) {
    auto* copy = static_cast<Config*>(std::malloc(sizeof(Config)));
    if (copy) *copy = *static_cast<const Config*>(c);
    return copy;
}
void* config_get(H5FD_t* f) { return config_copy(&as_file(f)->config); }
herr_t config_free(void* c) {
    std::free(c);
    return 0;
}

H5FD_t* open_file(const char*, unsigned, hid_t fapl, haddr_t) {
    const auto* config = static_cast<const Config*>(H5Pget_driver_info(fapl));
    if (!config) return nullptr;
    auto* f = static_cast<File*>(std::calloc(1, sizeof(File)));
    if (!f) return nullptr;
    f->config = *config;
    const off_t end = ::lseek(config->fd, 0, SEEK_END);
    f->eof = end > 0 ? haddr_t(end) : 0;
    return &f->pub;
}

herr_t close_file(H5FD_t* f) {
    std::free(as_file(f));
    return 0;
}

int compare(const H5FD_t* a, const H5FD_t* b) {
    const int x = as_file(a)->config.fd, y = as_file(b)->config.fd;
    return x < y ? -1 : x > y ? 1 : 0;
}

herr_t query(const H5FD_t*, unsigned long* flags) {
    // The allocation features of sec2 and core: they decide where objects go in the file.
    if (flags)
        *flags = H5FD_FEAT_AGGREGATE_METADATA | H5FD_FEAT_ACCUMULATE_METADATA | H5FD_FEAT_DATA_SIEVE |
                 H5FD_FEAT_AGGREGATE_SMALLDATA;
    return 0;
}

haddr_t get_eoa(const H5FD_t* f, H5FD_mem_t) { return as_file(f)->eoa; }
herr_t set_eoa(H5FD_t* f, H5FD_mem_t, haddr_t addr) {
    as_file(f)->eoa = addr;
    return 0;
}
haddr_t get_eof(const H5FD_t* f, H5FD_mem_t) { return as_file(f)->eof; }

herr_t get_handle(H5FD_t* f, hid_t, void** handle) {
    *handle = &as_file(f)->config.fd;
    return 0;
}

void record(File* f, int error) {
    if (f->config.status->error == 0) f->config.status->error = error;
}

herr_t read(H5FD_t* pub, H5FD_mem_t, hid_t, haddr_t addr, size_t size, void* buffer) {
    File* f = as_file(pub);
    auto* out = static_cast<unsigned char*>(buffer);
    while (size > 0) {
        const ssize_t n = ::pread(f->config.fd, out, size, off_t(addr));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) record(f, errno);
        if (n <= 0) break;  // past the end of the file (or failed): zeros, as sec2 reads
        out += n;
        addr += haddr_t(n);
        size -= size_t(n);
    }
    std::memset(out, 0, size);
    return 0;
}

herr_t write(H5FD_t* pub, H5FD_mem_t, hid_t, haddr_t addr, size_t size, const void* buffer) {
    File* f = as_file(pub);
    f->eof = std::max(f->eof, addr + size);
    if (f->config.status->error != 0) return 0;  // the file is lost already
    const auto* in = static_cast<const unsigned char*>(buffer);
    while (size > 0) {
        const ssize_t n = ::pwrite(f->config.fd, in, size, off_t(addr));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            record(f, n < 0 ? errno : EIO);
            return 0;
        }
        in += n;
        addr += haddr_t(n);
        size -= size_t(n);
    }
    return 0;
}

// The file ends where the allocated space ends, as with sec2 (which extends or cuts it).
herr_t truncate(H5FD_t* pub, hid_t, hbool_t) {
    File* f = as_file(pub);
    if (f->eoa == f->eof) return 0;
    if (f->config.status->error == 0 && ::ftruncate(f->config.fd, off_t(f->eoa)) != 0) record(f, errno);
    f->eof = f->eoa;
    return 0;
}

H5FD_class_t make_class() {
    H5FD_class_t c;
    std::memset(&c, 0, sizeof c);
#ifdef H5FD_CLASS_VERSION
    // HDF5 >= 1.13.2 versions the class and gives every driver a number (256-511 are free
    // for drivers that are not registered with The HDF Group). Not built here (Debian 12
    // has 1.10.8): if the registration fails, write_bpm builds the file in memory instead.
    c.version = H5FD_CLASS_VERSION;
    c.value = H5FD_class_value_t(511);
#endif
    c.name = "bpm_descriptor";
    c.maxaddr = (haddr_t(1) << (8 * sizeof(off_t) - 1)) - 1;
    c.fc_degree = H5F_CLOSE_WEAK;
    c.fapl_size = sizeof(Config);
    c.fapl_get = config_get;
    c.fapl_copy = config_copy;
    c.fapl_free = config_free;
    c.open = open_file;
    c.close = close_file;
    c.cmp = compare;
    c.query = query;
    c.get_eoa = get_eoa;
    c.set_eoa = set_eoa;
    c.get_eof = get_eof;
    c.get_handle = get_handle;
    c.read = read;
    c.write = write;
    c.truncate = truncate;
    const H5FD_mem_t dichotomy[H5FD_MEM_NTYPES] = H5FD_FLMAP_DICHOTOMY;  // as sec2 and core
    std::copy(dichotomy, dichotomy + H5FD_MEM_NTYPES, c.fl_map);
    return c;
}

}  // namespace

namespace {
// The driver's id, registered once (again if HDF5 was closed and reopened); negative if
// HDF5 refuses the class.
hid_t registered_driver() {
    static const H5FD_class_t driver_class = make_class();
    static hid_t driver = -1;
    static std::mutex mutex;
    std::lock_guard<std::mutex> lock(mutex);
    if (driver < 0 || H5Iis_valid(driver) <= 0) driver = H5FDregister(&driver_class);
    return driver;
}
}  // namespace

bool fd_driver_available() { return registered_driver() >= 0; }

hid_t fd_driver_access_plist(int fd, FdDriverStatus* status) {
    const hid_t driver = registered_driver();
    if (driver < 0) return -1;
    const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    if (fapl < 0) return -1;
    const Config config{fd, status};
    if (H5Pset_driver(fapl, driver, &config) < 0) {
        H5Pclose(fapl);
        return -1;
    }
    return fapl;
}

}  // namespace bpm::detail
