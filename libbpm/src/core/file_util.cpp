#include "core/file_util.h"
#include "core/gzip.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>
#include <random>
#include <vector>

#include "bpm/errors.h"
#include "core/huge_pages.h"

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

namespace {
// Makes a rename in `dir` durable (power loss); errors are ignored: the file is complete.
void sync_directory(const std::string& dir) {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    (void)::fsync(fd);
    ::close(fd);
}
}  // namespace

namespace {
// The directory of `path`, after checking that `path` can be a file there.
std::filesystem::path output_directory(const std::string& path) {
    namespace fs = std::filesystem;
    const fs::path target(path);
    std::error_code ec;
    if (fs::is_directory(target, ec)) throw OutputError(path, "is a directory");
    fs::path dir = target.parent_path();
    if (dir.empty()) dir = ".";
    if (!fs::is_directory(dir, ec)) throw OutputError(path, "directory does not exist: " + dir.string());
    return dir;
}

// The file `path` names, through any symbolic links: the output replaces that file, as
// writing into it would (a shell's '>' or cp), and the links stay links (renaming over
// `path` itself would replace the link with a file and leave its target as it was).
// A dangling link names the file it would create. Throws OutputError for a loop.
std::string follow_symlinks(const std::string& path) {
    std::string p = path;
    for (int hops = 0; hops < 40; ++hops) {
        struct stat st;
        if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return p;
        std::vector<char> text(static_cast<size_t>(st.st_size > 0 ? st.st_size : 255) + 1);
        const ssize_t n = ::readlink(p.c_str(), text.data(), text.size());
        if (n < 0 || static_cast<size_t>(n) >= text.size()) return p;  // changed meanwhile: rename over it
        const std::filesystem::path link(std::string(text.data(), static_cast<size_t>(n)));
        p = link.is_absolute() ? link.string() : (std::filesystem::path(p).parent_path() / link).string();
    }
    throw OutputError(path, "cannot write through it: too many levels of symbolic links");
}

// The permission bits of the regular file `path` replaces, so that a file made private
// (chmod 600) or executable stays so; nothing if there is none.
std::optional<mode_t> existing_mode(const std::string& path) {
    struct stat st;
    if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return std::nullopt;
    return st.st_mode & 07777;
}

// Gives the finished file the permission bits of the one it replaces.
void keep_mode(int fd, const std::optional<mode_t>& mode, const std::string& path) {
    if (mode && ::fchmod(fd, *mode) != 0) throw OutputError(path, "cannot set its permissions: " + errno_text());
}

// A fresh temporary name next to `path` (so that rename() is atomic): ".NAME.tmpXXXXXXXX".
std::string temporary_name(const std::filesystem::path& dir, const std::string& path) {
    static thread_local std::random_device rd;
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, ".tmp%08x", static_cast<unsigned>(rd()));
    return (dir / ("." + std::filesystem::path(path).filename().string() + suffix)).string();
}

// Creates a new temporary file next to `path`, open read-write; its name in `tmp`.
int create_temporary(const std::filesystem::path& dir, const std::string& path, std::string& tmp) {
    int fd = -1;
    for (int attempt = 0; attempt < 16 && fd < 0; ++attempt) {
        tmp = temporary_name(dir, path);
        fd = ::open(tmp.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
        if (fd < 0 && errno != EEXIST) throw OutputError(path, "cannot create file: " + errno_text());
    }
    if (fd < 0) throw OutputError(path, "cannot create a temporary file next to it");
    return fd;
}

// Gives the unnamed file open as `fd` a temporary name next to `path` (in `tmp`), through
// /proc/self/fd. Returns false, with errno set, if that is not possible.
bool name_unnamed(int fd, const std::filesystem::path& dir, const std::string& path, std::string& tmp) {
    const std::string self = "/proc/self/fd/" + std::to_string(fd);
    for (int attempt = 0; attempt < 16; ++attempt) {
        tmp = temporary_name(dir, path);
        if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, tmp.c_str(), AT_SYMLINK_FOLLOW) == 0) return true;
        if (errno != EEXIST) return false;
    }
    return false;
}

// Closes `fd`, the complete temporary file `tmp`, and renames it over `path`; the
// temporary is removed if any of it fails.
// `where` names the output in messages (the path the user gave, `path` may be its link's target).
void close_and_rename(int fd, const std::string& tmp, const std::string& path, const std::filesystem::path& dir,
                      const std::string& where) {
    if (::close(fd) != 0) {
        const std::string why = errno_text();
        ::unlink(tmp.c_str());
        throw OutputError(where, "cannot close: " + why);
    }
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        const std::string why = errno_text();
        ::unlink(tmp.c_str());
        throw OutputError(where, "cannot rename the finished file into place: " + why);
    }
    sync_directory(dir.string());
}
}  // namespace

void write_file_atomically(const std::string& path, const std::string& bytes) {
    if (path == "-") {
        write_all(STDOUT_FILENO, bytes, "<stdout>");
        return;
    }
    write_file_atomically(path, [&](int fd) { write_all(fd, bytes, path); });
}

