// libFuzzer target: bpm::read_bpm_from_memory, then everything bpm-check runs on what it
// read, then a write/read round trip.
//
// Properties checked for every input:
//   * read_bpm_from_memory returns or throws bpm::InputError naming the input with a
//     non-empty message (anything else - another exception, a crash, an ASan/UBSan
//     report, a leak, a hang, a huge allocation - is a finding);
//   * every HDF5 identifier it opened is closed again;
//   * on a file that reads, every check (format, original-intersections, intersections,
//     topology, bijectivity, quality, distance, replay) and both report renderers run
//     without throwing: checks report bad data, they never throw on it (bpm/check.h);
//   * a file that reads can be written (write_bpm refuses exactly what read_bpm
//     refuses), the written bytes read back, and writing that again gives the same
//     bytes (determinism).
//
// HDF5 crashes. HDF5 itself (Debian libhdf5 1.10.8, not instrumented) crashes on some
// corrupt files, about one input in a few thousand, or misbehaves in a way ASan sees at
// its libc calls (heap over-reads in strdup, memcpy with size -1; bpm_file.cpp, "HDF5
// crashes"). The tools survive that by parsing in a child process first
// (bpm::set_hdf5_isolation). This target does the same, but keeps the child's sanitizer
// report and classifies it: a report whose innermost frame outside libc and the sanitizer
// runtime is in libhdf5 is HDF5's (the input is skipped, counted on stderr as "HDF5 crash
// skipped", and saved to $BPM_FUZZ_HDF5_CRASH_DIR if set); a report anywhere else - our
// reader - is a finding. A child that takes longer than kChildSeconds is sent SIGABRT, so
// that ASan prints where it hangs (scripts/fuzz.sh sets handle_abort=1), and classified
// the same way. Inputs the child parsed without any report are then parsed in-process,
// with coverage, leak checks and everything below.
#include <fcntl.h>
#include <hdf5.h>
#include <poll.h>
#include <sanitizer/common_interface_defs.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include "bpm/bpm_file.h"
#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/tetmesh.h"

namespace {

constexpr int kChildSeconds = 10;

[[noreturn]] void fail(const char* what, const std::string& detail = "") {
    std::fprintf(stderr, "fuzz property violated: %s %s\n", what, detail.c_str());
    std::abort();
}

// Every HDF5 identifier the library opened must be closed again, whatever the input.
void check_nothing_open() {
    const ssize_t open = H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL);
    if (open != 0) fail("HDF5 identifiers left open:", std::to_string(open));
}

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
        (void)bpm::read_bpm_from_memory(bytes, "fuzz-input");
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

void start_zygote() {
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

// Parses `bytes` in a child process. True: the child survived (parse in-process next).
// False: HDF5 crashed or hung on this input (skip it). Aborts (a finding) when the child
// crashed or hung anywhere else.
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

void fuzz_one(const std::string& bytes) {
    static const char* kName = "fuzz-input";
    if (!survives_in_child(bytes)) return;
    bpm::BpmFile file;
    try {
        file = bpm::read_bpm_from_memory(bytes, kName);
    } catch (const bpm::InputError& e) {
        if (e.where() != kName) fail("InputError does not name the input", e.where());
        if (std::string(e.what()).empty()) fail("InputError without a message");
        return;
    }

    bpm::CheckSelection selection;
    selection.original_intersections = true;
    selection.replay = true;  // "not checked" without a /simplification_steps record
    bpm::CheckOptions options;
    options.max_aspect_ratio = 10;
    options.min_angle_degrees = 5;
    options.error_sample_spacing = 0.05;  // coarse sampling: a tiny file may hold huge triangles
    try {
        // Unconditionally: a node image of 8e252 once made check_distance hand an
        // overflowed NaN to GMP (SIGFPE; found by this target); it now refuses such files.
        options.max_error = 0.01;
        bpm::CheckReport report = bpm::run_checks(file, selection, options);
        report.input = kName;
        (void)bpm::check_report_to_json(report);
        (void)bpm::check_report_to_text(report);
        if (file.tetmesh) (void)bpm::tetmesh_stats(*file.tetmesh);
    } catch (const std::exception& e) {
        fail("a check threw on a file read_bpm accepted:", e.what());
    }

    std::string written;
    try {
        written = bpm::write_bpm_to_memory(file);
    } catch (const std::exception& e) {
        fail("write_bpm refused a file read_bpm accepted:", e.what());
    }
    try {
        const bpm::BpmFile again = bpm::read_bpm_from_memory(written, "round-trip");
        if (bpm::write_bpm_to_memory(again) != written) fail("writing is not deterministic across a round trip");
    } catch (const bpm::Error& e) {
        fail("the written file does not read back:", e.what());
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    start_zygote();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fuzz_one(std::string(reinterpret_cast<const char*>(data), size));
    check_nothing_open();
    return 0;
}
