#include "file_util.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <random>

#include "bpm/errors.h"

namespace bpm::detail {

namespace {
std::string errno_text() { return std::strerror(errno); }

void write_all(int fd, const std::string& bytes, const std::string& where) {
    size_t done = 0;
    while (done < bytes.size()) {
        ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw OutputError(where, "cannot write: " + errno_text());
        }
        done += static_cast<size_t>(n);
    }
}
}  // namespace

std::string display_name(const std::string& path) { return path == "-" ? "<stdin>" : path; }

void write_file_atomically(const std::string& path, const std::string& bytes) {
    if (path == "-") {
        write_all(STDOUT_FILENO, bytes, "<stdout>");
        return;
    }
    namespace fs = std::filesystem;
    const fs::path target(path);
    std::error_code ec;
    if (fs::is_directory(target, ec)) throw OutputError(path, "is a directory");
    fs::path dir = target.parent_path();
    if (dir.empty()) dir = ".";
    if (!fs::is_directory(dir, ec)) throw OutputError(path, "directory does not exist: " + dir.string());

    // Unique temporary name next to the target, so that rename() is atomic.
    std::random_device rd;
    std::string tmp;
    int fd = -1;
    for (int attempt = 0; attempt < 16 && fd < 0; ++attempt) {
        char suffix[32];
        std::snprintf(suffix, sizeof suffix, ".tmp%08x", static_cast<unsigned>(rd()));
        tmp = (dir / ("." + target.filename().string() + suffix)).string();
        fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
        if (fd < 0 && errno != EEXIST) throw OutputError(path, "cannot create file: " + errno_text());
    }
    if (fd < 0) throw OutputError(path, "cannot create a temporary file next to it");
    try {
        write_all(fd, bytes, path);
        if (::fsync(fd) != 0) throw OutputError(path, "cannot flush to disk: " + errno_text());
    } catch (...) {
        ::close(fd);
        ::unlink(tmp.c_str());
        throw;
    }
    if (::close(fd) != 0) {
        ::unlink(tmp.c_str());
        throw OutputError(path, "cannot close: " + errno_text());
    }
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        const std::string why = errno_text();
        ::unlink(tmp.c_str());
        throw OutputError(path, "cannot rename the finished file into place: " + why);
    }
}

std::string read_whole_input(const std::string& path, size_t max_bytes) {
    const std::string where = display_name(path);
    int fd = STDIN_FILENO;
    if (path != "-") {
        struct stat st {};
        if (::stat(path.c_str(), &st) != 0) throw InputError(where, "cannot open: " + errno_text());
        if (S_ISDIR(st.st_mode)) throw InputError(where, "is a directory, not a file");
        if (S_ISREG(st.st_mode) && static_cast<unsigned long long>(st.st_size) > max_bytes)
            throw InputError(where, "file is larger than the limit of " + std::to_string(max_bytes) + " bytes");
        fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) throw InputError(where, "cannot open: " + errno_text());
    }
    std::string bytes;
    char buffer[1 << 16];
    for (;;) {
        ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n < 0) {
            if (errno == EINTR) continue;
            const std::string why = errno_text();
            if (fd != STDIN_FILENO) ::close(fd);
            throw InputError(where, "cannot read: " + why);
        }
        if (n == 0) break;
        if (bytes.size() + static_cast<size_t>(n) > max_bytes) {
            if (fd != STDIN_FILENO) ::close(fd);
            throw InputError(where, "input is larger than the limit of " + std::to_string(max_bytes) + " bytes");
        }
        bytes.append(buffer, static_cast<size_t>(n));
    }
    if (fd != STDIN_FILENO) ::close(fd);
    return bytes;
}

}  // namespace bpm::detail
