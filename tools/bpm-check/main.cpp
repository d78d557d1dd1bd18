// bpm-check: validates a .bpm file (or, with --surface, a plain surface file).
// Thin: options -> CheckSelection/CheckOptions -> run_checks -> text or JSON report.
#include <iostream>
#include <sstream>

#include "bpm/bpm_file.h"
#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/surface_io.h"
#include "common/tool_main.h"

namespace {
// Adds a check to the report in the documented order (spec/check-report.md): before
// "replay", the only check that may follow quality and distance.
void add_in_order(bpm::CheckReport& report, bpm::CheckResult result) {
    auto at = report.checks.end();
    if (!report.checks.empty() && report.checks.back().name == "replay") --at;
    if (result.name == "quality" && at != report.checks.begin() && std::prev(at)->name == "distance") --at;
    report.checks.insert(at, std::move(result));
}

// Adds the tetmesh check where run_checks puts it: after the structural checks.
void add_tetmesh_in_order(bpm::CheckReport& report, bpm::CheckResult result) {
    auto at = report.checks.begin();
    for (auto it = report.checks.begin(); it != report.checks.end(); ++it)
        if (it->name == "format" || it->name == "original-intersections" || it->name == "intersections" ||
            it->name == "topology" || it->name == "junctions")
            at = std::next(it);
    report.checks.insert(at, std::move(result));
}
}  // namespace

// The library reports in its own terms (CheckOptions fields, what a file lacks); the
// flags that set or fix them are ours to name, as they were before the library dropped them.
void name_flags(bpm::CheckReport& report, bool replay_without_steps, bool without_tetmesh) {
    for (bpm::CheckResult& r : report.checks) {
        if (r.name == "distance")
            for (bpm::CheckProblem& pr : r.problems) {
                const std::string field = "the limit max_error = ";
                const size_t at = pr.message.find(field);
                if (at != std::string::npos) pr.message.replace(at, field.size(), "--max-distance ");
            }
        if (r.name == "tetmesh" && without_tetmesh) {
            const std::string hint = " (bpm-mesh writes one)";
            r.summary += hint;
            for (bpm::CheckProblem& pr : r.problems) pr.message += hint;
        }
        if (r.name == "replay" && replay_without_steps) {
            const std::string hint = " (write it with bpm-simplify --record-steps)";
            r.summary += hint;
            for (bpm::CheckProblem& pr : r.problems) pr.message += hint;
        }
    }
}

