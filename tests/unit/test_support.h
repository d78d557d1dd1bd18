#pragma once
// Small helpers shared by the unit tests.

#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "bpm/check.h"
#include "bpm/parametrization.h"
#include "bpm/simplify.h"
#include "bpm/surface_io.h"

namespace bpm::test_support {

// A check result with its problems, for INFO().
inline std::string check_text(const CheckResult& r) {
    std::string s = r.name + (r.passed ? " passed" : " failed") + ": " + r.summary;
    for (const auto& p : r.problems) s += "\n  " + p.describe();
    return s;
}

// The parametrization passes the format, bijectivity and topology checks.
inline void require_valid_parametrization(const Parametrization& p) {
    const CheckResult format = check_format(p);
    INFO(check_text(format));
    REQUIRE(format.passed);
    const CheckResult bijective = check_bijectivity(p);
    INFO(check_text(bijective));
    CHECK(bijective.passed);
    const CheckResult topology = check_topology(p);
    INFO(check_text(topology));
    CHECK(topology.passed);
}

// Is the tetgen executable on PATH? (Debian package `tetgen`, installed by scripts/setup.sh)
inline bool have_tetgen() {
    static const bool found = std::system("command -v tetgen >/dev/null 2>&1") == 0;
    return found;
}

// femur.off of .data/meshes simplified to 10% (once per test run, shared by the tests);
// nullptr if the mesh is missing.
inline const Parametrization* simplified_femur() {
    static bool done = false;
    static Parametrization p;
    if (!done) {
        done = true;
        const std::string path = std::string(BPM_MESH_DIR) + "/femur.off";
        if (std::filesystem::exists(path)) {
            SimplifyOptions options;
            options.target_ratio = 0.1;
            simplify(read_surface(path), options, Context{}, p);
        }
    }
    return p.coarse.num_triangles() > 0 ? &p : nullptr;
}

// A fresh directory bpm_NAME_PID under the system's temporary directory for a test's
// files, removed with its contents when it goes out of scope (each test case runs in its
// own process under ctest, so the pid keeps parallel tests apart).
struct ScratchDir {
    std::filesystem::path path;
    explicit ScratchDir(const std::string& name)
        : path(std::filesystem::temp_directory_path() / ("bpm_" + name + "_" + std::to_string(::getpid()))) {
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~ScratchDir() {
        std::error_code ignored;  // a destructor must not throw
        std::filesystem::remove_all(path, ignored);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    std::string file(const std::string& name) const { return (path / name).string(); }
};

// Runs a shell command; returns its exit status (-1 if it did not exit normally) and its
// standard output in `output`.
inline int run_command(const std::string& command, std::string& output) {
    output.clear();
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return -1;
    char buffer[4096];
    size_t n;
    while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
    const int status = pclose(pipe);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The line (1-based) of a text file's first occurrence of `marker`, for expected messages.
inline int line_of(const std::string& bytes, const std::string& marker) {
    const size_t at = bytes.find(marker);
    REQUIRE(at != std::string::npos);
    return 1 + static_cast<int>(std::count(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

}  // namespace bpm::test_support

// Skips the current test case, saying why, when tetgen is missing.
#define REQUIRE_TETGEN()                                                                       \
    do {                                                                                       \
        if (!bpm::test_support::have_tetgen()) {                                               \
            WARN("SKIPPED: the tetgen executable (Debian package 'tetgen') is not on PATH"); \
            return;                                                                            \
        }                                                                                      \
    } while (0)
