// bpm-simplify: coarse surface + bijective parametrization from a triangulated surface.
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <utility>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/check.h"
#include "bpm/self_intersection_repair.h"
#include "bpm/simplify.h"
#include "bpm/surface_io.h"
#include "common/tool_main.h"

namespace {

// The library names SimplifyOptions fields in its errors and reasons; a user of this tool
// knows them by their flags.
std::string with_flags(std::string text) {
    static const std::pair<const char*, const char*> kFlags[] = {
        {"set reject_self_intersecting_input = false", "use --allow-self-intersecting-input"},
        {"repair_self_intersections()", "rerun with --repair-self-intersections, which"},
        {"max_normal_deviation_degrees", "--max-normal-deviation"},
        {"max_change =", "--max-repair-change"},
        {"feature_angle_degrees", "--feature-angle"},
        {"crease_chain_angle_degrees", "--crease-chain-angle"},
        {"crease_chain_length", "--crease-chain-length"},
        {"fold_limit_degrees", "--fold-limit"},
        {"fold_weight", "--fold-weight"},
        {"distortion_weight", "--distortion-weight"},
        {"max_aspect_ratio", "--max-aspect"},
        {"min_ridge_angle_degrees", "--min-ridge-angle"},
        {"flip_min_dihedral_degrees", "--flip-min-dihedral"},
        {"max_edge_length", "--max-edge-length"},
        {"queue_tolerance", "--queue-tolerance"},
        {"target_vertices", "--vertices"},
        {"target_ratio", "--ratio"},
        {"max_error", "--max-error"},
    };
    for (const auto& [field, flag] : kFlags)
        for (size_t at = text.find(field); at != std::string::npos; at = text.find(field, at + 1))
            text.replace(at, std::string(field).size(), flag);
    return text;
}

// Wall and CPU seconds per phase, for -v (issue 21: the floor broken down without a
// profiler): the tool's own phases (reading, writing, the distortion report) around the
// library's (SimplifyResult::phases). Process CPU time counts every thread (with
// --threads 2 the second one spins between short rounds).
class PhaseClock {
public:
    explicit PhaseClock(std::string first) { start(std::move(first)); }
    void start(std::string name) {
        end();
        const auto [wall, cpu] = now();
        phases_.push_back({std::move(name), wall, cpu});
        open_ = true;
    }
    // Ends the current phase (before the library call, whose phases it measures itself).
    void end() {
        if (!open_) return;
        const auto [wall, cpu] = now();
        phases_.back().wall_seconds = wall - phases_.back().wall_seconds;
        phases_.back().cpu_seconds = cpu - phases_.back().cpu_seconds;
        open_ = false;
    }
    // The library's phases, measured by it, after the tool's so far.
    void add(const std::vector<bpm::SimplifyPhaseTime>& phases) {
        end();
        phases_.insert(phases_.end(), phases.begin(), phases.end());
    }
    // One line per phase and the total. Ends the current phase.
    std::vector<std::string> lines() {
        end();
        std::vector<std::string> out;
        double wall = 0, cpu = 0;
        char line[160];
        for (const bpm::SimplifyPhaseTime& p : phases_) {
            // e.g. the moment before the check when the set-up runs beside it (--threads 2)
            if (p.wall_seconds < 0.0005 && p.cpu_seconds < 0.0005) continue;
            std::snprintf(line, sizeof line, "time: %-40s %8.3f s wall %8.3f s CPU", p.name.c_str(), p.wall_seconds,
                          p.cpu_seconds);
            out.push_back(line);
            wall += p.wall_seconds;
            cpu += p.cpu_seconds;
        }
        std::snprintf(line, sizeof line, "time: %-40s %8.3f s wall %8.3f s CPU", "total (from reading)", wall, cpu);
        out.push_back(line);
        return out;
    }

private:
    std::vector<bpm::SimplifyPhaseTime> phases_;  // start times while open, then durations
    bool open_ = false;
    static std::pair<double, double> now() {
        timespec w{}, c{};
        clock_gettime(CLOCK_MONOTONIC, &w);
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c);
        return {double(w.tv_sec) + 1e-9 * double(w.tv_nsec), double(c.tv_sec) + 1e-9 * double(c.tv_nsec)};
    }
};

// "1 triangle", "2 triangles".
std::string count(int64_t n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
}

