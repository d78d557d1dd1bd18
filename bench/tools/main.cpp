// bpm-bench-metrics: compares a coarse surface with the original one and prints JSON
// (bench/README.md lists every field). Inputs: ORIGINAL COARSE, each any surface format
// read_surface reads, COARSE also a psurface .vtu or a .bpm (its /coarse); or one .bpm
// file alone (its /original and /coarse).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/surface_io.h"
#include "bpm/surface_topology.h"
#include "common/tool_main.h"
#include "metrics.h"

namespace {

using namespace bpm;

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A number as JSON: 17 significant digits; NaN/Inf (which JSON lacks) as null.
std::string num(double v) {
    if (!std::isfinite(v)) return "null";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}
std::string num(int64_t v) { return std::to_string(v); }
std::string str(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\', out += c;
        else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
        } else out += c;
    }
    return out + "\"";
}

struct Loaded {
    Surface surface;
    std::string source;  // "surface", "vtu", "bpm:/coarse", "bpm:/original"
    int64_t dropped_vertices = 0;
};

Loaded load(const std::string& path, bool coarse_of_bpm) {
    Loaded l;
    if (ends_with(path, ".vtu")) {
        l.surface = bench::read_vtu(path, &l.dropped_vertices);
        l.source = "vtu";
    } else if (ends_with(path, ".bpm")) {
        BpmFile f = read_bpm(path);
        l.surface = coarse_of_bpm ? std::move(f.param.coarse) : std::move(f.param.original);
        l.source = coarse_of_bpm ? "bpm:/coarse" : "bpm:/original";
    } else {
        SurfaceReadOptions options;
        options.drop_unreferenced_vertices = coarse_of_bpm;  // tolerated in results, not in inputs
        SurfaceReadReport report;
        l.surface = read_surface(path, options, &report);
        l.dropped_vertices = report.dropped_vertices;
        l.source = "surface";
    }
    return l;
}

std::string quality_json(const Surface& s) {
    double max = 0.0, sum = 0.0;
    int64_t finite = 0, degenerate = 0;
    for (const Tri& t : s.triangles) {
        const double a = aspect_ratio(s.vertices[t[0]], s.vertices[t[1]], s.vertices[t[2]]);
        if (!std::isfinite(a)) {
            ++degenerate;
            continue;
        }
        max = std::max(max, a);
        sum += a;
        ++finite;
    }
    std::ostringstream o;
    o << "{\"max\": " << num(degenerate > 0 ? std::numeric_limits<double>::infinity() : max)
      << ", \"max_finite\": " << num(max) << ", \"mean\": " << num(finite > 0 ? sum / static_cast<double>(finite) : 0.0)
      << ", \"degenerate\": " << degenerate << "}";
    return o.str();
}

std::string topology_json(const SurfaceTopology& t) {
    std::ostringstream o;
    o << "{\"components\": " << t.components.size() << ", \"euler_characteristic\": " << t.euler_characteristic
      << ", \"betti\": [" << t.betti0 << ", " << t.betti1 << ", " << t.betti2 << "]"
      << ", \"boundary_loops\": " << t.boundary_loops << ", \"orientable\": " << (t.orientable ? "true" : "false")
      << ", \"manifold\": " << (t.manifold ? "true" : "false") << ", \"feature_lines\": " << t.feature_lines.size()
      << ", \"summary\": " << str(describe_topology(t)) << "}";
    return o.str();
}

