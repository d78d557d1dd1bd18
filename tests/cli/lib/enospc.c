/* A full disk for tests/cli/faults.sh, without root: an LD_PRELOAD shim whose write(),
 * pwrite(), pwrite64() and writev() fail with ENOSPC on regular files below the directory
 * $BPM_TEST_ENOSPC_DIR, after the first $BPM_TEST_ENOSPC_AFTER bytes (default 4096) of
 * each file descriptor - a short write first, then ENOSPC, as a filling disk does.
 * Everything else (stderr, pipes, files elsewhere, TetGen's temporary files) is untouched.
 * bpm writes its text outputs with write() (libbpm/src/core/file_util.cpp) and .bpm files
 * with pwrite() (HDF5 through libbpm/src/io/hdf5_fd_driver.cpp), so these are the paths a
 * real full disk takes.
 *
 *   cc -shared -fPIC -o enospc.so enospc.c -ldl
 *   LD_PRELOAD=./enospc.so BPM_TEST_ENOSPC_DIR=/some/dir bpm-simplify ... -o /some/dir/out.bpm
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

#define MAX_FDS 1024
static long long written[MAX_FDS];

/* Bytes that may still be written to `fd` (LLONG_MAX: not a file the shim fails). */
static long long room(int fd) {
    const char* dir = getenv("BPM_TEST_ENOSPC_DIR");
    if (!dir || !*dir || fd < 0 || fd >= MAX_FDS) return LLONG_MAX;
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) return LLONG_MAX;
    char link[64], path[PATH_MAX];
    snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
    const ssize_t n = readlink(link, path, sizeof path - 1);
    if (n < 0) return LLONG_MAX;
    path[n] = '\0';
    const size_t len = strlen(dir);
    if (strncmp(path, dir, len) != 0 || path[len] != '/') return LLONG_MAX;
    const char* after = getenv("BPM_TEST_ENOSPC_AFTER");
    const long long limit = after ? atoll(after) : 4096;
    return written[fd] >= limit ? 0 : limit - written[fd];
}

/* How much of `count` bytes to pass on; -1 with errno = ENOSPC when nothing fits. */
static ssize_t allowed(int fd, size_t count) {
    const long long r = room(fd);
    if (r == LLONG_MAX || count == 0) return (ssize_t)count;
    if (r == 0) {
        errno = ENOSPC;
        return -1;
    }
    return (ssize_t)((long long)count < r ? (long long)count : r);
}

static void account(int fd, ssize_t n) {
    if (n > 0 && fd >= 0 && fd < MAX_FDS) written[fd] += n;
}

ssize_t write(int fd, const void* buf, size_t count) {
    static ssize_t (*real)(int, const void*, size_t);
    if (!real) real = (ssize_t(*)(int, const void*, size_t))dlsym(RTLD_NEXT, "write");
    const ssize_t n = allowed(fd, count);
    if (n < 0) return -1;
    const ssize_t done = real(fd, buf, (size_t)n);
    account(fd, done);
    return done;
}

ssize_t pwrite(int fd, const void* buf, size_t count, off_t offset) {
    static ssize_t (*real)(int, const void*, size_t, off_t);
    if (!real) real = (ssize_t(*)(int, const void*, size_t, off_t))dlsym(RTLD_NEXT, "pwrite");
    const ssize_t n = allowed(fd, count);
    if (n < 0) return -1;
    const ssize_t done = real(fd, buf, (size_t)n, offset);
    account(fd, done);
    return done;
}

ssize_t pwrite64(int fd, const void* buf, size_t count, off_t offset) {
    static ssize_t (*real)(int, const void*, size_t, off_t);
    if (!real) real = (ssize_t(*)(int, const void*, size_t, off_t))dlsym(RTLD_NEXT, "pwrite64");
    const ssize_t n = allowed(fd, count);
    if (n < 0) return -1;
    const ssize_t done = real(fd, buf, (size_t)n, offset);
    account(fd, done);
    return done;
}

ssize_t writev(int fd, const struct iovec* iov, int iovcnt) {
    static ssize_t (*real)(int, const struct iovec*, int);
    if (!real) real = (ssize_t(*)(int, const struct iovec*, int))dlsym(RTLD_NEXT, "writev");
    size_t total = 0;
    for (int i = 0; i < iovcnt; ++i) total += iov[i].iov_len;
    const ssize_t n = allowed(fd, total);
    if (n < 0) return -1;
    if ((size_t)n < total) {  /* a short write: only the first buffer, cut to what fits */
        const size_t first = iovcnt > 0 ? iov[0].iov_len : 0;
        return write(fd, iovcnt > 0 ? iov[0].iov_base : NULL, (size_t)n < first ? (size_t)n : first);
    }
    const ssize_t done = real(fd, iov, iovcnt);
    account(fd, done);
    return done;
}

int close(int fd) {
    static int (*real)(int);
    if (!real) real = (int (*)(int))dlsym(RTLD_NEXT, "close");
    if (fd >= 0 && fd < MAX_FDS) written[fd] = 0;
    return real(fd);
}