int main(int argc, char** argv) {
    const std::string tool = "bpm-check";
    CLI::App app{
        "Validates a parametrized surface (.bpm) and exits 0 only if every requested check passes.\n"
        "The checks (--checks):\n"
        "  format         the file is consistent: sizes, indices and numbers in range, every point of\n"
        "                 phi where it says it is (spec/bpm-format.md lists the rules)\n"
        "  intersections  the coarse surface does not intersect itself\n"
        "  topology       coarse and original surface have the same shape: per connected part the same\n"
        "                 genus, orientability, boundary loops, non-manifold edges and vertices, and\n"
        "                 the same topological feature vertices and lines: the feature lines of\n"
        "                 boundaries, patch borders and non-manifold edges (not creases, which are\n"
        "                 geometry; bpm-info counts both)\n"
        "  junctions      around every edge of three or more triangles (where materials meet) the sheets,\n"
        "                 in their order around the edge, agree about the material between each two (from\n"
        "                 the patches' materials; edges without them are counted and skipped); S and S0;\n"
        "                 and every component of S lies in the materials its component of S0 lies in\n"
        "  bijectivity    phi is one-to-one and onto: its pieces exactly cover every coarse and every\n"
        "                 original triangle\n"
        "  replay         (with --replay) the removals stored by bpm-simplify --record-steps are each a\n"
        "                 valid removal and together give the coarse surface\n"
        "  tetmesh        (files with a volume mesh, from bpm-mesh) the tetrahedra are positively oriented\n"
        "                 and meet face to face, fill the inside of the coarse surface, and their faces\n"
        "                 on it cover every coarse triangle exactly once\n"
        "  quality        (with --max-aspect / --min-angle) shapes of the coarse triangles\n"
        "  distance       (with --max-distance) how far phi's image and the coarse surface are from the original",
        tool};
    std::string input;
    std::string checks = "format,intersections,topology,junctions,bijectivity,distortion,tetmesh";
    bool original = false, json = false, surface_mode = false;
    double max_aspect = 0, min_angle = 0, max_distance = 0, sample_spacing = 1e-3;
    bool replay = false;
    int64_t replay_interval = 0;
    size_t max_problems = 10;
    int threads = 0;
    std::string surface_format;
    app.add_option("FILE", input, "Input .bpm file, or a surface file with --surface; '-' reads standard input")
        ->required();
    app.add_option("--checks", checks,
                   "Comma-separated checks to run: format, intersections, topology, junctions, bijectivity, distortion, "
                   "tetmesh, replay ('all' = the first seven, the default; tetmesh runs on files with a volume mesh and, named "
                   "here by itself, fails on files without one). With --surface: intersections, topology, junctions")
        ->capture_default_str();
    app.add_flag("--original", original,
                 "Also check the original surface for self-intersections (reported as 'original-intersections')");
    app.add_flag("--json", json, "Print the report as JSON on standard output (format: spec/check-report.md)");
    auto* aspect_opt = app.add_option("--max-aspect", max_aspect,
                                      "Fail if a coarse triangle has aspect ratio R/r above A (at least 2 = equilateral)")
                           ->check(bpm::tools::aspect_ratio_limit());
    aspect_opt->type_name("A");
    auto* angle_opt = app.add_option("--min-angle", min_angle, "Fail if a coarse triangle has an angle below D degrees")
                          ->check(CLI::Range(0.0, 60.0));
    angle_opt->type_name("D");
    // --max-distance is a Hausdorff distance; it was --max-error, which bpm-simplify and
    // bpm-refine use for max |phi(x) - x| (an upper bound of one direction of it).
    auto* distance_opt =
        app.add_option("--max-distance", max_distance,
                       "Fail if the Hausdorff distance of phi's image or of the coarse surface to the original is "
                       "above D (fraction of the diagonal)")
            ->check(CLI::NonNegativeNumber);
    distance_opt->type_name("D");
    auto* distance_alias =
        bpm::tools::add_deprecated_alias(app, "--max-error", max_distance, distance_opt,
                                         "--max-error of bpm-simplify and bpm-refine is max |phi(x) - x|, which "
                                         "bpm-check reports as coarse_to_original_bound")
            ->check(CLI::NonNegativeNumber);
    auto* spacing_opt = app.add_option("--sample-spacing", sample_spacing,
                                       "Sample spacing of --max-distance (fraction of the diagonal; the estimate is at "
                                       "most this low)")
                            ->check(CLI::PositiveNumber)
                            ->type_name("H")
                            ->capture_default_str();
    bpm::tools::add_deprecated_alias(app, "--error-spacing", sample_spacing, spacing_opt)->check(CLI::PositiveNumber);
    app.add_flag("--replay", replay,
                 "Also replay the steps stored by bpm-simplify --record-steps (= 'replay' in --checks)");
    app.add_option("--replay-interval", replay_interval,
                   "With --replay: recompute the invariants from scratch every K steps (0 = 4 times) and at the end")
        ->check(CLI::NonNegativeNumber)
        ->type_name("K")
        ->capture_default_str();
    app.add_option("--max-problems", max_problems, "Offending elements listed per check")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--threads", threads,
                   "Threads for checks side by side (0 = up to 2, 1 = one after the other); the report does not "
                   "depend on it")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    app.add_flag("--surface", surface_mode,
                 "FILE is a plain surface or a label image, not a .bpm: check intersections, topology and junctions");
    bool triangulate_polygons = false;
    bpm::SurfaceReadOptions read_options;
    app.add_flag("--triangulate-polygons", triangulate_polygons,
                 "Split faces with more than 3 corners into triangles first");
    // The other repairs of bpm-simplify, so that the flags an error names work here too.
    app.add_flag("--merge-duplicate-vertices", read_options.merge_duplicate_vertices,
                 "Merge vertices with identical coordinates first");
    bpm::tools::add_merge_vertices_within_option(app, read_options);
    app.add_flag("--merge-duplicate-triangles", read_options.merge_duplicate_triangles,
                 "Fuse triangles with the same three vertices first");
    app.add_flag("--drop-unreferenced-vertices", read_options.drop_unreferenced_vertices,
                 "Drop vertices that no triangle uses first");
    bpm::tools::add_format_option(app, surface_format, "input",
                                  "Surface format for --surface when reading '-' (off, obj, stl, ply, msh, vtk, vtp, "
                                  "vtu, surf)");
    bool verbose = false, quiet = false;
    app.add_flag("-v,--verbose", verbose, "More detail on standard error");
    app.add_flag("-q,--quiet", quiet, "Only errors on standard error (the report still goes to standard output)");
    bpm::tools::add_version_flag(app, tool);
    bpm::tools::group_options(app, "Checks", {"--checks", "--original", "--replay", "--surface"});
    bpm::tools::group_options(app, "Thresholds (each adds a check)",
                              {"--max-aspect", "--min-angle", "--max-distance", "--sample-spacing"});
    bpm::tools::group_options(app, "Input repairs (with --surface)",
                              {"--input-format", "--triangulate-polygons", "--merge-duplicate-vertices",
                               "--merge-vertices-within", "--merge-duplicate-triangles", "--drop-unreferenced-vertices"});
    bpm::tools::group_options(app, "Output", {"--json", "--max-problems", "--verbose", "--quiet"});
    bpm::tools::group_options(app, "Advanced", {"--replay-interval", "--threads"});
    bpm::tools::add_examples(app, {"bpm-check femur.bpm", "bpm-check femur.bpm --max-distance 0.005 --json",
                                   "bpm-check --surface femur.off"});

    // With --json every error is a report too (spec/check-report.md, "Errors").
    bpm::tools::set_json_error_report(json, [&](const bpm::tools::ErrorReport& error) {
        return "{\"bpm_check_report\": 1, \"input\": " + bpm::tools::json_string(input) +
               ", \"passed\": false, \"checks\": [], \"error\": " + bpm::tools::error_json(error) + "}";
    });
    return bpm::tools::run(tool, argc, argv, app, [&]() {
        bpm::CheckSelection sel;
        sel.format = sel.intersections = sel.topology = sel.junctions = sel.bijectivity = sel.tetmesh = false;
        // distance and quality are run by their limits (--max-distance, --max-aspect,
        // --min-angle); named in --checks without one they measure and pass.
        bool want_distance = false, want_quality = false;
        bool tetmesh_named = false;  // "tetmesh" itself in --checks (not by "all")
        std::stringstream list(checks);
        std::string item;
        while (std::getline(list, item, ',')) {
            if (item == "format") sel.format = true;
            else if (item == "intersections") sel.intersections = true;
            else if (item == "topology") sel.topology = true;
            else if (item == "junctions") sel.junctions = true;
            else if (item == "bijectivity") sel.bijectivity = true;
            else if (item == "replay") sel.replay = true;
            else if (item == "distortion") sel.distortion = true;
            else if (item == "tetmesh") sel.tetmesh = tetmesh_named = true;
            else if (item == "distance") want_distance = true;
            else if (item == "quality") want_quality = true;
            else if (item == "all")
                sel.format = sel.intersections = sel.topology = sel.junctions = sel.bijectivity = sel.distortion =
                    sel.tetmesh = true;
            else
                throw CLI::ValidationError("--checks", "unknown check '" + item +
                                                           "' (known: format, intersections, topology, junctions, bijectivity, "
                                                           "distortion, tetmesh, quality, distance, replay, all)");
        }
        sel.original_intersections = original;
        if (replay) sel.replay = true;
        bpm::CheckOptions options;
        options.max_problems = max_problems;
        if (*aspect_opt) options.max_aspect_ratio = max_aspect;
        if (*angle_opt) options.min_angle_degrees = min_angle;
        const bool distance_limit = distance_opt->count() + distance_alias->count() > 0;
        if (distance_limit) options.max_error = max_distance;
        options.error_sample_spacing = sample_spacing;
        options.replay_check_interval = replay_interval;
        options.threads = threads;
        const bpm::Context context = bpm::tools::make_context(tool, verbose, quiet || json);

        bpm::CheckReport report;
        if (surface_mode) {
            if (sel.replay) throw CLI::ValidationError("--replay", "replay needs a .bpm file, not --surface");
            if (distance_limit)
                throw CLI::ValidationError("--max-distance", "--max-distance needs a .bpm file, not --surface");
            if (sel.format || sel.bijectivity || sel.distortion || sel.tetmesh) {
                if (app.count("--checks"))
                    throw CLI::ValidationError("--checks",
                                               "format, bijectivity, distortion and tetmesh need a .bpm file, not --surface");
                sel.format = sel.bijectivity = sel.distortion = sel.tetmesh = false;
            }
            read_options.triangulate_polygons = triangulate_polygons;
            if (!surface_format.empty()) {
                read_options.format = bpm::surface_format_from_name(surface_format);
                if (!read_options.format)
                    throw CLI::ValidationError("--input-format", "unknown surface format '" + surface_format + "'");
            }
            if (want_distance) throw CLI::ValidationError("--checks", "distance needs a .bpm file, not --surface");
            bpm::tools::require_input_format_for_stdin({input}, surface_format);
            bpm::SurfaceReadReport read_report;
            const bpm::Surface surface = bpm::read_surface(input, read_options, &read_report);
            for (const auto& note : read_report.notes) context.info(note);
            for (const auto& warning : read_report.warnings) context.warn(warning);
            if (std::string seam = bpm::tools::open_seam_warning(read_report); !seam.empty()) context.warn(seam);
            report = bpm::run_surface_checks(surface, sel, options, context);
            if (sel.junctions) {  // after topology; run_surface_checks has no patch info to give it
                auto at = report.checks.begin();
                for (auto it = report.checks.begin(); it != report.checks.end(); ++it)
                    if (it->name == "intersections" || it->name == "topology") at = std::next(it);
                report.checks.insert(at, bpm::check_junctions(surface, read_report.patch_info, options, context));
            }
            if (want_quality && !report.find("quality")) add_in_order(report, bpm::check_quality(surface, options, context));
        } else {
            const bpm::BpmFile file = bpm::tools::read_bpm_input(input, "check it with bpm-check --surface " + input);
            // distance reads phi, so it needs a structurally sound file.
            if (want_distance && !distance_limit) sel.format = true;
            report = bpm::run_checks(file, sel, options, context);
            if (want_quality && !report.find("quality"))
                add_in_order(report, bpm::check_quality(file.param.coarse, options, context));
            const bpm::CheckResult* format_check = report.find("format");
            if (want_distance && !report.find("distance") && format_check && format_check->passed)
                add_in_order(report, bpm::check_distance(file.param, options, context));
            // tetmesh runs on files that have a tet mesh; named in --checks (not by "all",
            // not by the default), its absence fails.
            const bool tetmesh_missing = tetmesh_named && app.count("--checks") > 0 && !file.tetmesh;
            if (tetmesh_missing) add_tetmesh_in_order(report, bpm::check_tetmesh(file, options, context));
            name_flags(report, sel.replay && !file.simplification_steps, tetmesh_missing);
        }
        report.input = input;
        bpm::tools::end_progress_line();
        std::cout << (json ? bpm::check_report_to_json(report) : bpm::check_report_to_text(report)) << std::flush;
        return report.passed() ? bpm::tools::kOk : bpm::tools::kCheckFailed;
    });
}
