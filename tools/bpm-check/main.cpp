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
}  // namespace

// read_bpm, with a hint when the file is a plain surface (bpm-check femur.off).
bpm::BpmFile read_bpm_or_hint(const std::string& input) {
    try {
        return bpm::read_bpm(input);
    } catch (const bpm::InputError& e) {
        if (input == "-" || !bpm::surface_format_from_path(input)) throw;
        throw bpm::InputError(e.where(), std::string(e.what()) + ". It looks like a surface file: check it with " +
                                             "bpm-check --surface " + input);
    }
}

// The library reports in its own terms (CheckOptions fields, what a file lacks); the
// flags that set or fix them are ours to name, as they were before the library dropped them.
void name_flags(bpm::CheckReport& report, bool replay_without_steps) {
    for (bpm::CheckResult& r : report.checks) {
        if (r.name == "distance")
            for (bpm::CheckProblem& pr : r.problems) {
                const std::string field = "the limit max_error = ";
                const size_t at = pr.message.find(field);
                if (at != std::string::npos) pr.message.replace(at, field.size(), "--max-error ");
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
        "Checks:\n"
        "  format         structural consistency: sizes, index ranges, CSR offsets, finite values,\n"
        "                 node barycentrics and identities, images equal to the points they name\n"
        "  intersections  the coarse surface has no self-intersections (coplanar overlaps included)\n"
        "  topology       coarse and original surface agree per component in Euler characteristic,\n"
        "                 orientability, boundary loops, Z2 Betti numbers and non-manifold structure\n"
        "                 (feature vertices by original id, feature lines with their sheet counts)\n"
        "  bijectivity    phi is a bijection: pieces tile every coarse and every original triangle\n"
        "  distortion     (a report, never fails) phi's area squeeze and normal deviation per piece,\n"
        "                 p50/p99/max, and the pieces turned more than 60 and 90 degrees (folds)\n"
        "  replay         (with --replay) the recorded removals (bpm-simplify --record-steps) are valid point\n"
        "                 removals (link = boundary of the new triangles, local condition of Conjecture 2.1,\n"
        "                 topology unchanged) and lead exactly to the coarse surface\n"
        "  quality        (with --max-aspect / --min-angle) triangle shapes of the coarse surface\n"
        "  distance       (with --max-error) Hausdorff distances of phi's image and of the coarse surface to S0",
        tool};
    std::string input;
    std::string checks = "format,intersections,topology,bijectivity,distortion";
    bool original = false, json = false, surface_mode = false;
    double max_aspect = 0, min_angle = 0, max_error = 0, error_spacing = 1e-3;
    bool replay = false;
    int64_t replay_interval = 0;
    size_t max_problems = 10;
    int threads = 0;
    std::string surface_format;
    app.add_option("FILE", input, "Input .bpm file, or a surface file with --surface; '-' reads standard input")
        ->required();
    app.add_option("--checks", checks,
                   "Comma-separated checks to run: format, intersections, topology, bijectivity, distortion, replay "
                   "('all' = the first five, the default). With --surface only intersections and topology apply")
        ->capture_default_str();
    app.add_flag("--original", original,
                 "Also check the original surface S0 for self-intersections (reported as "
                 "'original-intersections', so a faulty input is told apart from a faulty result)");
    app.add_flag("--json", json, "Print the report as JSON on standard output (format: spec/check-report.md)");
    auto* aspect_opt = app.add_option("--max-aspect", max_aspect,
                                      "Fail if a coarse triangle has aspect ratio R/r above A (2 = equilateral)")
                           ->check(CLI::PositiveNumber);
    aspect_opt->type_name("A");
    auto* angle_opt = app.add_option("--min-angle", min_angle, "Fail if a coarse triangle has an angle below D degrees")
                          ->check(CLI::Range(0.0, 60.0));
    angle_opt->type_name("D");
    auto* error_opt =
        app.add_option("--max-error", max_error,
                       "Fail if phi's image or the coarse surface is farther than E from S0 (two-sided Hausdorff "
                       "distances, as a fraction of the bounding-box diagonal of S0; e.g. 0.005)")
            ->check(CLI::NonNegativeNumber);
    error_opt->type_name("E");
    app.add_option("--error-spacing", error_spacing,
                   "Sample spacing of --max-error on every triangle, as a fraction of the diagonal (the estimate is at "
                   "most this far below the true distance)")
        ->check(CLI::PositiveNumber)
        ->type_name("H")
        ->capture_default_str();
    app.add_flag("--replay", replay,
                 "Also replay the recorded simplification steps (files written by bpm-simplify --record-steps); "
                 "same as adding 'replay' to --checks");
    app.add_option("--replay-interval", replay_interval,
                   "With --replay: recompute all topological invariants from scratch every K steps (0 = 4 times "
                   "evenly spaced); they are always recomputed after the last step")
        ->check(CLI::NonNegativeNumber)
        ->type_name("K")
        ->capture_default_str();
    app.add_option("--max-problems", max_problems, "Offending elements listed per check")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--threads", threads,
                   "Threads for running checks side by side (0 = up to 2 as the hardware allows, 1 = one after "
                   "the other); the report does not depend on it")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    app.add_flag("--surface", surface_mode,
                 "FILE is a plain surface (OFF, OBJ, STL, PLY, MSH, VTK, VTP, VTU, SURF): run intersections and topology on it alone");
    bool triangulate_polygons = false;
    bpm::SurfaceReadOptions read_options;
    app.add_flag("--triangulate-polygons", triangulate_polygons,
                 "With --surface: split faces with more than 3 corners into triangles first (as bpm-simplify's "
                 "repair of that name)");
    // The other repairs of bpm-simplify, so that the flags an error names work here too.
    app.add_flag("--merge-duplicate-vertices", read_options.merge_duplicate_vertices,
                 "With --surface: merge vertices with identical coordinates first");
    app.add_flag("--merge-duplicate-triangles", read_options.merge_duplicate_triangles,
                 "With --surface: fuse triangles with the same three vertices into one first");
    app.add_flag("--drop-unreferenced-vertices", read_options.drop_unreferenced_vertices,
                 "With --surface: drop vertices that no triangle uses first");
    bpm::tools::add_format_option(app, surface_format, "input",
                                  "Surface format for --surface when reading '-' (off, obj, stl, ply, msh, vtk, vtp, "
                                  "vtu, surf)");
    bool verbose = false, quiet = false;
    app.add_flag("-v,--verbose", verbose, "More detail on standard error");
    app.add_flag("-q,--quiet", quiet, "Only errors on standard error (the report still goes to standard output)");
    bpm::tools::add_version_flag(app, tool);
    bpm::tools::add_examples(app, {"bpm-check femur.bpm", "bpm-check femur.bpm --max-error 0.005 --json",
                                   "bpm-check --surface femur.off"});

    // With --json every error is a report too (spec/check-report.md, "Errors").
    bpm::tools::set_json_error_report(json, [&](const bpm::tools::ErrorReport& error) {
        return "{\"bpm_check_report\": 1, \"input\": " + bpm::tools::json_string(input) +
               ", \"passed\": false, \"checks\": [], \"error\": " + bpm::tools::error_json(error) + "}";
    });
    return bpm::tools::run(tool, argc, argv, app, [&]() {
        bpm::CheckSelection sel;
        sel.format = sel.intersections = sel.topology = sel.bijectivity = false;
        // distance and quality are run by their limits (--max-error, --max-aspect,
        // --min-angle); named in --checks without one they measure and pass.
        bool want_distance = false, want_quality = false;
        std::stringstream list(checks);
        std::string item;
        while (std::getline(list, item, ',')) {
            if (item == "format") sel.format = true;
            else if (item == "intersections") sel.intersections = true;
            else if (item == "topology") sel.topology = true;
            else if (item == "bijectivity") sel.bijectivity = true;
            else if (item == "replay") sel.replay = true;
            else if (item == "distortion") sel.distortion = true;
            else if (item == "distance") want_distance = true;
            else if (item == "quality") want_quality = true;
            else if (item == "all") sel.format = sel.intersections = sel.topology = sel.bijectivity = sel.distortion = true;
            else
                throw CLI::ValidationError("--checks", "unknown check '" + item +
                                                           "' (known: format, intersections, topology, bijectivity, "
                                                           "distortion, quality, distance, replay, all)");
        }
        sel.original_intersections = original;
        if (replay) sel.replay = true;
        bpm::CheckOptions options;
        options.max_problems = max_problems;
        if (*aspect_opt) options.max_aspect_ratio = max_aspect;
        if (*angle_opt) options.min_angle_degrees = min_angle;
        if (*error_opt) options.max_error = max_error;
        options.error_sample_spacing = error_spacing;
        options.replay_check_interval = replay_interval;
        options.threads = threads;
        const bpm::Context context = bpm::tools::make_context(tool, verbose, quiet || json);

        bpm::CheckReport report;
        if (surface_mode) {
            if (sel.replay) throw CLI::ValidationError("--replay", "replay needs a .bpm file, not --surface");
            if (*error_opt) throw CLI::ValidationError("--max-error", "--max-error needs a .bpm file, not --surface");
            if (sel.format || sel.bijectivity || sel.distortion) {
                if (app.count("--checks"))
                    throw CLI::ValidationError("--checks", "format, bijectivity and distortion need a .bpm file, not --surface");
                sel.format = sel.bijectivity = sel.distortion = false;
            }
            read_options.triangulate_polygons = triangulate_polygons;
            if (!surface_format.empty()) {
                read_options.format = bpm::surface_format_from_name(surface_format);
                if (!read_options.format)
                    throw CLI::ValidationError("--input-format", "unknown surface format '" + surface_format + "'");
            }
            if (want_distance) throw CLI::ValidationError("--checks", "distance needs a .bpm file, not --surface");
            bpm::tools::require_input_format_for_stdin({input}, surface_format);
            const bpm::Surface surface = bpm::read_surface(input, read_options);
            report = bpm::run_surface_checks(surface, sel, options, context);
            if (want_quality && !report.find("quality")) add_in_order(report, bpm::check_quality(surface, options, context));
        } else {
            const bpm::BpmFile file = read_bpm_or_hint(input);
            // distance reads phi, so it needs a structurally sound file.
            if (want_distance && !*error_opt) sel.format = true;
            report = bpm::run_checks(file, sel, options, context);
            if (want_quality && !report.find("quality"))
                add_in_order(report, bpm::check_quality(file.param.coarse, options, context));
            const bpm::CheckResult* format_check = report.find("format");
            if (want_distance && !report.find("distance") && format_check && format_check->passed)
                add_in_order(report, bpm::check_distance(file.param, options, context));
            name_flags(report, sel.replay && !file.simplification_steps);
        }
        report.input = input;
        std::cout << (json ? bpm::check_report_to_json(report) : bpm::check_report_to_text(report)) << std::flush;
        return report.passed() ? bpm::tools::kOk : bpm::tools::kCheckFailed;
    });
}
