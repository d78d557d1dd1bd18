// bpm-simplify: coarse surface + bijective parametrization from a triangulated surface.
#include <cstdio>
#include <iostream>
#include <utility>

#include "bpm/bpm_file.h"
#include "bpm/check.h"
#include "bpm/simplify.h"
#include "bpm/surface_io.h"
#include "common/tool_main.h"

int main(int argc, char** argv) {
    const std::string tool = "bpm-simplify";
    CLI::App app{
        "Simplify a triangulated surface by point removal, keeping a bijective piecewise-linear map phi from\n"
        "the coarse surface onto the original (Krause & Sander). Writes a .bpm file (spec/bpm-format.md).\n"
        "Stops at the first of --vertices / --ratio / --max-error that is reached.",
        tool};
    std::vector<std::string> inputs;
    std::string output, format;
    bpm::SimplifyOptions options;
    bpm::SurfaceReadOptions read_options;
    bool verbose = false, quiet = false, allow_intersections = false, deterministic = false;
    std::string units;
    app.add_option("INPUT", inputs,
                   "Input surface (.off .obj .stl .ply .msh .vtk .vtp .vtu .surf), or - for standard input. Several inputs "
                   "(e.g. one closed surface per material) are simplified together as one surface; the patches of "
                   "different inputs are kept apart")
        ->required();
    app.add_option("-o,--output", output, "Output .bpm file, or - for standard output")->required();
    bpm::tools::add_format_option(app, format, "input",
                                  "Input format when it cannot be told from the name (needed for standard input): off, "
                                  "obj, stl, ply, msh, vtk (legacy VTK), vtp, vtu (VTK XML), surf (Amira HyperSurface)");
    app.add_option("--vertices", options.target_vertices, "Stop when the coarse surface has this many vertices")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--ratio", options.target_ratio,
                   "Stop at this fraction of the input vertices (0..1; e.g. 0.1 keeps 10%)")
        ->check(bpm::tools::decimal_range(0.0, 1.0, true, false, "0.1"));
    app.add_option("--max-error", options.max_error,
                   "Never let max |phi(x) - x| exceed this fraction of the bounding-box diagonal (e.g. 0.005)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--max-edge-length", options.max_edge_length,
                   "Longest edge a removal may create, as a fraction of the bounding-box diagonal")
        ->check(CLI::PositiveNumber);
    app.add_option("--max-aspect", options.max_aspect_ratio,
                   "Refuse removals that create a triangle with circumradius/inradius above this (2 = equilateral; "
                   "default 30), unless the removed triangles were worse")
        ->check(CLI::Range(2.0, 1e300));
    app.add_option("--max-normal-deviation", options.max_normal_deviation_degrees,
                   "Refuse removals after which some coarse triangle would carry a piece of the original surface "
                   "turned by more than this many degrees from it (angle between the normals; above 90 the original "
                   "folds back over the coarse triangle). Such pieces are squeezed by phi, and surfaces refined "
                   "through phi converge to them slowly. Default 180 = off")
        ->check(CLI::Range(0.0, 180.0));
    app.add_option("--distortion-weight", options.distortion_weight,
                   "Weight of phi's distortion in the cost: removals that leave a piece of the original turned more "
                   "than 45 degrees from its coarse triangle cost more, those past --fold-limit come after all others "
                   "(e.g. 0.3; default 0 = off: it cost up to 1.22x the Hausdorff distance at 10 %)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--fold-limit", options.fold_limit_degrees,
                   "Removals turning a piece of the original more than this many degrees from its coarse triangle "
                   "(a fold of phi) are made only when the target cannot be reached otherwise (default 180 = off: 90 "
                   "costs up to 4.6x the Hausdorff distance on scanned surfaces)")
        ->check(CLI::Range(0.0, 180.0));
    app.add_option("--aspect-weight", options.aspect_weight,
                   "Weight of triangle shape (circumradius/inradius) against geometric error in the cost (default 1)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--queue-tolerance", options.queue_tolerance,
                   "Remove the best candidate at once if its full cost is at most this fraction above the next "
                   "candidate's estimate, instead of putting it back in the queue (default 0.1; 0 with "
                   "--one-removal-per-step = strict cost order, a few percent slower, results about as good)")
        ->check(CLI::Range(0.0, 10.0));
    bool one_removal_per_step = false;
    app.add_flag("--one-removal-per-step", one_removal_per_step,
                 "Remove one vertex per step. By default a step also removes the best of the next few candidates "
                 "outside the first one's neighbourhood when the first removal leaves its plan unchanged; the two "
                 "share the threads' work (about 10 % faster, results about as good)");
    app.add_option("--feature-angle", options.feature_angle_degrees,
                   "Keep edges whose normals differ by more than this many degrees as feature lines (default 60; "
                   "180 = off). Boundaries, patch borders and edges of 3 or more sheets are always kept")
        ->check(CLI::Range(0.0, 180.0));
    bool no_keep_corners = false;
    app.add_flag("--no-keep-corners", no_keep_corners,
                 "Let corners of creases go when the error allows. By default a vertex where three or more sharp "
                 "edges (creases, boundaries, patch borders) meet, such as a corner of a box, or where a crease ends "
                 "at a sharp tip, is never removed, like the ends and junctions of boundaries and patch borders; "
                 "a vertex target below their number is then not reached (the summary says so)");
    app.add_flag("--allow-intersections", allow_intersections,
                 "Do not refuse removals that make the surface intersect itself (faster; output may be unusable "
                 "for mesh generators)");
    bool allow_bad_input = false;
    app.add_flag("--allow-self-intersecting-input", allow_bad_input,
                 "Simplify an input that intersects itself instead of refusing it (the output will intersect "
                 "itself too and fail bpm-check)");
    app.add_flag("--merge-duplicate-vertices", read_options.merge_duplicate_vertices,
                 "Repair: merge input vertices with identical coordinates (reported)");
    app.add_flag("--merge-duplicate-triangles", read_options.merge_duplicate_triangles,
                 "Repair: fuse triangles with the same three vertices into one; with one closed surface per material "
                 "(and --merge-duplicate-vertices) each shared interface becomes a patch of its own (reported)");
    app.add_flag("--drop-unreferenced-vertices", read_options.drop_unreferenced_vertices,
                 "Repair: drop input vertices that no triangle uses (reported)");
    app.add_flag("--triangulate-polygons", read_options.triangulate_polygons,
                 "Repair: split faces with more than 3 corners (OFF, OBJ, PLY, VTK; e.g. quads of CAD exports) into "
                 "triangles by ear clipping in the face's plane (reported)");
    app.add_option("--units", units, "Length unit of the coordinates, recorded in the file (e.g. mm)");
    app.add_option("--threads", options.threads,
                   "Threads (default 0 = automatic: 2 unless every core is busy, judged by the 1-minute load average; "
                   "else 1). Two take about 1.2x less time and 1.5x more CPU time; the output does not depend on it")
        ->check(CLI::Range(0, 64));
    app.add_flag("--trace", options.trace_removals, "With -v: one line per removed vertex (cost, error, aspect ratio)");
    app.add_flag("--record-steps", options.record_steps,
                 "Store the sequence of removals in the file (/simplification_steps, spec/bpm-format.md), so that "
                 "bpm-check --replay can re-apply and verify them");
    bpm::tools::add_output_tool_flags(app, tool, deterministic, verbose, quiet);
    bpm::tools::add_examples(app, {"bpm-simplify femur.off -o femur.bpm --ratio 0.1",
                                   "bpm-simplify bone.stl marrow.stl -o bone.bpm --vertices 2000 "
                                   "--merge-duplicate-vertices --merge-duplicate-triangles",
                                   "cat femur.off | bpm-simplify - --input-format off -o femur.bpm --max-error 0.005"});

    return bpm::tools::run(tool, argc, argv, app, [&]() {
        bpm::tools::require_output_directory(output);
        bpm::tools::require_bpm_output(output, tool);
        bpm::tools::refuse_binary_to_terminal(output, "binary .bpm (HDF5) data");
        bpm::tools::require_input_format_for_stdin(inputs, format);
        if (!format.empty()) {
            read_options.format = bpm::surface_format_from_name(format);
            if (!read_options.format) throw CLI::ValidationError("--input-format", "unknown format '" + format + "'");
        }
        if (options.target_vertices == 0 && options.target_ratio == 0 && !std::isfinite(options.max_error))
            throw CLI::ValidationError("give at least one of --vertices, --ratio, --max-error");
        options.prevent_intersections = !allow_intersections;
        options.keep_corners = !no_keep_corners;
        options.batch_removals = !one_removal_per_step;
        options.reject_self_intersecting_input = !allow_bad_input;
        const bpm::Context context = bpm::tools::make_context(tool, verbose, quiet);

        bpm::SurfaceReadReport report;
        const bpm::Surface surface = bpm::read_surfaces(inputs, read_options, &report);
        for (const auto& note : report.notes) context.info(note);
        context.info("read " + std::to_string(surface.num_vertices()) + " vertices, " +
                     std::to_string(surface.num_triangles()) + " triangles");
        // A target the input already meets is a no-op: say so rather than "3897 -> 3897".
        // The first target reached stops the run, so one the input meets stops it at once.
        if (options.target_ratio >= 1.0)
            context.warn("--ratio 1 keeps all " + std::to_string(surface.num_vertices()) +
                         " vertices: nothing will be removed");
        else if (options.target_vertices > 0 && options.target_vertices >= surface.num_vertices())
            context.warn("--vertices " + std::to_string(options.target_vertices) + " is not below the input's " +
                         std::to_string(surface.num_vertices()) +
                         " vertices: nothing will be removed (use a smaller --vertices or --ratio)");

        // What the input says about its patches: with -v (the default output stays at two lines).
        for (size_t i = 0; i < report.patch_info.size() && i < 20; ++i) {
            const bpm::PatchInfo& p = report.patch_info[i];
            context.debug("patch " + std::to_string(p.patch) + " '" + p.name + "': " +
                         (p.front.empty() && p.back.empty() ? std::string("no materials")
                          : p.oriented ? "front " + (p.front.empty() ? "?" : p.front) + ", back " +
                                             (p.back.empty() ? "?" : p.back)
                                       : "between " + p.front + " and " + p.back + " (sides not known)"));
        }

        bpm::BpmFile file;
        file.patch_info = report.patch_info;
        bpm::SimplifyResult result = bpm::simplify(surface, options, context, file.param);
        file.simplification_steps = std::move(result.steps);
        file.units = units;
        file.provenance.push_back({tool, bpm::tools::version_line(tool), bpm::tools::command_line(argc, argv),
                                   deterministic ? std::string() : bpm::tools::utc_timestamp()});
        bpm::write_bpm(output, file);

        // phi's worst distortion (bpm-check's distortion check, spec/check-report.md).
        const bpm::CheckResult distortion = bpm::check_distortion(file.param);
        const int64_t folds = distortion.count("pieces_turned_over_90_degrees");
        const double turn = distortion.worst ? distortion.worst->value : 0.0;
        char line[640];
        std::snprintf(line, sizeof line,
                      "%lld -> %lld vertices (%lld triangles), max error %.3g of diagonal, worst aspect ratio %.3g, "
                      "phi turns pieces by up to %.3g degrees (%lld > 90), %.2f s (%d %s)",
                      (long long)result.input_vertices, (long long)result.output_vertices,
                      (long long)result.output_triangles, result.max_error, result.worst_aspect_ratio, turn,
                      (long long)std::max<int64_t>(folds, 0), result.seconds, result.threads,
                      result.threads == 1 ? "thread" : "threads");
        context.info(line);
        // The kept feature vertices matter when they stopped the simplifier (said next to
        // the warning below); otherwise they are a detail for -v.
        if (result.kept_feature_vertices() > 0) {
            const std::string kept = std::to_string(result.kept_feature_vertices()) + " feature vertices kept (" +
                         std::to_string(result.line_feature_vertices) +
                         " ends or junctions of boundaries, patch borders or non-manifold lines" +
                         (result.corners_kept ? ", " + std::to_string(result.crease_junctions) +
                                                    " corners where three or more feature edges meet, " +
                                                    std::to_string(result.crease_cone_ends) +
                                                    " ends of creases at sharp cones"
                                              : std::string()) +
                         ")";
            if (result.target_reached) context.debug(kept);
            else context.info(kept);
        }
        if (!result.target_reached) {
            context.warn("stopped before the target: " + result.stop_reason);
            for (const auto& [why, count] : result.blocked)
                context.warn("  " + std::to_string(count) + " vertices kept: " + why);
            if (result.corners_kept && result.crease_junctions + result.crease_cone_ends > 0 &&
                std::max<int64_t>(options.target_vertices, int64_t(std::ceil(options.target_ratio * double(result.input_vertices)))) < result.kept_feature_vertices())
                context.warn("  (--no-keep-corners lets the corners of creases go)");
        }
        return int(bpm::tools::kOk);
    });
}