std::string one_sided_json(const bench::OneSidedDistance& d, double diagonal) {
    const double scale = diagonal > 0.0 ? 1.0 / diagonal : 0.0;
    std::ostringstream o;
    o << "{\"samples\": " << d.samples << ", \"max\": " << num(d.max) << ", \"mean\": " << num(d.mean)
      << ", \"rms\": " << num(d.rms) << ", \"max_relative\": " << num(d.max * scale)
      << ", \"mean_relative\": " << num(d.mean * scale) << ", \"rms_relative\": " << num(d.rms * scale)
      << ", \"max_at\": [" << num(d.max_at[0]) << ", " << num(d.max_at[1]) << ", " << num(d.max_at[2]) << "]}";
    return o.str();
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
    const std::string tool = "bpm-bench-metrics";
    CLI::App app{
        "Compares a coarse surface with the original one and prints JSON: counts, sampled two-sided\n"
        "(Hausdorff) distance relative to the original's bounding-box diagonal, triangle aspect ratio R/r,\n"
        "self-intersecting triangle pairs of the coarse surface, topological invariants of both.\n"
        "Samples on each surface: all vertices, all edge midpoints and max(K, round(N * area share))\n"
        "uniform random points per triangle (N = --samples, K = --min-per-triangle), each measured\n"
        "against the other surface with closest-point queries in a CGAL AABB tree.",
        tool};
    std::string first, second, output = "-";
    bench::SamplingOptions sampling;
    bool skip_intersections = false;
    app.add_option("ORIGINAL", first, "Original surface (.off .obj .stl .ply .msh), or a .bpm file alone")->required();
    app.add_option("COARSE", second, "Coarse surface: any of the above, a psurface .vtu, or a .bpm (its /coarse)");
    app.add_option("-o,--output", output, "Write the JSON here instead of standard output");
    app.add_option("--samples", sampling.area_samples, "Area-proportional random samples per surface (N)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    app.add_option("--min-per-triangle", sampling.min_per_triangle, "Random samples at least per triangle (K)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    app.add_option("--seed", sampling.seed, "Seed of the sample generator")->capture_default_str();
    app.add_flag("--no-intersections", skip_intersections, "Do not count self-intersecting pairs of the coarse surface");
    tools::add_version_flag(app, tool);

    return tools::run(tool, argc, argv, app, [&]() {
        const auto t_start = std::chrono::steady_clock::now();
        Loaded original, coarse;
        std::string original_name = first, coarse_name = second;
        if (second.empty()) {
            if (!ends_with(first, ".bpm")) throw CLI::ValidationError("COARSE", "needed unless ORIGINAL is a .bpm file");
            BpmFile f = read_bpm(first);
            original.surface = std::move(f.param.original);
            original.source = "bpm:/original";
            coarse.surface = std::move(f.param.coarse);
            coarse.source = "bpm:/coarse";
            coarse_name = first;
        } else {
            original = load(first, false);
            coarse = load(second, true);
        }
        const double load_seconds = seconds_since(t_start);

        const double diagonal = bounding_box_diagonal(original.surface);
        auto t0 = std::chrono::steady_clock::now();
        const bench::DistanceReport distance = bench::compute_distances(original.surface, coarse.surface, sampling);
        const double distance_seconds = seconds_since(t0);

        t0 = std::chrono::steady_clock::now();
        const SurfaceTopology topo_original = compute_topology(original.surface);
        const SurfaceTopology topo_coarse = compute_topology(coarse.surface);
        const std::vector<std::string> differences = compare_topology(topo_original, topo_coarse, {}, 10);
        const double topology_seconds = seconds_since(t0);

        int64_t intersecting = -1, degenerate = -1;
        double intersection_seconds = 0.0;
        if (!skip_intersections) {
            t0 = std::chrono::steady_clock::now();
            CheckOptions options;
            options.max_problems = 1;
            const CheckResult r = check_intersections(coarse.surface, options);
            intersecting = r.count("intersecting_pairs");
            degenerate = r.count("degenerate_triangles");
            intersection_seconds = seconds_since(t0);
        }

        std::ostringstream o;
        o << "{\n";
        o << "  \"original\": {\"file\": " << str(original_name) << ", \"source\": " << str(original.source)
          << ", \"vertices\": " << original.surface.num_vertices() << ", \"triangles\": " << original.surface.num_triangles()
          << ", \"bbox_diagonal\": " << num(diagonal) << ",\n    \"aspect_ratio\": " << quality_json(original.surface)
          << ",\n    \"topology\": " << topology_json(topo_original) << "},\n";
        o << "  \"coarse\": {\"file\": " << str(coarse_name) << ", \"source\": " << str(coarse.source)
          << ", \"vertices\": " << coarse.surface.num_vertices() << ", \"triangles\": " << coarse.surface.num_triangles()
          << ", \"dropped_unreferenced_vertices\": " << coarse.dropped_vertices
          << ",\n    \"aspect_ratio\": " << quality_json(coarse.surface)
          << ",\n    \"self_intersecting_pairs\": " << (intersecting < 0 ? "null" : num(intersecting))
          << ", \"degenerate_triangles\": " << (degenerate < 0 ? "null" : num(degenerate))
          << ",\n    \"topology\": " << topology_json(topo_coarse) << "},\n";
        o << "  \"topology_preserved\": " << (differences.empty() ? "true" : "false") << ", \"topology_differences\": [";
        for (size_t i = 0; i < differences.size(); ++i) o << (i ? ", " : "") << str(differences[i]);
        o << "],\n";
        o << "  \"distance\": {\n    \"sampling\": {\"area_samples\": " << sampling.area_samples
          << ", \"min_per_triangle\": " << sampling.min_per_triangle << ", \"seed\": " << sampling.seed
          << ", \"method\": \"all vertices + all edge midpoints + max(K, round(N*area share)) uniform random points per "
             "triangle; closest point on the other surface by CGAL AABB tree\"},\n";
        o << "    \"hausdorff\": " << num(distance.hausdorff)
          << ", \"hausdorff_relative\": " << num(diagonal > 0.0 ? distance.hausdorff / diagonal : 0.0)
          << ", \"mean_two_sided_relative\": "
          << num(diagonal > 0.0 ? 0.5 * (distance.original_to_coarse.mean + distance.coarse_to_original.mean) / diagonal : 0.0)
          << ",\n    \"original_to_coarse\": " << one_sided_json(distance.original_to_coarse, diagonal)
          << ",\n    \"coarse_to_original\": " << one_sided_json(distance.coarse_to_original, diagonal) << "},\n";
        o << "  \"seconds\": {\"load\": " << num(load_seconds) << ", \"distance\": " << num(distance_seconds)
          << ", \"topology\": " << num(topology_seconds) << ", \"intersections\": " << num(intersection_seconds) << "}\n";
        o << "}\n";

        if (output == "-") {
            std::cout << o.str();
        } else {
            FILE* f = std::fopen(output.c_str(), "wb");
            if (!f) throw OutputError(output, "cannot open for writing");
            const std::string text = o.str();
            const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
            if (std::fclose(f) != 0 || !ok) throw OutputError(output, "write failed");
        }
        return tools::kOk;
    });
}
