// bpm-mesh: tetrahedral mesh of the volume bounded by the coarse surface of a .bpm file
// (TetGen), optionally red-refined with boundary vertices moved onto the original surface.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/errors.h"
#include "bpm/tet_refine.h"
#include "bpm/tetmesh.h"
#include "bpm/write_tetmesh.h"
#include "bpm/tetmesh_materials.h"
#include "common/tool_main.h"

namespace {

std::string json_double(double v) {
    if (!std::isfinite(v)) return "null";
    return bpm::tools::significant_text(v, 10);
}

std::string json_escape(const std::string& s) {
    std::string out;
    for (unsigned char c : s) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += char(c);
        } else if (c < 0x20) {
            char buffer[8];
            std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
            out += buffer;
        } else {
            out += char(c);
        }
    }
    return out;
}

// How many region ids, materials and problems the log lists before it counts the rest: a
// noisy label image gives thousands of regions (64^3 voxels: 7920), and one line naming
// every region was tens of kilobytes. --json lists every region with its material.
constexpr size_t kListed = 8, kListedMaterials = 20, kListedProblems = 10;

// "1 region", "3 regions".
std::string count_text(size_t n, const std::string& noun) { return std::to_string(n) + " " + noun + (n == 1 ? "" : "s"); }

// "1,5,6" or "1,5,6,9,11,13,19,25 and 6 more".
std::string listed_ids(const std::vector<int64_t>& ids) {
    std::string text;
    for (size_t k = 0; k < ids.size() && k < kListed; ++k) text += (k ? "," : "") + std::to_string(ids[k]);
    if (ids.size() > kListed) text += " and " + std::to_string(ids.size() - kListed) + " more";
    return text;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string tool = "bpm-mesh";
    CLI::App app{
        "Tetrahedral mesh of the volume bounded by the coarse surface of a .bpm file, made by TetGen (Debian\n"
        "package 'tetgen', found on PATH) with the surface kept exactly (-p -Y -q -A). Every enclosed region of\n"
        "a multi-material surface gets its own region id (1, 2, ...); the outside is not meshed. Every region\n"
        "gets a material from the patch information of the input (Amira InnerRegion/OuterRegion, one input\n"
        "file per material, Gmsh physical names 'A|B' or 'pair_A_B', MSH 4.1 physical volumes; spec/tetmesh.md\n"
        "3.7) or from --material; regions nothing decides are materials of their own, named region_<id>.\n"
        "Output by extension: .bpm (the input file plus a /tetmesh group, spec/tetmesh.md), .msh (Gmsh 4.1),\n"
        ".vtu (VTK), .mesh (MEDIT). With --refine K the mesh is red-refined K times and new boundary vertices\n"
        "are moved onto the original surface through phi (Krause & Sander §3.3). Vertices not on the surface\n"
        "are smoothed (TetGen's Steiner points, and after every refinement level) to keep the elements next to\n"
        "the moved boundary well shaped, and tetrahedra with a small dihedral angle are flipped (2-3 flips,\n"
        "edge removals; never a face of the surface) where that raises it, at level 0 followed by a new\n"
        "interior vertex in those no flip improves; --no-smooth turns all of it off, --no-flip the flips\n"
        "and the new vertices. Tetrahedra with a corner whose three edges are on the surface are split at level 0\n"
        "(refining them would make tetrahedra with four corners on the surface, which phi flattens;\n"
        "--no-corner-split keeps them).",
        tool};
    std::string input, output, format;
    bpm::TetMeshOptions options;
    double max_volume = 0;
    int refine_levels = 0;
    bool existing = false, flat = false, json = false, verbose = false, quiet = false, deterministic = false;
    app.add_option("INPUT", input, "Input .bpm file, or - for standard input")->required();
    app.add_option("-o,--output", output, "Output .bpm .msh .vtu .mesh, or - for standard output (see --format)")
        ->required();
    bpm::tools::add_format_option(app, format, "output",
                                  "Output format when it cannot be told from the name: bpm, msh, vtu, mesh, or msh22 "
                                  "(MSH 2.2, for DUNE's GmshReader)");
    bpm::tools::EncodingFlags encoding_flags;
    bpm::tools::add_encoding_options(app, encoding_flags);
    app.add_option("--quality", options.quality, "TetGen -q: maximum radius-edge ratio, > 1.0 (default 1.414)")
        ->check(CLI::PositiveNumber);
    double min_dihedral = -1;
    app.add_option("--min-dihedral", min_dihedral,
                   "TetGen -q<quality>/<angle>: minimum dihedral angle in degrees to aim for, at most " +
                       std::to_string(int(bpm::kMaxTetgenMinDihedralDegrees)) +
                       " (TetGen does not terminate above; default: none)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--max-dihedral", options.max_dihedral_degrees,
                   "TetGen -o/<angle>: largest dihedral angle TetGen's optimisation aims below (degrees; default "
                   "150, 0 = TetGen's own 165)")
        ->check(CLI::Range(0.0, 179.0));
    app.add_option("--time-limit", options.time_limit_seconds,
                   "Stop TetGen after this many seconds with an error (default 0 = no limit)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--max-volume", max_volume, "TetGen -a: maximum tetrahedron volume, in the file's units^3 (default: no limit)")
        ->check(CLI::PositiveNumber);
    app.add_option("--refine", refine_levels, "Red-refine the mesh K times, moving new boundary vertices to phi (default 0)")
        ->check(CLI::Range(0, 8));
    double min_volume_fraction = 0.1;
    app.add_option("--min-volume-fraction", min_volume_fraction,
                   "Hold a boundary vertex short of phi until its tetrahedra keep this fraction of their volume "
                   "(default 0.1)")
        ->check(CLI::Range(0.0, 0.99));
    bool no_smooth = false;
    app.add_flag("--no-smooth", no_smooth,
                 "Do not smooth the interior vertices (smoothing never inverts or worsens)");
    bool no_flip = false;
    app.add_flag("--no-flip", no_flip,
                 "Do not flip tetrahedra or insert vertices to remove slivers (keeps TetGen's mesh and, with "
                 "--refine, red refinement)");
    double remedy_min_dihedral = bpm::TetRefineOptions{}.repair.min_dihedral_degrees;
    app.add_option("--remedy-min-dihedral", remedy_min_dihedral,
                   "Hold a boundary vertex short of phi rather than bring a dihedral angle below this (degrees; "
                   "default 8)")
        ->check(CLI::Range(0.0, 60.0));
    bool no_corner_split = false;
    app.add_flag("--no-corner-split", no_corner_split,
                 "Keep the tetrahedra with a corner whose three edges are on the surface (see above)");
    app.add_flag("--existing", existing, "Use the tetrahedral mesh already in INPUT instead of running TetGen");
    app.add_flag("--flat", flat, "With --refine: leave new boundary vertices on the coarse surface (red refinement of the boundary)");
    app.add_option("--tetgen", options.tetgen, "TetGen executable (default: tetgen on PATH)");
    app.add_flag("--keep-temporary", options.keep_temporary, "Keep TetGen's input and output files (path on stderr)");
    std::vector<std::string> material_args;
    app.add_option("--material", material_args,
                   "Name region REGION (an id from the log or --json) material NAME; repeatable")
        ->type_name("REGION=NAME");
    app.add_flag("--json", json, "Print a JSON report (counts, timings, region volumes, quality) on standard output");
    bpm::tools::add_output_tool_flags(app, tool, deterministic, verbose, quiet);
    bpm::tools::group_options(app, "Output", {"--output", "--output-format", "--binary", "--compress", "--json"});
    bpm::tools::group_options(app, "Quality", {"--quality", "--min-dihedral", "--max-dihedral", "--max-volume", "--time-limit"});
    bpm::tools::group_options(app, "Refinement", {"--refine", "--flat", "--min-volume-fraction", "--remedy-min-dihedral"});
    bpm::tools::group_options(app, "Regions", {"--material"});
    bpm::tools::group_options(app, "Advanced", {"--no-smooth", "--no-flip", "--no-corner-split", "--existing", "--tetgen", "--keep-temporary"});
    bpm::tools::add_examples(app, {"bpm-mesh femur.bpm -o femur.tet.bpm",
                                   "bpm-mesh femur.bpm -o femur.msh --refine 1 --time-limit 600 --json"});

    // With --json every error is a report too: {"input", "ok": false, "error"}.
    bpm::tools::set_json_error_report(json, [&](const bpm::tools::ErrorReport& error) {
        return "{\"input\": " + bpm::tools::json_string(input) + ", \"ok\": false, \"error\": " +
               bpm::tools::error_json(error) + "}";
    });
    return bpm::tools::run(tool, argc, argv, app, [&]() {
        bpm::tools::set_error_input(input);
        bpm::tools::require_output_directory(output);
        std::optional<bpm::TetMeshFormat> out_format =
            format.empty() ? (output == "-" ? std::optional(bpm::TetMeshFormat::Bpm) : bpm::tetmesh_format_from_path(output))
                           : bpm::tetmesh_format_from_name(format);
        if (!out_format)
            throw CLI::ValidationError(format.empty() ? "--output" : "--output-format",
                                       format.empty() ? "cannot tell the format from '" + output +
                                                            "': use .bpm .msh .vtu .mesh or --output-format"
                                                      : "unknown output format '" + format +
                                                            "' (valid: bpm msh msh22 vtu mesh)");
        if (json && output == "-") throw CLI::ValidationError("--json", "needs an output file (stdout carries the JSON)");
        if (*out_format == bpm::TetMeshFormat::Bpm) bpm::tools::refuse_binary_to_terminal(output, "binary .bpm (HDF5) data");
        const bpm::MeshEncoding encoding =
            bpm::tools::output_encoding(encoding_flags, bpm::tetmesh_format_name(*out_format), output);
        if (max_volume > 0) options.max_volume = max_volume;
        if (min_dihedral >= 0) options.min_dihedral_degrees = min_dihedral;
        if (options.max_dihedral_degrees != 0 && options.max_dihedral_degrees < 90)
            throw CLI::ValidationError("--max-dihedral", "must be 0 (TetGen's default) or between 90 and 179 degrees");
        options.smooth = !no_smooth;
        options.flip = !no_smooth && !no_flip;  // --no-smooth: no quality improvement at all, as before flips
        options.split_surface_corners = !no_corner_split;
        bpm::MaterialOptions material_options;
        for (const std::string& a : material_args) {
            const size_t eq = a.find('=');
            int region = 0;
            try {
                if (eq == std::string::npos || eq == 0 || eq + 1 == a.size()) throw std::invalid_argument(a);
                size_t used = 0;
                region = std::stoi(a.substr(0, eq), &used);
                if (used != eq) throw std::invalid_argument(a);
            } catch (const std::exception&) {
                throw CLI::ValidationError("--material", "expected REGION=NAME with a region id, got '" + a + "'");
            }
            material_options.region_names[region] = a.substr(eq + 1);
        }
        bpm::Context context = bpm::tools::make_context(tool, verbose, quiet);
        // TetGen can run forever with quality bounds near their limits (e.g. --quality 1.1
        // --min-dihedral 18 on a fine surface, each fine alone); when the user tightened a
        // bound and set no time limit, the first progress line says how to bound the run
        // (with the defaults a long run is just a big mesh).
        const bool bounds_tightened =
            min_dihedral >= 0 || options.quality < bpm::TetMeshOptions{}.quality;
        if (bounds_tightened && options.time_limit_seconds <= 0 && context.log) {
            auto hinted = std::make_shared<bool>(false);
            context.log = [log = context.log, hinted, quiet](bpm::LogLevel level, const std::string& line) {
                log(level, line);
                if (!*hinted && !quiet && line.rfind("TetGen still running", 0) == 0) {
                    *hinted = true;
                    log(bpm::LogLevel::Warning,
                        "TetGen may not finish with --quality or --min-dihedral near their limits; "
                        "--time-limit SECONDS stops it with an error (exit 6)");
                }
            };
        }

        bpm::BpmFile file = bpm::tools::read_bpm_input(input);
        bpm::TetMeshResult mesh_result;
        if (existing) {
            if (!file.tetmesh) throw bpm::InputError(input, "--existing: the file has no /tetmesh group");
        } else {
            bpm::TetMesh mesh;
            mesh_result = bpm::generate_tetmesh(file.param, options, context, mesh);
            file.tetmesh = std::move(mesh);
            char line[256];
            std::snprintf(line, sizeof line, "%lld vertices (%lld Steiner), %lld tetrahedra, %lld regions, %.2f s",
                          (long long)mesh_result.vertices, (long long)mesh_result.steiner_points,
                          (long long)mesh_result.tetrahedra, (long long)mesh_result.regions, mesh_result.seconds);
            context.info(line);
        }
        // The region volumes before --refine, for --json's coarse_volume only (a pass over every
        // tetrahedron; without --refine they are those of `stats` below).
        const bpm::TetMeshStats coarse_stats =
            json && refine_levels > 0 ? bpm::tetmesh_stats(*file.tetmesh) : bpm::TetMeshStats{};
        bpm::TetRefineResult refine_result;
        if (refine_levels > 0) {
            bpm::TetRefineOptions ro;
            ro.levels = refine_levels;
            ro.move_to_surface = !flat;
            ro.repair.min_volume_fraction = min_volume_fraction;
            ro.repair.min_dihedral_degrees = remedy_min_dihedral;
            ro.repair.smooth = !no_smooth;
            ro.flip = !no_smooth && !no_flip;
            bpm::TetMesh fine;
            refine_result = bpm::refine_tetmesh(file.param, *file.tetmesh, ro, context, fine);
            file.tetmesh = std::move(fine);
            char line[256];
            for (size_t k = 0; k < refine_result.levels.size(); ++k)
                context.debug(bpm::describe_level(refine_result.levels[k], k + 1));
            std::snprintf(line, sizeof line,
                          "refined %d levels: %lld tetrahedra; %lld boundary vertices kept off the surface by the "
                          "lambda remedy (max distance %.3g = %.3g of the diagonal), %.2f s",
                          refine_levels, (long long)refine_result.tetrahedra,
                          (long long)refine_result.remedied_vertices, refine_result.max_remedy_distance,
                          refine_result.max_remedy_distance_relative, refine_result.seconds);
            context.info(line);
        }
        const bpm::MaterialResult materials = bpm::assign_materials(*file.tetmesh, file.patch_info, material_options);
        // /patch_info and the MSH physical names as the regions show them (a nested file's
        // outer side is the enclosing material, not exterior).
        if (const int64_t renamed = bpm::name_patches_after_regions(*file.tetmesh, file.patch_info); renamed > 0)
            context.debug(std::to_string(renamed) + " patch" + (renamed == 1 ? "" : "es") +
                          " named after the regions on their sides (exterior was the enclosing material)");
        {
            const bpm::TetMesh& m = *file.tetmesh;
            std::string line = std::to_string(materials.materials) + " material" + (materials.materials == 1 ? "" : "s") + ":";
            // assign_materials gave every region a material in 1 .. #materials.
            std::vector<std::vector<int64_t>> regions_of(m.material_names.size());
            for (size_t r = 0; r < m.region_material.size(); ++r)
                regions_of[size_t(m.region_material[r] - 1)].push_back(int64_t(r) + 1);
            for (size_t i = 0; i < regions_of.size() && i < kListedMaterials; ++i)
                line += std::string(i ? ";" : "") + " " + std::to_string(i + 1) + " " + m.material_names[i] +
                        " (region" + (regions_of[i].size() == 1 ? " " : "s ") + listed_ids(regions_of[i]) + ")";
            if (regions_of.size() > kListedMaterials)
                line += "; and " + count_text(regions_of.size() - kListedMaterials, "more material");
            context.info(line);
            if (materials.orientation_ignored)
                context.warn("the patches' front/back materials contradict each other (reversed normals?): read them "
                             "as unordered pairs");
            for (size_t k = 0; k < materials.problems.size() && k < kListedProblems; ++k)
                context.warn(materials.problems[k]);
            if (materials.problems.size() > kListedProblems)
                context.warn("and " + count_text(materials.problems.size() - kListedProblems, "more region") +
                             " like these (--json lists every region with its material)");
            // Each problem leaves a region named region_<id>: say how to name it.
            std::string unnamed;
            size_t unnamed_count = 0;
            for (size_t r = 0; r < m.region_material.size(); ++r) {
                const std::string id = std::to_string(r + 1);
                if (m.material_names[size_t(m.region_material[r] - 1)] != "region_" + id) continue;
                if (++unnamed_count <= kListed) unnamed += (unnamed.empty() ? "" : " ") + std::string("--material ") + id + "=NAME";
            }
            if (unnamed_count > kListed)
                unnamed += " and so on for " + std::to_string(unnamed_count - kListed) +
                           " more (--json lists them: material_name region_<id>)";
            if (!materials.problems.empty() && unnamed_count > 0)
                context.warn("to name the regions the input does not decide, rerun with " + unnamed);
        }
        // For the warning (which -q hides) and --json only.
        const bpm::TetMeshStats stats = json || !quiet ? bpm::tetmesh_stats(*file.tetmesh) : bpm::TetMeshStats{};
        if (stats.inverted > 0) context.warn(std::to_string(stats.inverted) + " inverted tetrahedra");

        if (*out_format == bpm::TetMeshFormat::Bpm) {
            file.provenance.push_back({tool, bpm::tools::version_line(tool), bpm::tools::command_line(argc, argv),
                                       deterministic ? std::string() : bpm::tools::utc_timestamp()});
            bpm::write_bpm(output, file);
        } else {
            bpm::write_tetmesh(output, *file.tetmesh, *out_format, file.patch_info, encoding);
        }

        if (json) {
            const auto original = bpm::region_volumes_on_original(file.param, *file.tetmesh);
            const bpm::TetMesh& m = *file.tetmesh;
            std::string j = "{\"input\": " + bpm::tools::json_string(input) + ", \"ok\": true, \"level\": " + std::to_string(m.level) +
                            ", \"vertices\": " + std::to_string(m.num_vertices()) +
                            ", \"tetrahedra\": " + std::to_string(m.num_tetrahedra()) +
                            ", \"faces\": " + std::to_string(m.faces.size()) +
                            ", \"coarse_triangles\": " + std::to_string(file.param.coarse.num_triangles()) +
                            ", \"steiner_points\": " + std::to_string(mesh_result.steiner_points) +
                            ", \"mesh_seconds\": " + json_double(mesh_result.seconds) +
                            ", \"tetgen_seconds\": " + json_double(mesh_result.tetgen_seconds) +
                            ", \"inverted\": " + std::to_string(stats.inverted) +
                            ", \"min_dihedral_degrees\": " + json_double(stats.min_dihedral_degrees) +
                            ", \"max_dihedral_degrees\": " + json_double(stats.max_dihedral_degrees) +
                            ", \"below_1_degree\": " + std::to_string(stats.below_1_degree) +
                            ", \"below_5_degrees\": " + std::to_string(stats.below_5_degrees) +
                            ", \"below_10_degrees\": " + std::to_string(stats.below_10_degrees) +
                            ", \"smoothed\": " + std::string(no_smooth ? "false" : "true") +
                            ", \"flips\": " + std::to_string([&] {
                                int64_t n = mesh_result.flips;
                                for (const auto& l : refine_result.levels) n += l.flips;
                                return n;
                            }()) +
                            ", \"insertions\": " + std::to_string(mesh_result.insertions) +
                            ", \"surface_corner_splits\": " + std::to_string(mesh_result.surface_corner_splits) +
                            ", \"flip_seconds\": " + json_double([&] {
                                double sec = mesh_result.flip_seconds;
                                for (const auto& l : refine_result.levels) sec += l.flip_seconds;
                                return sec;
                            }()) +
                            ", \"remedied_vertices\": " + std::to_string(refine_result.remedied_vertices) +
                            ", \"max_remedy_distance\": " + json_double(refine_result.max_remedy_distance) +
                            ", \"max_remedy_distance_relative\": " +
                            json_double(refine_result.max_remedy_distance_relative) +
                            ", \"refine_seconds\": " + json_double(refine_result.seconds) + ", \"regions\": [";
            for (size_t r = 0; r < stats.region_volumes.size(); ++r) {
                const int32_t mat = m.region_material[r];
                j += std::string(r ? ", " : "") + "{\"id\": " + std::to_string(r + 1) +
                     ", \"material\": " + std::to_string(mat) + ", \"material_name\": \"" +
                     json_escape(m.material_names[size_t(mat - 1)]) + "\"" +
                     ", \"volume\": " + json_double(stats.region_volumes[r]) +
                     ", \"coarse_volume\": " +
                     json_double(refine_levels == 0 ? stats.region_volumes[r]
                                 : r < coarse_stats.region_volumes.size() ? coarse_stats.region_volumes[r] : NAN) +
                     ", \"original_volume\": " + json_double(r < original.size() ? original[r] : NAN) + "}";
            }
            j += "], \"materials\": [";
            for (size_t i = 0; i < m.material_names.size(); ++i)
                j += std::string(i ? ", " : "") + "{\"id\": " + std::to_string(i + 1) + ", \"name\": \"" +
                     json_escape(m.material_names[i]) + "\"}";
            j += "], \"material_problems\": " + std::to_string(materials.problems.size()) + "}";
            bpm::tools::end_progress_line();
            std::cout << j << std::endl;
        }
        return int(bpm::tools::kOk);
    });
}
