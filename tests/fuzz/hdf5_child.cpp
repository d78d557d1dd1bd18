// The HDF5 isolation of the .bpm fuzz targets (tests/fuzz/hdf5_child.h).
//
// HDF5 crashes. HDF5 itself (Debian libhdf5 1.10.8, not instrumented) crashes on some
// corrupt files, about one input in a few thousand, or misbehaves in a way ASan sees at
// its libc calls (heap over-reads in strdup, memcpy with size -1; io/bpm_read.cpp, "HDF5
// crashes"). The tools survive that by parsing in a child process first
// (bpm::set_hdf5_isolation). The .bpm targets do the same, but keep the child's sanitizer
// report and classifies it: a report whose innermost frame outside libc and the sanitizer
// runtime is in libhdf5 is HDF5's (the input is skipped, counted on stderr as "HDF5 crash
// skipped", and saved to $BPM_FUZZ_HDF5_CRASH_DIR if set); a report anywhere else - our
// reader - is a finding. A child that takes longer than kChildSeconds is sent SIGABRT, so
// that ASan prints where it hangs (scripts/fuzz.sh sets handle_abort=1), and classified
// the same way. Inputs the child parsed without any report are then parsed in-process,
// with coverage, leak checks and the target's own properties.

#include "hdf5_child.h"

#include <fcntl.h>
#include <hdf5.h>
#include <poll.h>
#include <sanitizer/common_interface_defs.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

namespace bpm_fuzz {

namespace {

constexpr int kChildSeconds = 10;

ParseFunction g_parse = nullptr;  // set by start_zygote, before the fork

}  // namespace

[[noreturn]] void fail(const char* what, const std::string& detail) {
    std::fprintf(stderr, "fuzz property violated: %s %s\n", what, detail.c_str());
    std::abort();
}

void check_nothing_open() {
    const ssize_t open = H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL);
    if (open != 0) fail("HDF5 identifiers left open:", std::to_string(open));
}

namespace {

// The innermost stack frame of a sanitizer report that is neither the sanitizer runtime
// nor libc; empty if there is none.
std::string culprit_frame(const std::string& report) {
    std::istringstream lines(report);
    std::string line;
    while (std::getline(lines, line)) {
        // "    #3 0x7f04705ae37a in H5O__create_ohdr (/lib/.../libhdf5_serial.so.103+0x1ae37a)"
        // or, without a symbol, "    #1 0x7f04705233e4  (/lib/.../libhdf5_serial.so.103+0x1233e4)"
        const size_t hash = line.find_first_not_of(' ');
        if (hash == std::string::npos || line[hash] != '#' || hash + 1 >= line.size() ||
            !std::isdigit(static_cast<unsigned char>(line[hash + 1])))
            continue;
        static const char* kRuntime[] = {"__interceptor_", "__asan", "__sanitizer", "__ubsan", "sysdeps/",
                                         "nptl/",          "libc.so", "libc-",      " in raise", " in abort",
                                         "/stdlib/",       "/malloc/", " in malloc ", " in calloc ", " in realloc ",
                                         " in free ",      " in strdup ", "libclang_rt", "compiler-rt"};
        bool runtime = false;
        for (const char* r : kRuntime) runtime = runtime || line.find(r) != std::string::npos;
        if (!runtime) return line;
    }
    return {};
}

void save_hdf5_crash(const std::string& bytes) {
    const char* dir = std::getenv("BPM_FUZZ_HDF5_CRASH_DIR");
    if (!dir) return;
    const std::string path = std::string(dir) + "/hdf5-crash-" + std::to_string(std::hash<std::string>{}(bytes));
    std::ofstream(path, std::ios::binary) << bytes;
}

// ---- the zygote ------------------------------------------------------------------------
// Forking the fuzzer process itself for every input costs ~100 ms (hundreds of MB of
// ASan quarantine and corpus to copy-on-write). So a small "zygote" process is forked
// once, before the fuzzer's memory grows; it forks a short-lived child per input, which
// parses it, and sends back the child's exit status and sanitizer report.

bool read_all(int fd, void* data, size_t size) {
    char* p = static_cast<char*>(data);
    while (size > 0) {
        const ssize_t n = ::read(fd, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        p += n;
        size -= static_cast<size_t>(n);
    }
    return true;
}

bool write_all(int fd, const void* data, size_t size) {
    const char* p = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::write(fd, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        p += n;
        size -= static_cast<size_t>(n);
    }
    return true;
}

struct ChildResult {
    int32_t status = 0;   // waitpid status
    int32_t hung = 0;     // 1: sent SIGABRT after kChildSeconds
    std::string report;   // the child's stderr / sanitizer report
};

// Runs in a fresh child of the zygote: parse, exit 0; a crash leaves a report.
[[noreturn]] void child_parse(const std::string& bytes, int report_fd) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    __sanitizer_set_report_fd(reinterpret_cast<void*>(static_cast<intptr_t>(report_fd)));
    __sanitizer_set_death_callback([] { ::_exit(99); });  // not libFuzzer's: no crash-* file
    ::dup2(report_fd, STDERR_FILENO);
    try {
        g_parse(bytes);
    } catch (...) {
        // an InputError is the expected outcome; anything else the in-process parse reports
    }
    ::_exit(0);
}

ChildResult zygote_run(const std::string& bytes) {
    ChildResult r;
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) ::_exit(98);
    const pid_t pid = ::fork();
    if (pid < 0) ::_exit(98);
    if (pid == 0) {
        ::close(fds[0]);
        child_parse(bytes, fds[1]);
    }
    ::close(fds[1]);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(kChildSeconds);
    for (;;) {
        pollfd p{fds[0], POLLIN, 0};
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        const int ready = ::poll(&p, 1, r.hung ? 5000 : std::max<int>(0, static_cast<int>(left.count())));
        if (ready == 0) {
            if (r.hung) break;
            ::kill(pid, SIGABRT);  // ASan (handle_abort=1) prints where the child hangs
            r.hung = 1;
            continue;
        }
        if (ready < 0) {
            if (errno == EINTR) continue;
            break;
        }
        char buffer[4096];
        const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        r.report.append(buffer, static_cast<size_t>(n));
    }
    ::close(fds[0]);
    ::kill(pid, SIGKILL);  // no-op unless it still hangs
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    r.status = status;
    return r;
}

