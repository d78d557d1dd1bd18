// bpm-bench-repair: the cost of bpm::repair_boundary (bpm/boundary_repair.h) on a refined
// tetrahedral mesh, for bench/repair.sh (bench/README.md). Prints one JSON object.
//
//   bpm-bench-repair FILE.bpm --levels K [--mode flat|solver] [--repeat R]
//
// FILE.bpm must hold a tet mesh (bpm-mesh). The mesh is red-refined K times without phi
// (refine_tetmesh with move_to_surface = false and no smoothing: every new boundary vertex
// at its edge midpoint, as a solver's own refinement leaves it), then repair_boundary with
// its default options is timed R times, each time on a fresh copy of the refined vertices
// (the call moves them). Mode "flat": all K levels flat, one repair at the end (every
// boundary vertex created by the K levels moves at once). Mode "solver": what a solver
// does after each adapt step: levels 1..K-1 each refined flat and repaired (not timed),
// then level K refined flat and the timed repair runs on it. Reported per run: process
// CPU seconds (all threads; the call is single-threaded) and wall seconds; the median of
// each, and the median wall seconds spent in interior smoothing; and the repair's own
// report (held back, distances, minimum dihedral angle, inverted tetrahedra) from the
// first run (every run gives the same result).

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "bpm/boundary_repair.h"
#include "bpm/bpm_file.h"
#include "bpm/phi_evaluation.h"
#include "bpm/tet_refine.h"

namespace {

using namespace bpm;

double cpu_now() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

std::string num(double v) {
    if (!std::isfinite(v)) return "null";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n == 0 ? 0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int usage() {
    std::cerr << "usage: bpm-bench-repair FILE.bpm --levels K [--mode flat|solver] [--repeat R]\n";
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    std::string path, mode = "flat";
    int levels = -1, repeat = 3;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--levels" && i + 1 < argc) levels = std::atoi(argv[++i]);
        else if (a == "--mode" && i + 1 < argc) mode = argv[++i];
        else if (a == "--repeat" && i + 1 < argc) repeat = std::atoi(argv[++i]);
        else if (!a.empty() && a[0] != '-' && path.empty()) path = a;
        else return usage();
    }
    if (path.empty() || levels < 1 || repeat < 1 || (mode != "flat" && mode != "solver")) return usage();
    try {
        BpmFile file = read_bpm(path);
        if (!file.tetmesh) {
            std::cerr << "bpm-bench-repair: " << path << " has no tet mesh\n";
            return 3;
        }
        const PhiEvaluator phi(file.param);
        TetRefineOptions flat;
        flat.move_to_surface = false;
        flat.repair.smooth = false;
        TetMesh mesh = *file.tetmesh;
        const auto prepare_start = std::chrono::steady_clock::now();
        if (mode == "flat") {
            flat.levels = levels;
            TetMesh fine;
            refine_tetmesh(file.param, mesh, flat, {}, fine);
            mesh = std::move(fine);
        } else {
            flat.levels = 1;
            for (int k = 1; k <= levels; ++k) {
                TetMesh fine;
                refine_tetmesh(file.param, mesh, flat, {}, fine);
                mesh = std::move(fine);
                if (k < levels) repair_boundary(phi, mesh.vertices, mesh.tetrahedra, mesh.vertex_parameter_points);
            }
        }
        const double prepare_seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - prepare_start).count();
        std::vector<double> cpu, wall, smoothing;
        BoundaryRepairResult first;
        for (int r = 0; r < repeat; ++r) {
            std::vector<Vec3> x = mesh.vertices;
            const double c0 = cpu_now();
            const auto w0 = std::chrono::steady_clock::now();
            const BoundaryRepairResult res = repair_boundary(phi, x, mesh.tetrahedra, mesh.vertex_parameter_points);
            wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count());
            cpu.push_back(cpu_now() - c0);
            smoothing.push_back(res.smoothing_seconds);
            if (r == 0) first = res;
        }
        std::string out = "{\"file\": \"" + path + "\", \"mode\": \"" + mode + "\", \"levels\": " +
                          std::to_string(levels) + ", \"vertices\": " + std::to_string(mesh.vertices.size()) +
                          ", \"tetrahedra\": " + std::to_string(mesh.tetrahedra.size()) +
                          ", \"prepare_seconds\": " + num(prepare_seconds) + ", \"cpu_seconds\": [";
        for (size_t i = 0; i < cpu.size(); ++i) out += (i ? ", " : "") + num(cpu[i]);
        out += "], \"wall_seconds\": [";
        for (size_t i = 0; i < wall.size(); ++i) out += (i ? ", " : "") + num(wall[i]);
        out += "], \"cpu_seconds_median\": " + num(median(cpu)) + ", \"wall_seconds_median\": " + num(median(wall)) +
               ", \"smoothing_wall_seconds_median\": " + num(median(smoothing)) +
               ", \"boundary_vertices\": " + std::to_string(first.boundary_vertices) +
               ", \"at_phi_before\": " + std::to_string(first.at_phi_before) +
               ", \"at_phi\": " + std::to_string(first.at_phi) + ", \"held_back\": " + std::to_string(first.held_back) +
               ", \"not_moved\": " + std::to_string(first.not_moved) + ", \"max_distance_relative\": " +
               num(first.max_distance_relative) + ", \"min_phi_fraction\": " + num(first.min_phi_fraction) +
               ", \"smoothed_vertices\": " + std::to_string(first.smoothed_vertices) +
               ", \"min_dihedral_degrees\": " + num(first.min_dihedral_degrees) +
               ", \"inverted_before\": " + std::to_string(first.inverted_before) +
               ", \"inverted_after\": " + std::to_string(first.inverted_after) + "}";
        std::cout << out << std::endl;
    } catch (const std::exception& e) {
        std::cerr << "bpm-bench-repair: error: " << e.what() << "\n";
        return 5;
    }
    return 0;
}
