// bpm-eval (test-only): evaluates phi of a .bpm file at a list of points, so that tests
// in other languages can compare their own evaluation with libbpm's.
//
//   bpm-eval [--binary] [--bench] FILE.bpm QUERIES [OUTPUT]
//
// QUERIES ("-" = stdin), one query per point (coarse triangle t, barycentric b0 b1 b2):
//   text:    lines "t b0 b1 b2"; blank lines and lines starting with '#' are skipped
//   binary:  packed little-endian records {int32 t; float64 b0, b1, b2} (28 bytes)
// OUTPUT ("-" or absent = stdout), one result per query, same order:
//   text:    "x y z original_triangle beta0 beta1 beta2 nx ny nz" with 17 significant digits
//   binary:  packed records {float64 x, y, z; int32 original_triangle;
//            float64 beta0, beta1, beta2; float64 nx, ny, nz} (76 bytes)
// --bench repeats the evaluation and reports evaluations per second on stderr.
// Exit codes: 0 ok, 2 usage, 3 input error, 4 output error.

#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/errors.h"
#include "bpm/phi_evaluation.h"
#include "../../libbpm/src/core/file_util.h"

namespace {

int usage() {
    std::fprintf(stderr, "usage: bpm-eval [--binary] [--bench] FILE.bpm QUERIES [OUTPUT]\n");
    return 2;
}

void put(std::string& out, const void* p, size_t n) { out.append(static_cast<const char*>(p), n); }

}  // namespace

int main(int argc, char** argv) {
    bool binary = false, bench = false;
    std::vector<std::string> args;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--binary") binary = true;
        else if (a == "--bench") bench = true;
        else if (a == "--help") {
            std::printf("usage: bpm-eval [--binary] [--bench] FILE.bpm QUERIES [OUTPUT]\n");
            return 0;
        } else if (a.size() > 1 && a[0] == '-' && a != "-")
            return usage();
        else
            args.push_back(a);
    }
    if (args.size() < 2 || args.size() > 3) return usage();
    const std::string output = args.size() == 3 ? args[2] : "-";
    try {
        const bpm::BpmFile file = bpm::read_bpm(args[0]);
        const bpm::Parametrization& p = file.param;
        const std::string raw = bpm::detail::read_whole_input(args[1]);
        std::vector<int32_t> tris;
        std::vector<bpm::Vec3> bs;
        const std::string qname = bpm::detail::display_name(args[1]);
        if (binary) {
            if (raw.size() % 28 != 0) throw bpm::InputError(qname, "size is not a multiple of 28 bytes");
            const size_t n = raw.size() / 28;
            tris.resize(n);
            bs.resize(n);
            for (size_t i = 0; i < n; ++i) {
                std::memcpy(&tris[i], raw.data() + 28 * i, 4);
                std::memcpy(bs[i].data(), raw.data() + 28 * i + 4, 24);
            }
        } else {
            std::istringstream in(raw);
            std::string line;
            size_t lineno = 0;
            while (std::getline(in, line)) {
                ++lineno;
                if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
                std::istringstream ls(line);
                int64_t t;
                bpm::Vec3 b;
                if (!(ls >> t >> b[0] >> b[1] >> b[2]))
                    throw bpm::InputError(qname, "line " + std::to_string(lineno) + ": expected 't b0 b1 b2'");
                tris.push_back(static_cast<int32_t>(t));
                bs.push_back(b);
            }
        }
        for (size_t i = 0; i < tris.size(); ++i)
            if (tris[i] < 0 || tris[i] >= p.num_coarse_triangles())
                throw bpm::InputError(qname, "query " + std::to_string(i) + ": coarse triangle " +
                                                 std::to_string(tris[i]) + " out of range");

        const auto t0 = std::chrono::steady_clock::now();
        bpm::PhiEvaluator eval(p);
        const auto t1 = std::chrono::steady_clock::now();
        std::vector<bpm::PhiSample> out;
        eval.evaluate(tris, bs, out);
        if (bench) {
            // CPU time of this process, so that other jobs on a shared machine do not
            // count against the throughput.
            const auto cpu_seconds = [] {
                timespec ts{};
                clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
                return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
            };
            int reps = 0;
            const double s0 = cpu_seconds();
            double seconds = 0;
            do {
                eval.evaluate(tris, bs, out);
                ++reps;
                seconds = cpu_seconds() - s0;
            } while (seconds < 2.0);
            std::fprintf(stderr,
                         "bpm-eval: %d coarse triangles, %lld pieces (%.1f per coarse triangle); "
                         "setup %.3f s; %.2f million evaluations/s single-threaded\n",
                         p.num_coarse_triangles(), static_cast<long long>(p.num_pieces()),
                         double(p.num_pieces()) / std::max(1, p.num_coarse_triangles()),
                         std::chrono::duration<double>(t1 - t0).count(),
                         double(tris.size()) * reps / seconds / 1e6);
        }

        std::string bytes;
        if (binary) {
            bytes.reserve(out.size() * 76);
            for (const auto& r : out) {
                put(bytes, r.position.data(), 24);
                put(bytes, &r.original_triangle, 4);
                put(bytes, r.original_barycentric.data(), 24);
                put(bytes, r.normal.data(), 24);
            }
        } else {
            char line[512];
            for (const auto& r : out) {
                std::snprintf(line, sizeof line, "%.17g %.17g %.17g %d %.17g %.17g %.17g %.17g %.17g %.17g\n",
                              r.position[0], r.position[1], r.position[2], r.original_triangle,
                              r.original_barycentric[0], r.original_barycentric[1], r.original_barycentric[2],
                              r.normal[0], r.normal[1], r.normal[2]);
                bytes += line;
            }
        }
        bpm::detail::write_file_atomically(output, bytes);
    } catch (const bpm::InputError& e) {
        std::fprintf(stderr, "bpm-eval: error: %s: %s\n", e.where().c_str(), e.what());
        return 3;
    } catch (const bpm::OutputError& e) {
        std::fprintf(stderr, "bpm-eval: error: %s: %s\n", e.where().c_str(), e.what());
        return 4;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bpm-eval: error: %s\n", e.what());
        return 5;
    }
    return 0;
}
