// bpm-bench-cgal-decimate: CGAL's edge-collapse simplification (Surface_mesh_simplification
// on a Surface_mesh, default Lindstrom-Turk cost and placement) down to a target vertex
// count. A plain decimation without a parametrization: the reference column of
// bench/run.py's simplify suite for the quality and speed of a tool that does less than
// bpm-simplify (no phi, no bijectivity, no intersection test).
//
//   bpm-bench-cgal-decimate INPUT -o OUTPUT.off (--vertices N | --ratio R) [--json]
//
// INPUT: any polygon-mesh format CGAL reads by extension (OFF, OBJ, PLY, STL); it must be a
// valid triangulated 2-manifold (with or without boundary). OUTPUT is written as OFF with 17
// significant digits, through a temporary file renamed at the end (never half a file).
// A one-line summary goes to standard error; --json prints it as JSON on standard output.
// Not reaching the target (every remaining edge rejected by the link condition or by the
// placement) is a warning, not an error: the output has the vertices that are left.
//
// Exit codes as for the bpm tools: 0 ok, 2 usage, 3 unreadable or unsuitable input,
// 4 output not written, 70 internal error.
//
// Lindstrom & Turk, "Fast and memory efficient polygonal simplification", IEEE
// Visualization 1998; CGAL manual, "Triangulated Surface Mesh Simplification".
#include <chrono>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/boost/graph/helpers.h>

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;

constexpr int kOk = 0, kUsage = 2, kInput = 3, kOutput = 4, kInternal = 70;

// Stops the edge collapse once the mesh has at most `target` vertices. Each collapse
// removes exactly one vertex, so the run ends exactly at the target when it can.
class VertexCountStop {
public:
    explicit VertexCountStop(std::size_t target) : target_(target) {}
    template <typename Cost, typename Profile>
    bool operator()(const Cost&, const Profile& profile, std::size_t, std::size_t) const {
        return profile.surface_mesh().number_of_vertices() <= target_;
    }

private:
    std::size_t target_;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string json_string(const std::string& s) {
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

int fail(int code, const std::string& where, const std::string& message) {
    std::cerr << "bpm-bench-cgal-decimate: error: " << where << ": " << message << "\n";
    return code;
}

int run(int argc, char** argv) {
    CLI::App app{"CGAL edge-collapse decimation (Lindstrom-Turk) to a target vertex count; a plain decimation "
                 "without a parametrization, the reference of bench/run.py's simplify suite."};
    std::string input, output;
    long long vertices = 0;
    double ratio = 0.0;
    bool json = false;
    app.add_option("INPUT", input, "Input surface (OFF, OBJ, PLY, STL): a triangulated 2-manifold")->required();
    app.add_option("-o,--output", output, "Output OFF file")->required();
    auto* v_opt = app.add_option("--vertices", vertices, "Target number of vertices")->check(CLI::PositiveNumber);
    auto* r_opt = app.add_option("--ratio", ratio, "Target as a fraction of the input vertices")
                      ->check(CLI::Range(0.0, 1.0));
    v_opt->excludes(r_opt);
    app.add_flag("--json", json, "Print the summary as JSON on standard output");
    try {
        app.parse(argc, argv);
        if (!v_opt->count() && !r_opt->count()) throw CLI::RequiredError("--vertices or --ratio");
        if (r_opt->count() && !(ratio > 0.0)) throw CLI::ValidationError("--ratio", "must be in (0, 1]");
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        app.exit(e);
        return kUsage;
    }

    const auto t_start = std::chrono::steady_clock::now();
    Mesh mesh;
    if (!CGAL::IO::read_polygon_mesh(input, mesh))
        return fail(kInput, input, "unreadable, or not a 2-manifold polygon mesh CGAL can build");
    if (mesh.number_of_faces() == 0) return fail(kInput, input, "no faces");
    if (!CGAL::is_triangle_mesh(mesh)) return fail(kInput, input, "not a triangle mesh (triangulate it first)");
    const double read_seconds = seconds_since(t_start);
    const std::size_t input_vertices = mesh.number_of_vertices();
    const std::size_t input_faces = mesh.number_of_faces();
    const std::size_t target = v_opt->count() ? static_cast<std::size_t>(vertices)
                                              : static_cast<std::size_t>(ratio * double(input_vertices) + 0.5);

    const auto t_simplify = std::chrono::steady_clock::now();
    const int edges_removed = CGAL::Surface_mesh_simplification::edge_collapse(mesh, VertexCountStop(target));
    const double simplify_seconds = seconds_since(t_simplify);
    mesh.collect_garbage();

    const auto t_write = std::chrono::steady_clock::now();
    const std::string tmp = output + ".tmp";
    if (!CGAL::IO::write_OFF(tmp, mesh, CGAL::parameters::stream_precision(17))) {
        std::remove(tmp.c_str());
        return fail(kOutput, output, "cannot write");
    }
    if (std::rename(tmp.c_str(), output.c_str()) != 0) {
        std::remove(tmp.c_str());
        return fail(kOutput, output, "cannot rename the temporary file into place");
    }
    const double write_seconds = seconds_since(t_write);
    const double total_seconds = seconds_since(t_start);

    const std::size_t out_vertices = mesh.number_of_vertices(), out_faces = mesh.number_of_faces();
    if (out_vertices > target)
        std::cerr << "bpm-bench-cgal-decimate: warning: stopped at " << out_vertices << " vertices, target " << target
                  << " (no admissible edge collapse left)\n";
    std::fprintf(stderr, "%s: %zu -> %zu vertices, %zu -> %zu triangles, %d edges removed, %.3f s simplify, %.3f s total\n",
                 input.c_str(), input_vertices, out_vertices, input_faces, out_faces, edges_removed, simplify_seconds,
                 total_seconds);
    if (json) {
        std::printf("{\"input\": %s, \"output\": %s, \"policy\": \"Lindstrom-Turk cost and placement (CGAL defaults)\", "
                    "\"input_vertices\": %zu, \"input_triangles\": %zu, \"target_vertices\": %zu, "
                    "\"vertices\": %zu, \"triangles\": %zu, \"edges_removed\": %d, "
                    "\"seconds\": {\"read\": %.6f, \"simplify\": %.6f, \"write\": %.6f, \"total\": %.6f}}\n",
                    json_string(input).c_str(), json_string(output).c_str(), input_vertices, input_faces, target,
                    out_vertices, out_faces, edges_removed, read_seconds, simplify_seconds, write_seconds, total_seconds);
    }
    return kOk;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const std::bad_alloc&) {
        return fail(kInternal, "memory", "out of memory");
    } catch (const std::exception& e) {
        return fail(kInternal, "internal error", e.what());
    }
}
