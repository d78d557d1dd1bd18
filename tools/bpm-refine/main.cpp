// bpm-refine: refine the coarse surface of a .bpm file through phi (new vertices on S0).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/geometry.h"
#include "bpm/refine.h"
#include "bpm/tet_refine.h"
#include "bpm/tetmesh.h"
#include "bpm/write_tetmesh.h"
#include "bpm/write_vtu.h"
#include "bpm/surface_io.h"
#include "common/tool_main.h"

namespace {

std::string extension_of(const std::string& path) {
    const auto dot = path.find_last_of('.');
    if (dot == std::string::npos || path.find_last_of('/') != std::string::npos && dot < path.find_last_of('/'))
        return "";
    std::string e = path.substr(dot + 1);
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

// A number as JSON (17 significant digits; null for NaN / infinity, which JSON lacks).
std::string json_double(double v) {
    if (!std::isfinite(v)) return "null";
    return bpm::tools::round_trip_text(v);
}

// A refined triangle whose proven bound is above --max-error, and where it is.
struct Unmet {
    int64_t triangle = 0;
    int32_t coarse_triangle = 0, level = 0;
    double bound = 0;
    bpm::Vec3 at{0, 0, 0};  // its centroid
};

// The `count` triangles with the largest bound above `tolerance` (none if tolerance < 0), worst first.
std::vector<Unmet> worst_unmet(const bpm::RefinedSurface& r, double tolerance, size_t count) {
    std::vector<Unmet> out;
    if (tolerance < 0) return out;
    for (size_t t = 0; t < r.triangle_bound.size(); ++t) {
        if (!(r.triangle_bound[t] > tolerance)) continue;
        Unmet u;
        u.triangle = int64_t(t);
        u.coarse_triangle = r.triangle_coarse[t];
        u.level = r.triangle_level[t];
        u.bound = r.triangle_bound[t];
        for (int32_t v : r.surface.triangles[t])
            for (size_t k = 0; k < 3; ++k) u.at[k] += r.surface.vertices[size_t(v)][k] / 3.0;
        out.push_back(u);
    }
    std::sort(out.begin(), out.end(), [](const Unmet& a, const Unmet& b) {
        return a.bound != b.bound ? a.bound > b.bound : a.triangle < b.triangle;
    });
    if (out.size() > count) out.resize(count);
    return out;
}

}  // namespace

namespace {

// Uniform refinements above this many triangles are announced before they start.
constexpr double kLargeRefinement = 2e7;

// --volume: the tetrahedral mesh of the file, refined through phi (bpm/tet_refine.h).
int refine_volume(const std::string& tool, int argc, char** argv, const std::string& input, const std::string& output,
                  const std::string& format, const bpm::tools::EncodingFlags& encoding_flags, int levels, bool smooth,
                  double remedy_min_dihedral, bool deterministic, bool verbose, bool quiet) {
    if (levels < 0) throw CLI::ValidationError("--volume needs --levels");
    const auto out_format = format.empty() ? bpm::tetmesh_format_from_path(output) : bpm::tetmesh_format_from_name(format);
    if (!out_format)
        throw CLI::ValidationError(format.empty() ? "--output" : "--output-format",
                                   (format.empty() ? std::string() : "unknown output format '" + format + "': ") +
                                       "--volume writes bpm msh msh22 vtu mesh (by extension or --output-format)");
    if (*out_format == bpm::TetMeshFormat::Bpm) bpm::tools::refuse_binary_to_terminal(output, "binary .bpm (HDF5) data");
    const bpm::MeshEncoding encoding =
        bpm::tools::output_encoding(encoding_flags, bpm::tetmesh_format_name(*out_format), output);
    const bpm::Context context = bpm::tools::make_context(tool, verbose, quiet);
    bpm::BpmFile file = bpm::tools::read_bpm_input(
        input, "--volume refines the .bpm that bpm-mesh writes: bpm-mesh COARSE.bpm -o TETS.bpm");
    if (!file.tetmesh)
        throw bpm::InputError(input, "has no tetrahedral mesh (make one with bpm-mesh first)");
    bpm::TetRefineOptions options;
    options.levels = levels;
    options.repair.smooth = smooth;
    options.repair.min_dihedral_degrees = remedy_min_dihedral;
    bpm::TetMesh fine;
    const bpm::TetRefineResult r = bpm::refine_tetmesh(file.param, *file.tetmesh, options, context, fine);
    char line[512];
    for (size_t k = 0; k < r.levels.size(); ++k) context.debug(bpm::describe_level(r.levels[k], k + 1));
    std::snprintf(line, sizeof line,
                  "%lld tetrahedra, %lld vertices (%lld on the boundary), %lld kept short of phi to keep elements "
                  "positive and not flat (max distance %.3g of diagonal), %lld inverted, min dihedral angle %.3g "
                  "degrees, %.2f s",
                  (long long)r.tetrahedra, (long long)r.vertices, (long long)r.boundary_vertices,
                  (long long)r.remedied_vertices, r.max_remedy_distance_relative, (long long)r.inverted,
                  r.levels.empty() ? 0.0 : r.levels.back().min_dihedral_degrees, r.seconds);
    context.info(line);
    if (*out_format == bpm::TetMeshFormat::Bpm) {
        file.tetmesh = std::move(fine);
        file.provenance.push_back({tool, bpm::tools::version_line(tool), bpm::tools::command_line(argc, argv),
                                   deterministic ? std::string() : bpm::tools::utc_timestamp()});
        bpm::write_bpm(output, file);
    } else {
        bpm::write_tetmesh(output, fine, *out_format, file.patch_info, encoding);
    }
    return r.inverted == 0 ? int(bpm::tools::kOk) : int(bpm::tools::kAlgorithm);
}

}  // namespace

int main(int argc, char** argv) {
    const std::string tool = "bpm-refine";
    CLI::App app{
        "Refine the coarse surface of a .bpm file: uniformly (--levels K, 4^K triangles per coarse triangle) or\n"
        "adaptively (--max-error E), placing every new vertex at phi of its parameter position, i.e. on the\n"
        "original surface. Output format by extension: .off .obj .ply .stl .msh .vtu, or .bpm (the refined surface\n"
        "with its own phi; see spec/refinement.md).",
        tool};
    std::string input, output, format;
    bpm::RefineOptions options;
    int levels = -1;
    double max_error = 0;
    bool data = false, verbose = false, quiet = false, deterministic = false, no_verify = false, json = false;
    app.add_option("INPUT", input, "Input .bpm file, or - for standard input")->required();
    app.add_option("-o,--output", output, "Output file (.off .obj .ply .stl .msh .vtu .bpm), or - for standard output")
        ->required();
    bpm::tools::add_format_option(app, format, "output",
                                  "Format if the name does not tell (needed for -): off obj ply stl msh msh22 vtu bpm; "
                                  "--volume: bpm msh msh22 vtu mesh");
    bpm::tools::EncodingFlags encoding_flags;
    bpm::tools::add_encoding_options(app, encoding_flags);
    auto* lv = app.add_option("--levels", levels, "Uniform refinement: each coarse triangle into 4^K triangles (0..10)")
                   ->check(CLI::Range(0, 10));
    // --max-error is the quantity bpm-simplify --max-error limits: max |phi(x) - x| over the
    // surface, as a fraction of the diagonal (it was --tolerance, which is bpm-smooth's
    // stopping threshold).
    auto* tol = app.add_option("--max-error", max_error,
                               "Adaptive refinement: split triangles until max |phi(x) - x| is at most this fraction "
                               "of the bounding-box diagonal (e.g. 0.001); on planar faces phi's drift within the "
                               "face is no error and does not count")
                    ->check(CLI::PositiveNumber);
    lv->excludes(tol);
    bpm::tools::add_deprecated_alias(app, "--tolerance", max_error, tol,
                                     "bpm-smooth's --tolerance is its stopping threshold, another quantity")
        ->check(CLI::PositiveNumber);
    // With --levels (and so with --volume) it was accepted and did nothing.
    lv->excludes(app.add_option("--max-level", options.max_level, "Adaptive: at most this many levels (default 10)")
                     ->check(CLI::Range(0, 10)));
    app.add_flag("--data", data,
                 "VTU output: the original's vertex data and normals through phi as point data (and where each "
                 "vertex lies)");
    bool volume = false;
    app.add_flag("--volume", volume,
                 "Refine the file's tetrahedral mesh (from bpm-mesh) --levels times; output .bpm .msh .vtu .mesh");
    bool no_smooth = false;
    app.add_flag("--no-smooth", no_smooth,
                 "Do not smooth the interior vertices after every level (smoothing never inverts or worsens)");
    double remedy_min_dihedral = bpm::TetRefineOptions{}.repair.min_dihedral_degrees;
    auto* remedy = app.add_option("--remedy-min-dihedral", remedy_min_dihedral,
                   "Hold a boundary vertex short of phi rather than bring a dihedral angle below this (degrees; "
                   "default 8)")
        ->check(CLI::Range(0.0, 60.0));
    app.add_flag("--no-verify", no_verify,
                 ".bpm output: skip the checks run before writing (faster)");
    bool allow_intersections = false;
    app.add_flag("--allow-intersections", allow_intersections,
                 "Place every new vertex at phi even where the surface then intersects itself (default: hold back)");
    app.add_flag("--json", json,
                 "Print a JSON report on standard output (counts, the proven bound, held-back vertices, the "
                 "triangles above --max-error)");
    bpm::tools::add_output_tool_flags(app, tool, deterministic, verbose, quiet);
    bpm::tools::group_options(app, "Output",
                              {"--output", "--output-format", "--binary", "--compress", "--data", "--json"});
    bpm::tools::group_options(app, "Target (one of)", {"--levels", "--max-error", "--max-level"});
    bpm::tools::group_options(app, "Volume", {"--volume", "--no-smooth", "--remedy-min-dihedral"});
    bpm::tools::group_options(app, "Advanced", {"--no-verify", "--allow-intersections"});
    bpm::tools::add_examples(app, {"bpm-refine femur.bpm --levels 2 -o fine.vtu --data",
                                   "bpm-refine femur.bpm --max-error 0.001 -o adaptive.off",
                                   "bpm-refine femur.tet.bpm --volume --levels 1 -o fine.msh"});

    // With --json every error is a report too: {"input", "ok": false, "error"}.
    bpm::tools::set_json_error_report(json, [&](const bpm::tools::ErrorReport& error) {
        return "{\"input\": " + bpm::tools::json_string(input) + ", \"ok\": false, \"error\": " +
               bpm::tools::error_json(error) + "}";
    });
    return bpm::tools::run(tool, argc, argv, app, [&]() {
        bpm::tools::set_error_input(input);
        bpm::tools::require_output_directory(output);
        if (json && output == "-") throw CLI::ValidationError("--json", "needs an output file (stdout carries the JSON)");
        if (json && volume) throw CLI::ValidationError("--json", "is not available with --volume yet");
        if (!volume && (no_smooth || remedy->count() > 0))
            throw CLI::ValidationError(no_smooth ? "--no-smooth" : "--remedy-min-dihedral",
                                       "only applies with --volume");
        if (volume)
            return refine_volume(tool, argc, argv, input, output, format, encoding_flags, levels, !no_smooth,
                                 remedy_min_dihedral, deterministic, verbose, quiet);
        if (levels < 0 && max_error <= 0) throw CLI::ValidationError("give one of --levels, --max-error");
        options.levels = levels;
        options.tolerance = max_error;
        options.prevent_intersections = !allow_intersections;
        std::string kind = format.empty() ? extension_of(output) : format;
        std::transform(kind.begin(), kind.end(), kind.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        if (output == "-" && format.empty()) throw CLI::ValidationError("--output-format", "writing to '-' needs --output-format (e.g. --output-format off)");
        const bool is_bpm = kind == "bpm", is_vtu = kind == "vtu";
        const auto surface_format = bpm::surface_format_from_name(kind);
        if (!is_bpm && !is_vtu && (!surface_format || *surface_format == bpm::SurfaceFormat::Vtk ||
                                        *surface_format == bpm::SurfaceFormat::Vtp ||
                                        *surface_format == bpm::SurfaceFormat::Surf ||
                                        *surface_format == bpm::SurfaceFormat::Nifti ||
                                        *surface_format == bpm::SurfaceFormat::Nrrd ||
                                        *surface_format == bpm::SurfaceFormat::MetaImage))
            throw CLI::ValidationError(format.empty() ? "--output" : "--output-format",
                                       (kind.empty() ? "cannot tell the format from '" + output + "' (no extension)"
                                                     : "unknown output format '" + kind + "'") +
                                           " (valid: off obj ply stl msh msh22 vtu bpm, by extension or --output-format)");
        if (is_bpm) bpm::tools::refuse_binary_to_terminal(output, "binary .bpm (HDF5) data");
        if (surface_format && (*surface_format == bpm::SurfaceFormat::Stl || *surface_format == bpm::SurfaceFormat::Ply))
            bpm::tools::refuse_binary_to_terminal(output, "binary " + kind + " data");
        const bpm::MeshEncoding encoding = bpm::tools::output_encoding(encoding_flags, kind, output);
        if (data && !is_vtu) throw CLI::ValidationError("--data", "--data needs .vtu output (the other formats hold no point data)");
        const bpm::Context context = bpm::tools::make_context(tool, verbose, quiet);

        bpm::BpmFile file = bpm::tools::read_bpm_input(input);
        if (file.tetmesh && !is_bpm)
            context.info("refining the surface; the file's tetrahedral mesh is refined with --volume");
        const bpm::Parametrization& param = file.param;
        // Each level quadruples the output: --levels 8 on a few thousand coarse triangles is
        // hundreds of millions of triangles, minutes and gigabytes, with nothing said first.
        if (levels >= 0) {
            const double triangles = double(param.num_coarse_triangles()) * std::pow(4.0, levels);
            if (triangles > kLargeRefinement)
                context.warn("--levels " + std::to_string(levels) + " makes " +
                             bpm::tools::three_digit_text(triangles / 1e6) + " million triangles (" +
                             std::to_string(param.num_coarse_triangles()) + " coarse triangles, 4^" +
                             std::to_string(levels) + " each): this takes a while and several GB; each level "
                             "less is a quarter of it (--max-error E refines only where needed)");
        }
        bpm::RefinedSurface refined;
        const bpm::RefineResult result = bpm::refine(param, options, context, refined);
        char line[512];
        std::snprintf(line, sizeof line,
                      "%lld coarse triangles -> %lld vertices, %lld triangles (level %d), max |flat - phi| %.3g of "
                      "diagonal (exact, over the overlay with phi), %.2f s",
                      (long long)result.coarse_triangles, (long long)result.vertices, (long long)result.triangles,
                      result.max_level, result.max_estimated_error, result.seconds);
        context.info(line);
        if (result.held_back_vertices > 0) {
            std::snprintf(line, sizeof line,
                          "%lld vertices held back from phi (towards their parent edges) so that the refined surface "
                          "does not intersect itself (at most %.3g of diagonal from phi; %d rounds)",
                          (long long)result.held_back_vertices, result.max_held_back, result.remedy_rounds);
            context.info(line);
        }
        std::snprintf(line, sizeof line,
                      "proven two-sided Hausdorff distance to the original surface: at most %.3g of diagonal%s",
                      result.hausdorff_bound,
                      result.held_back_vertices > 0 ? " (with the held-back vertices where they are)" : "");
        context.info(line);
        const std::vector<Unmet> unmet = worst_unmet(refined, levels < 0 ? max_error : -1.0, 10);
        if (result.triangles_above_tolerance > 0) {
            std::snprintf(line, sizeof line,
                          "--max-error %g not met: %lld triangles are above it (%lld of them at --max-level %d), "
                          "the bound is %.3g; the worst:",
                          max_error, (long long)result.triangles_above_tolerance,
                          (long long)result.triangles_at_max_level_above_tolerance, options.max_level,
                          result.hausdorff_bound);
            std::string text = line;
            for (size_t k = 0; k < std::min<size_t>(3, unmet.size()); ++k) {
                const Unmet& u = unmet[k];
                std::snprintf(line, sizeof line, " triangle %lld (coarse triangle %d, level %d, at %.4g %.4g %.4g): %.3g%s",
                              (long long)u.triangle, u.coarse_triangle, u.level, u.at[0], u.at[1], u.at[2], u.bound,
                              k + 1 < std::min<size_t>(3, unmet.size()) ? ";" : "");
                text += line;
            }
            if (result.triangles_at_max_level_above_tolerance > 0 && options.max_level < 10)
                text += " (a higher --max-level, at most 10, may reach it)";
            context.warn(text);
        }

        if (is_bpm) {
            bpm::BpmFile out;
            out.param = bpm::refined_parametrization(param, refined, context);
            out.units = file.units;
            out.coordinate_frame = file.coordinate_frame;
            out.patch_info = file.patch_info;  // refinement keeps patch ids and orientations
            out.provenance = file.provenance;
            out.provenance.push_back({tool, bpm::tools::version_line(tool), bpm::tools::command_line(argc, argv),
                                      deterministic ? std::string() : bpm::tools::utc_timestamp()});
            context.info("refined phi: " + std::to_string(out.param.num_nodes()) + " nodes, " +
                         std::to_string(out.param.num_pieces()) + " pieces; original surface cut into " +
                         std::to_string(out.param.original.num_triangles()) + " triangles");
            if (!no_verify) {
                // Never write a file bpm-check would reject. A failure is a bug of bpm (the
                // input passed its checks): std::logic_error, exit 70, not a property of the input.
                const bpm::CheckResult format = bpm::check_format(out.param);
                std::vector<bpm::CheckResult> results{format};
                if (format.passed) {
                    // (--allow-intersections: the user accepted them)
                    if (!allow_intersections) results.push_back(bpm::check_intersections(out.param.coarse));
                    results.push_back(bpm::check_topology(out.param));
                    results.push_back(bpm::check_bijectivity(out.param));
                }
                for (const bpm::CheckResult& r : results)
                    if (!r.passed)
                        throw std::logic_error("internal error: the refined .bpm failed its " + r.name + " check (" +
                                               (r.problems.empty() ? r.summary : r.problems.front().describe()) +
                                               "); not written");
                context.info(allow_intersections
                                 ? "refined .bpm passed the format, topology and bijectivity checks"
                                 : "refined .bpm passed the format, intersections, topology and bijectivity checks");
            }
            bpm::write_bpm(output, out);
        } else if (is_vtu) {
            std::vector<bpm::VtuArray> point_data, cell_data;
            if (data) {
                const std::vector<bpm::Vec3> n0 = bpm::vertex_normals(param.original);
                std::vector<double> flat;
                for (const auto& n : n0) flat.insert(flat.end(), n.begin(), n.end());
                std::vector<double> n = bpm::transfer_vertex_data(refined, param.original, flat, 3);
                for (size_t v = 0; v + 2 < n.size(); v += 3) {
                    const double l = std::sqrt(n[v] * n[v] + n[v + 1] * n[v + 1] + n[v + 2] * n[v + 2]);
                    if (l > 0) n[v] /= l, n[v + 1] /= l, n[v + 2] /= l;
                }
                point_data.push_back({"original_normal", 3, std::move(n)});
                // The data arrays of the original surface (read from PLY / VTK input), by
                // linear interpolation in the original triangle each vertex lies in.
                for (const bpm::VertexArray& a : param.original.vertex_data)
                    point_data.push_back({a.name == "original_normal" || a.name == "coarse_triangle" ||
                                                  a.name == "coarse_barycentric" || a.name == "original_triangle"
                                              ? a.name + "_data"  // the names bpm-refine uses itself
                                              : a.name,
                                          a.components,
                                          bpm::transfer_vertex_data(refined, param.original, a.values, a.components)});
                bpm::VtuArray tri{"coarse_triangle", 1, {}}, bary{"coarse_barycentric", 3, {}};
                bpm::VtuArray otri{"original_triangle", 1, {}};
                for (size_t v = 0; v < refined.vertex_coarse_triangle.size(); ++v) {
                    tri.values.push_back(refined.vertex_coarse_triangle[v]);
                    otri.values.push_back(refined.vertex_original_triangle[v]);
                    bary.values.insert(bary.values.end(), refined.vertex_barycentric[v].begin(),
                                       refined.vertex_barycentric[v].end());
                }
                point_data.push_back(std::move(tri));
                point_data.push_back(std::move(bary));
                point_data.push_back(std::move(otri));
            }
            bpm::VtuArray ct{"coarse_triangle", 1, {}}, lvl{"level", 1, {}};
            for (size_t t = 0; t < refined.triangle_coarse.size(); ++t) {
                ct.values.push_back(refined.triangle_coarse[t]);
                lvl.values.push_back(refined.triangle_level[t]);
            }
            cell_data.push_back(std::move(ct));
            cell_data.push_back(std::move(lvl));
            bpm::write_surface_vtu(output, refined.surface, point_data, cell_data, encoding);
        } else {
            // The input's patch names become MSH physical names (they were "patch_<id>").
            bpm::write_surface(output, refined.surface, surface_format, encoding, file.patch_info);
        }
        if (json) {
            std::string j = "{\"input\": " + bpm::tools::json_string(input) + ", \"output\": " +
                            bpm::tools::json_string(output) + ", \"ok\": true, \"mode\": \"" +
                            (levels >= 0 ? "uniform" : "adaptive") + "\"";
            if (levels >= 0) j += ", \"levels\": " + std::to_string(levels);
            else j += ", \"max_error\": " + json_double(max_error) + ", \"max_level_option\": " +
                      std::to_string(options.max_level);
            j += ", \"coarse_triangles\": " + std::to_string(result.coarse_triangles) +
                 ", \"vertices\": " + std::to_string(result.vertices) +
                 ", \"triangles\": " + std::to_string(result.triangles) +
                 ", \"max_level\": " + std::to_string(result.max_level) +
                 ", \"max_flat_phi\": " + json_double(result.max_estimated_error) +
                 ", \"hausdorff_bound\": " + json_double(result.hausdorff_bound) +
                 ", \"held_back_vertices\": " + std::to_string(result.held_back_vertices) +
                 ", \"max_held_back\": " + json_double(result.max_held_back) +
                 ", \"remedy_rounds\": " + std::to_string(result.remedy_rounds) +
                 ", \"adaptive_passes\": " + std::to_string(result.adaptive_passes) +
                 ", \"triangles_above_max_error\": " + std::to_string(result.triangles_above_tolerance) +
                 ", \"triangles_at_max_level_above_max_error\": " +
                 std::to_string(result.triangles_at_max_level_above_tolerance) + ", \"above_max_error\": [";
            for (size_t k = 0; k < unmet.size(); ++k) {
                const Unmet& u = unmet[k];
                j += std::string(k ? ", " : "") + "{\"triangle\": " + std::to_string(u.triangle) +
                     ", \"coarse_triangle\": " + std::to_string(u.coarse_triangle) +
                     ", \"level\": " + std::to_string(u.level) + ", \"bound\": " + json_double(u.bound) +
                     ", \"at\": [" + json_double(u.at[0]) + ", " + json_double(u.at[1]) + ", " +
                     json_double(u.at[2]) + "]}";
            }
            j += "], \"seconds\": " + json_double(result.seconds) + "}\n";
            bpm::tools::end_progress_line();
            std::fputs(j.c_str(), stdout);
        }
        return int(bpm::tools::kOk);
    });
}