int g_to_zygote = -1, g_from_zygote = -1;

[[noreturn]] void zygote_loop(int in, int out) {
    for (;;) {
        uint64_t size = 0;
        if (!read_all(in, &size, sizeof size)) ::_exit(0);  // the fuzzer is gone
        std::string bytes(size, '\0');
        if (!read_all(in, bytes.data(), bytes.size())) ::_exit(0);
        const ChildResult r = zygote_run(bytes);
        const uint64_t length = r.report.size();
        if (!write_all(out, &r.status, sizeof r.status) || !write_all(out, &r.hung, sizeof r.hung) ||
            !write_all(out, &length, sizeof length) || !write_all(out, r.report.data(), r.report.size()))
            ::_exit(0);
    }
}

}  // namespace

void start_zygote(ParseFunction parse) {
    g_parse = parse;
    int request[2], reply[2];
    if (::pipe2(request, O_CLOEXEC) != 0 || ::pipe2(reply, O_CLOEXEC) != 0) fail("pipe failed");
    H5open();  // initialise HDF5 once, in the zygote's image
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid < 0) fail("fork failed");
    if (pid == 0) {
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);
        ::close(request[1]);
        ::close(reply[0]);
        zygote_loop(request[0], reply[1]);
    }
    ::close(request[0]);
    ::close(reply[1]);
    g_to_zygote = request[1];
    g_from_zygote = reply[0];
}

namespace {

// True if `report` says nothing but that malloc() returned NULL for a huge request
// (allocator_may_return_null=1, as under `ulimit -v`: HDF5 asks for sizes read from the
// file and fails cleanly when it gets NULL). A child that exited normally after that is fine.
bool only_allocation_warnings(const std::string& report) {
    size_t start = 0;
    while (start < report.size()) {
        size_t end = report.find('\n', start);
        if (end == std::string::npos) end = report.size();
        const std::string line = report.substr(start, end - start);
        if (!line.empty() && line.find("WARNING: AddressSanitizer failed to allocate") == std::string::npos)
            return false;
        start = end + 1;
    }
    return true;
}

}  // namespace

bool survives_in_child(const std::string& bytes) {
    const uint64_t size = bytes.size();
    ChildResult r;
    uint64_t length = 0;
    if (!write_all(g_to_zygote, &size, sizeof size) || !write_all(g_to_zygote, bytes.data(), bytes.size()) ||
        !read_all(g_from_zygote, &r.status, sizeof r.status) || !read_all(g_from_zygote, &r.hung, sizeof r.hung) ||
        !read_all(g_from_zygote, &length, sizeof length))
        fail("the zygote process died");
    r.report.resize(length);
    if (!read_all(g_from_zygote, r.report.data(), r.report.size())) fail("the zygote process died");
    if (!r.hung && WIFEXITED(r.status) && WEXITSTATUS(r.status) == 0 && only_allocation_warnings(r.report))
        return true;
    const std::string frame = culprit_frame(r.report);
    if (frame.find("libhdf5") != std::string::npos) {
        std::fprintf(stderr, "HDF5 crash skipped (%s): %s\n", r.hung ? "hang" : "crash",
                     frame.substr(frame.find_first_not_of(' ')).c_str());
        save_hdf5_crash(bytes);
        return false;
    }
    std::fprintf(stderr, "---- report of the child process that parsed the input ----\n%s\n----\n", r.report.c_str());
    fail(r.hung ? "the reader hangs (not in HDF5)" : "the reader crashed (not in HDF5)", frame);
}

}  // namespace bpm_fuzz