// What --repair-self-intersections did, in a line or two.
void report_repair(const bpm::SelfIntersectionRepair& r, const bpm::Context& context) {
    const std::string pairs = count(r.intersecting_pairs, "intersecting pair", "intersecting pairs");
    if (r.intersecting_pairs == 0) {
        context.info("--repair-self-intersections: the input does not intersect itself; nothing to repair");
        return;
    }
    if (!r.refused.empty()) {
        context.warn("--repair-self-intersections: the input has " + pairs + " and was left as it is: " +
                     with_flags(r.refused));
        return;
    }
    char change[64];
    std::snprintf(change, sizeof change, "%.3g", r.largest_change);
    context.info("--repair-self-intersections: " + pairs + ", " + std::to_string(r.remaining_pairs) + " left; " +
                 count(r.removed_triangles, "triangle", "triangles") + " replaced by " +
                 std::to_string(r.added_triangles) + " (" + count(r.added_vertices, "new vertex", "new vertices") +
                 ", " + count(r.removed_vertices, "vertex", "vertices") + " gone); the surface moved by about " +
                 change + " of the bounding-box diagonal, and phi maps onto the repaired surface");
    if (!r.topology_change.empty())
        context.warn("--repair-self-intersections changed the topology: " + r.topology_change);
    if (r.remaining_pairs > 0)
        context.warn("--repair-self-intersections: " + count(r.remaining_pairs, "intersecting pair", "intersecting pairs") +
                     " of the input could not be repaired locally");
}

}  // namespace

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
    // Help: one plain line per option (default and unit in it), grouped by what a user
    // wants to set; the tuning internals under "Advanced".
    app.add_option("INPUT", inputs,
                   "Input surface(s): .off .obj .stl .ply .msh .vtk .vtp .vtu .surf, a label image .nii (.nii.gz) .nrrd .mha .mhd, or -; "
                   "several (one per "
                   "material) are simplified as one")
        ->required();
    const std::string target = "Target (the first one reached stops)", quality = "Quality",
                      features = "Features", repairs = "Input repairs (each is reported)", output_group = "Output",
                      advanced = "Advanced";
    app.add_option("--vertices", options.target_vertices, "Stop at this many coarse vertices")
        ->check(CLI::NonNegativeNumber)
        ->group(target);
    app.add_option("--ratio", options.target_ratio, "Stop at this fraction of the input vertices (0..1, e.g. 0.1)")
        ->check(bpm::tools::decimal_range(0.0, 1.0, true, false, "0.1"))
        ->group(target);
    app.add_option("--max-error", options.max_error,
                   "Stop before max |phi(x) - x| exceeds this (fraction of the bounding-box diagonal, e.g. 0.005)")
        ->check(CLI::NonNegativeNumber)
        ->group(target);
    app.add_option("--max-aspect", options.max_aspect_ratio,
                   "Refuse new triangles with circumradius/inradius above this, and remove the input's worse ones first where possible (default 30; 2 = equilateral)")
        ->check(bpm::tools::aspect_ratio_limit())
        ->group(quality);
    bool no_flips = false;
    app.add_flag("--no-flips", no_flips,
                 "Do not flip edges of needles (and of thin tetrahedra, --flip-min-dihedral) at the end")
        ->group(quality);
    app.add_option("--flip-min-dihedral", options.flip_min_dihedral_degrees,
                   "Flip convex edges whose tetrahedron with their two triangles has a dihedral angle below this "
                   "(degrees; default 0 = needles only, e.g. 6)")
        ->check(CLI::Range(0.0, 60.0))
        ->group(quality);
    app.add_option("--max-edge-length", options.max_edge_length,
                   "Longest edge a removal may create (fraction of the bounding-box diagonal; default none)")
        ->check(CLI::PositiveNumber)
        ->group(quality);
    app.add_option("--max-normal-deviation", options.max_normal_deviation_degrees,
                   "Refuse coarse triangles whose piece of the original turns more than this (degrees; default 180 = off)")
        ->check(CLI::Range(0.0, 180.0))
        ->group(quality);
    app.add_option("--min-ridge-angle", options.min_ridge_angle_degrees,
                   "Refuse removals and the final edge flips that leave a coarse edge (not a feature line) folded "
                   "sharper than this, or than the original's sharpest edge where it lies minus 5 (degrees: interior "
                   "angle of a convex edge, exterior of a concave one; default 30, 0 = off); on feature lines, the wedges between sheets are kept "
                   "at least 15 degrees wide at junctions and 5 elsewhere, or not made thinner than they are, and no new triangle "
                   "comes closer than 0.1 % of its size to another sheet (1 % with two or more patches); with two or more patches, "
                   "no two triangles with one common corner are laid onto each other at less than 4 degrees")
        ->check(CLI::Range(0.0, 90.0))
        ->group(quality);
    app.add_option("--distortion-weight", options.distortion_weight,
                   "Make removals that turn pieces of the original past 45 degrees cost more (e.g. 0.3; default 0 = off)")
        ->check(CLI::NonNegativeNumber)
        ->group(quality);
    app.add_option("--fold-weight", options.fold_weight,
                   "Weight of the fold term: removals that turn a piece of the original past 90 degrees against "
                   "its coarse triangle (a fold of phi, where refining through phi converges slowly) cost "
                   "W * 0.1 % of the diagonal * (angle - 90) / 90 more (default 0 = off)")
        ->check(CLI::Range(0.0, 1000.0))
        ->group(quality);
    app.add_option("--fold-limit", options.fold_limit_degrees,
                   "Turn pieces past this (a fold of phi) only when the target needs it (degrees; default 180 = off)")
        ->check(CLI::Range(0.0, 180.0))
        ->group(quality);
    app.add_flag("--allow-intersections", allow_intersections,
                 "Allow removals that make the surface intersect itself (faster; bad for mesh generators)")
        ->group(quality);
    bool allow_bad_input = false;
    app.add_flag("--allow-self-intersecting-input", allow_bad_input,
                 "Simplify an input that intersects itself (the output will fail bpm-check)")
        ->group(quality);
    app.add_option("--feature-angle", options.feature_angle_degrees,
                   "Keep edges whose normals differ by more than this as feature lines (degrees; default 60, 180 = off; "
                   "shallower creases that run as long lines are kept too, see --crease-chain-angle)")
        ->check(CLI::Range(0.0, 180.0))
        ->group(features);
    app.add_option("--crease-chain-angle", options.crease_chain_angle_degrees,
                   "Also keep shallower edges (normals more than this many degrees apart) where they line up into one "
                   "long, smooth, even crease (8 or more edges in a row), like a CAD part's gently curved edge; the kinks "
                   "of the scans measured (femur, elephant, armadillo) do not (default 20, 180 = off)")
        ->check(CLI::Range(0.0, 180.0))
        ->group(features);
    app.add_option("--crease-chain-length", options.crease_chain_length,
                   "How long such a line must be to count, as a fraction of the bounding-box diagonal (default 0.1)")
        ->check(CLI::Range(0.0, 1.0))
        ->group(features);
    bool no_keep_corners = false;
    app.add_flag("--no-keep-corners", no_keep_corners,
                 "Let corners (3+ sharp edges meeting, crease tips) go when the error allows; by default they stay")
        ->group(features);
    bpm::tools::add_format_option(app, format, "input",
                                  "Input format when the name does not tell (needed for -): off obj stl ply msh vtk "
                                  "vtp vtu surf")
        ->group(repairs);
    app.add_flag("--merge-duplicate-vertices", read_options.merge_duplicate_vertices,
                 "Merge input vertices with identical coordinates")
        ->group(repairs);
    bpm::tools::add_merge_vertices_within_option(app, read_options)->group(repairs);
    app.add_flag("--merge-duplicate-triangles", read_options.merge_duplicate_triangles,
                 "Fuse triangles with the same three vertices (shared interfaces of per-material files become patches)")
        ->group(repairs);
    app.add_flag("--drop-unreferenced-vertices", read_options.drop_unreferenced_vertices,
                 "Drop input vertices that no triangle uses")
        ->group(repairs);
    app.add_flag("--triangulate-polygons", read_options.triangulate_polygons,
                 "Split faces with more than 3 corners (OFF OBJ PLY VTK) into triangles")
        ->group(repairs);
    std::string image_frame = "lps";
    app.add_option("--image-frame", image_frame,
                   "Coordinates of a label image's surface: lps (default; DICOM, ITK, MetaImage, 3D Slicer) or ras "
                   "(NIfTI's); the other frame is turned 180 degrees about z (x, y negated). Recorded in the file")
        ->check(CLI::IsMember({"lps", "ras"}))
        ->group(output_group);
    bool repair_intersections = false, repaired_surface = false;
    bpm::SelfIntersectionRepairOptions repair_options;
    app.add_flag("--repair-self-intersections", repair_intersections,
                 "Replace the triangles where the input crosses itself by local patches (phi maps onto the result)")
        ->group(repairs);
    app.add_option("--max-repair-change", repair_options.max_change,
                   "Refuse a --repair-self-intersections that moves the surface further than this (fraction of the "
                   "diagonal; default 0.01)")
        ->check(CLI::PositiveNumber)
        ->group(repairs);
    app.add_option("-o,--output", output, "Output .bpm file, or - for standard output")->required()->group(output_group);
    app.add_option("--units", units, "Length unit of the coordinates, recorded in the file (e.g. mm)")->group(output_group);
    app.add_flag("--record-steps", options.record_steps,
                 "Store the removals in the file so that bpm-check --replay can verify them")
        ->group(output_group);
    app.add_option("--aspect-weight", options.aspect_weight,
                   "Weight of triangle shape against geometric error in the cost (default 1)")
        ->check(CLI::NonNegativeNumber)
        ->group(advanced);
    app.add_option("--queue-tolerance", options.queue_tolerance,
                   "Remove the best candidate at once if within this fraction of the next one's estimate (default 0.1)")
        ->check(CLI::Range(0.0, 10.0))
        ->group(advanced);
    bool one_removal_per_step = false;
    auto* one_per_step = app.add_flag("--one-removal-per-step", one_removal_per_step,
                                      "One removal per step (same as --removals-per-step 1)")
                             ->group(advanced);
    app.add_option("--removals-per-step", options.removals_per_step,
                   "Removals tried together per step, in queue order with disjoint stars (default 2; 1..64); the "
                   "output depends on it, not on --threads")
        ->check(CLI::Range(1, 64))
        ->excludes(one_per_step)
        ->group(advanced);
    app.add_option("--threads", options.threads,
                   "Threads (default 0 = 2, or 1 for inputs under 10000 triangles or when every core is busy); "
                   "the output does not depend on it")
        ->check(CLI::Range(0, 64))
        ->group(advanced);
    app.add_flag("--trace", options.trace_removals, "With -v: one line per removed vertex (cost, error, aspect ratio)")
        ->group(advanced);
    bpm::tools::add_output_tool_flags(app, tool, deterministic, verbose, quiet);
    bpm::tools::add_examples(app, {"bpm-simplify femur.off -o femur.bpm --ratio 0.1",
                                   "bpm-simplify bone.stl marrow.stl -o bone.bpm --vertices 2000 "
                                   "--merge-duplicate-vertices --merge-duplicate-triangles",
                                   "cat femur.off | bpm-simplify - --input-format off -o femur.bpm --max-error 0.005"});

    return bpm::tools::run(tool, argc, argv, app, [&]() {
        {
            std::string names;  // as the reader names several inputs together
            for (const std::string& in : inputs) names += (names.empty() ? "" : " + ") + (in == "-" ? "<stdin>" : in);
            bpm::tools::set_error_input(names);
        }
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
        options.flip_edges = !no_flips;
        if (one_removal_per_step) options.removals_per_step = 1;
        options.reject_self_intersecting_input = !allow_bad_input;
        bpm::Context context = bpm::tools::make_context(tool, verbose, quiet);
        read_options.context = &context;  // label images: the surface extraction reports progress
        read_options.label_image.frame = image_frame == "ras" ? bpm::ImageFrame::Ras : bpm::ImageFrame::Lps;
        PhaseClock clock("reading");

        bpm::SurfaceReadReport report;
        bpm::Surface surface = bpm::read_surfaces(inputs, read_options, &report);
        for (const auto& note : report.notes) context.info(note);
        for (const auto& warning : report.warnings) context.warn(warning);
        if (std::string seam = bpm::tools::open_seam_warning(report); !seam.empty()) context.warn(seam);
        if (app.count("--image-frame") > 0 && report.frame == bpm::ImageFrame::Unknown)
            context.warn("--image-frame " + image_frame + " did nothing: the input is not a label image in LPS or RAS "
                         "coordinates, so they are used as they are");
        context.info("read " + std::to_string(surface.num_vertices()) + " vertices, " +
                     std::to_string(surface.num_triangles()) + " triangles");
        // bpm::simplify refuses such coordinates too, but the repair would run on them first,
        // and only the tool knows the flag that records the new unit.
        if (const std::string why = bpm::coordinate_range_problem(surface); !why.empty())
            throw bpm::AlgorithmError(why + " (--units records the unit in the file)");
        if (repair_intersections) {
            clock.start("self-intersection repair");
            const bpm::SelfIntersectionRepair repair = bpm::repair_self_intersections(surface, repair_options, context);
            report_repair(repair, context);
            repaired_surface = repair.refused.empty() && repair.removed_triangles + repair.added_triangles > 0;
        }
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
        bpm::SimplifyResult result;
        clock.end();
        try {
            // The surface moves into file.param.original: not held twice while phi is written.
            result = bpm::simplify(std::move(surface), options, context, file.param);
        } catch (const bpm::OptionError& e) {
            throw bpm::OptionError(with_flags(e.what()));
        } catch (const bpm::AlgorithmError& e) {
            std::string message = e.what();
            // After --repair-self-intersections, what is left is for a repair by hand.
            const std::string suggestion = "repair_self_intersections() replaces the triangles around a few local ones";
            if (const size_t at = message.find(suggestion); repair_intersections && at != std::string::npos)
                message.replace(at, suggestion.size(), "--repair-self-intersections could not repair these");
            // Its triangle numbers are those of the surface the repair left.
            if (const size_t at = message.find("the input surface intersects itself"); repaired_surface && at == 0)
                message.replace(0, 35, "the repaired input surface still intersects itself");
            throw bpm::AlgorithmError(with_flags(message));
        }
        file.simplification_steps = std::move(result.steps);
        file.units = units;
        file.coordinate_frame = bpm::image_frame_name(report.frame);
        file.provenance.push_back({tool, bpm::tools::version_line(tool), bpm::tools::command_line(argc, argv),
                                   deterministic ? std::string() : bpm::tools::utc_timestamp()});
        clock.add(result.phases);
        // The summary line is an info line, which -q never shows: its distortion figures (phi's
        // worst turn, bpm-check's distortion check over every piece) would be measured for nothing.
        // Measured before writing, so that the check's memory is free again when the writer
        // takes its buffers (on small inputs the writing is the peak of a run).
        std::string summary;
        if (!quiet) {
            clock.start("distortion of phi (report)");
            const bpm::CheckResult distortion = bpm::check_distortion(file.param);
            const int64_t folds = distortion.count("pieces_turned_over_90_degrees");
            const double turn = distortion.worst ? distortion.worst->value : 0.0;
            char line[640];
            std::snprintf(line, sizeof line,
                          "%lld -> %lld vertices (%lld triangles), max error %.3g of diagonal, worst aspect ratio "
                          "%.3g, phi turns pieces by up to %.3g degrees (%lld pieces over 90), %.2f s (%d %s)",
                          (long long)result.input_vertices, (long long)result.output_vertices,
                          (long long)result.output_triangles, result.max_error, result.worst_aspect_ratio, turn,
                          (long long)std::max<int64_t>(folds, 0), result.seconds, result.threads,
                          result.threads == 1 ? "thread" : "threads");
            summary = line;
        }
        clock.start("writing the .bpm");
        bpm::write_bpm(output, file);
        if (!quiet) context.info(summary);
        if (verbose)
            for (const std::string& l : clock.lines()) context.debug(l);
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
        // Input slivers that stayed (issue 19 item 5): never silently, since bpm-mesh
        // meshes them into flat tetrahedra.
        if (result.slivers > 0) {
            char head[200];
            std::snprintf(head, sizeof head, "%lld coarse triangles have an aspect ratio above --max-aspect %g (input slivers that could not be removed); the worst:",
                          (long long)result.slivers, options.max_aspect_ratio);
            context.warn(head);
            for (const bpm::SliverReport& s : result.worst_slivers) {
                char where[200];
                std::snprintf(where, sizeof where, "  R/r %.3g at (%.6g, %.6g, %.6g), input vertices %d %d %d:",
                              s.aspect_ratio, s.centroid[0], s.centroid[1], s.centroid[2], s.vertices[0],
                              s.vertices[1], s.vertices[2]);
                std::string line = where;
                for (int k = 0; k < 3; ++k)
                    line += (k ? "; " : " ") + std::to_string(s.vertices[size_t(k)]) + " kept: " + with_flags(s.kept[size_t(k)]);
                context.warn(line);
            }
        }
        if (!result.target_reached) {
            context.warn("stopped before the target: " + with_flags(result.stop_reason));
            for (const auto& [why, count] : result.blocked)
                context.warn("  " + std::to_string(count) + (count == 1 ? " vertex" : " vertices") + " kept: " + with_flags(why));
            if (result.corners_kept && result.crease_junctions + result.crease_cone_ends > 0 &&
                std::max<int64_t>(options.target_vertices, int64_t(std::ceil(options.target_ratio * double(result.input_vertices)))) < result.kept_feature_vertices())
                context.warn("  (--no-keep-corners lets the corners of creases go)");
        }
        return int(bpm::tools::kOk);
    });
}