void write_file_atomically(const std::string& where, const std::function<void(int fd)>& fill) {
    if (where == "-") throw OutputError("<stdout>", "internal error: standard output cannot be written in place");
    const std::string path = follow_symlinks(where);
    const std::filesystem::path dir = output_directory(path);
    const std::optional<mode_t> mode = existing_mode(path);

#ifdef O_TMPFILE
    // Preferred (Linux): an unnamed file in the target's directory, given a name only once
    // it is complete and on disk, so that a process killed while writing leaves nothing
    // behind. Filesystems without O_TMPFILE fall through to a named temporary file.
    int unnamed = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0644);
    if (unnamed < 0 && errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL)
        throw OutputError(where, "cannot create file: " + errno_text());
    if (unnamed >= 0) {
        try {
            fill(unnamed);
            keep_mode(unnamed, mode, where);
            if (::fsync(unnamed) != 0) throw OutputError(where, "cannot flush to disk: " + errno_text());
        } catch (...) {
            ::close(unnamed);  // the unnamed file disappears with its descriptor
            throw;
        }
        std::string tmp;
        if (name_unnamed(unnamed, dir, path, tmp)) {
            close_and_rename(unnamed, tmp, path, dir, where);
            return;
        }
        const int link_errno = errno;
        ::close(unnamed);
        // No /proc, or linking refused: write again under a name (below), unless the
        // directory cannot take one more entry anyway.
        if (link_errno == ENOSPC || link_errno == EDQUOT || link_errno == EROFS)
            throw OutputError(where, "cannot create file: " + std::string(std::strerror(link_errno)));
    }
#endif

    std::string tmp;
    const int fd = create_temporary(dir, path, tmp);
    try {
        fill(fd);
        keep_mode(fd, mode, where);
        if (::fsync(fd) != 0) throw OutputError(where, "cannot flush to disk: " + errno_text());
    } catch (...) {
        ::close(fd);
        ::unlink(tmp.c_str());
        throw;
    }
    close_and_rename(fd, tmp, path, dir, where);
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
    // A regular file is read in one piece of its size, without regrowing the string
    // (a copy and fresh page faults per doubling; a few percent of reading a large OFF).
    struct stat st {};
    if (fd != STDIN_FILENO && ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0)
        bytes.reserve(std::min(static_cast<size_t>(st.st_size) + 1, max_bytes + 1));
    advise_huge_pages(bytes.data(), bytes.capacity());
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
    return decompress_if_gzip(std::move(bytes), where, path != "-" && has_gz_suffix(path), max_bytes);
}

namespace {
// Exit codes of the isolated child.
constexpr int kChildOk = 0;
constexpr int kChildInputError = 3;
constexpr int kChildOtherError = 70;
}  // namespace

std::optional<std::string> run_isolated(const std::string& where, const std::string& library,
                                        const std::function<std::string()>& parse) {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return std::nullopt;
    std::fflush(nullptr);  // nothing buffered may be written twice
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        return std::nullopt;
    }
    if (pid == 0) {
        // The child: parse, report, and leave with _exit (no atexit handlers, no stdio
        // flush of buffers inherited from the parent).
        ::close(fds[0]);
#ifdef __linux__
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (::getppid() == 1) ::_exit(kChildOtherError);  // the parent is already gone
#endif
        const int devnull = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
        if (devnull >= 0) {
            ::dup2(devnull, STDOUT_FILENO);
            ::dup2(devnull, STDERR_FILENO);
        }
        if (const char* crash = std::getenv("BPM_TEST_ISOLATED_CRASH")) {
            ::signal(std::atoi(crash), SIG_DFL);
            ::raise(std::atoi(crash));
        }
        // The pipe carries the result on success, the message on an InputError; first
        // its length (8 bytes), so that the parent can allocate it at once.
        auto send = [&](const std::string& bytes) {
            const uint64_t length = bytes.size();
            const char* parts[2] = {reinterpret_cast<const char*>(&length), bytes.data()};
            const size_t sizes[2] = {sizeof length, bytes.size()};
            for (int part = 0; part < 2; ++part) {
                size_t done = 0;
                while (done < sizes[part]) {
                    const ssize_t n = ::write(fds[1], parts[part] + done, sizes[part] - done);
                    if (n < 0 && errno == EINTR) continue;
                    if (n <= 0) return false;
                    done += static_cast<size_t>(n);
                }
            }
            return true;
        };
        int code = kChildOk;
        try {
            if (!send(parse())) code = kChildOtherError;  // the parent then parses in-process
        } catch (const InputError& e) {
            send(e.what());
            code = kChildInputError;
        } catch (...) {
            code = kChildOtherError;
        }
        ::_exit(code);
    }
    ::close(fds[1]);
    // The result, or the message of an InputError, after its 8-byte length. Whatever
    // arrives is read to the end (the child must not block on a full pipe).
    std::string message;
    {
        uint64_t length = 0;
        size_t got = 0;
        std::vector<char> buffer(size_t(1) << 16);  // appended to `message`, reserved at once
        for (;;) {
            const bool header = got < sizeof length;
            char* into = header ? reinterpret_cast<char*>(&length) + got : buffer.data();
            const size_t room = header ? sizeof length - got : buffer.size();
            const ssize_t n = ::read(fds[0], into, room);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) break;
            if (header) {
                got += static_cast<size_t>(n);
                if (got == sizeof length) message.reserve(static_cast<size_t>(std::min<uint64_t>(length, uint64_t(1) << 36)));
            } else {
                message.append(into, static_cast<size_t>(n));
            }
        }
    }
    ::close(fds[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR) return std::nullopt;  // cannot tell what happened: parse in-process
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == kChildOk) return message;
    if (WIFEXITED(status) && WEXITSTATUS(status) == kChildOtherError) return std::nullopt;
    if (WIFEXITED(status) && WEXITSTATUS(status) == kChildInputError) throw InputError(where, message);
    if (WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)
        throw InputError(where, "the process reading it with the " + library +
                                    " library was killed (signal 9; out of memory?)");
    std::string how;
    if (WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        const char* name = ::strsignal(sig);
        how = "signal " + std::to_string(sig) + (name ? std::string(", ") + name : std::string());
    } else {
        how = "exit code " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    }
    throw InputError(where, "the " + library + " library crashed reading it (" + how + "): the file is corrupt");
}

}  // namespace bpm::detail
