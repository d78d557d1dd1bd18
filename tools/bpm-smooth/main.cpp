// bpm-smooth: improve phi by edge relaxation (Krause & Sander §2.5); the surfaces do not move.
#include <cstdio>

#include "bpm/bpm_file.h"
#include "bpm/smooth.h"
#include "common/tool_main.h"

int main(int argc, char** argv) {
    const std::string tool = "bpm-smooth";
    CLI::App app{
        "Smooth the parametrization phi of a .bpm file by edge relaxation: for every pair of coarse triangles\n"
        "sharing an edge, re-place the original vertices inside by a shape-preserving (mean value) map and cut\n"
        "along the edge again. The coarse and the original surface do not change; updates that would flip a\n"
        "piece are rejected. Along feature lines and patch borders the original vertices only slide along the edge.",
        tool};
    std::string input, output;
    bpm::SmoothOptions options;
    bool verbose = false, quiet = false, deterministic = false, no_quality = false;
    app.add_option("INPUT", input, "Input .bpm file, or - for standard input")->required();
    app.add_option("-o,--output", output, "Output .bpm file, or - for standard output")->required();
    app.add_option("--iterations", options.iterations, "At most this many sweeps over all pairs (default 10)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--tolerance", options.tolerance,
                   "Stop when no vertex moved more than this in a sweep (fraction of its pair's edge length; "
                   "default 0.001)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--feature-angle", options.feature_angle_degrees,
                   "Leave coarse edges along original edges sharper than this many degrees alone (default 60)")
        ->check(CLI::Range(0.0, 180.0));
    app.add_option("--crease-chain-angle", options.crease_chain_angle_degrees,
                   "Also leave alone those sharper than this many degrees that line up into one long, smooth, even "
                   "crease (default 20, 180 = off; give the value bpm-simplify had)")
        ->check(CLI::Range(0.0, 180.0));
    app.add_option("--crease-chain-length", options.crease_chain_length,
                   "How long such a line must be, as a fraction of the bounding-box diagonal (default 0.1; as "
                   "bpm-simplify)")
        ->check(CLI::Range(0.0, 1.0));
    std::string weights = "mean-value";
    app.add_option("--weights", weights,
                   "Placement of original vertices among their neighbours: mean-value (default) or "
                   "shape-preserving (converges less well)")
        ->check(CLI::IsMember({"shape-preserving", "mean-value"}));
    app.add_flag("--no-quality", no_quality, "Do not measure the refined-triangle quality before and after");
    bpm::tools::add_output_tool_flags(app, tool, deterministic, verbose, quiet);
    bpm::tools::group_options(app, "Output", {"--output"});
    bpm::tools::group_options(app, "Stopping", {"--iterations", "--tolerance"});
    bpm::tools::group_options(app, "Features", {"--feature-angle", "--crease-chain-angle", "--crease-chain-length"});
    bpm::tools::group_options(app, "Advanced", {"--weights", "--no-quality"});
    bpm::tools::add_examples(app, {"bpm-smooth coarse.bpm -o smooth.bpm",
                                   "bpm-smooth coarse.bpm -o smooth.bpm --iterations 20 -v   (with the breakdown)"});

    return bpm::tools::run(tool, argc, argv, app, [&]() {
        bpm::tools::set_error_input(input);
        bpm::tools::require_output_directory(output);
        bpm::tools::require_bpm_output(output, tool);
        bpm::tools::refuse_binary_to_terminal(output, "binary .bpm (HDF5) data");
        // The quality line is an info line, which -q never shows: refining the surface before and
        // after (4^3 triangles per coarse triangle, each placed through phi) would be for nothing.
        options.measure_quality = !no_quality && !quiet;
        options.weights = weights == "shape-preserving" ? bpm::SmoothWeights::ShapePreserving : bpm::SmoothWeights::MeanValue;
        const bpm::Context context = bpm::tools::make_context(tool, verbose, quiet);
        // A no-op that wrote a copy with "0 sweeps" and exit 0 (as bpm-simplify --ratio 1 warns).
        if (options.iterations == 0)
            context.warn("--iterations 0: no sweep, so phi is written out unchanged (give 1 or more; default 10)");
        bpm::BpmFile file = bpm::tools::read_bpm_input(input);
        const bpm::SmoothResult r = bpm::smooth(file.param, options, context);
        file.provenance.push_back({tool, bpm::tools::version_line(tool), bpm::tools::command_line(argc, argv),
                                   deterministic ? std::string() : bpm::tools::utc_timestamp()});
        bpm::write_bpm(output, file);
        char line[512];
        std::snprintf(line, sizeof line,
                      "%d sweeps over %lld pairs (%lld left alone): %lld updates (%lld sliding along feature lines), "
                      "%lld rejected, last move %.3g, %.2f s",
                      r.sweeps, (long long)r.pairs, (long long)r.skipped, (long long)r.updates, (long long)r.slides,
                      (long long)r.rejected, r.last_change, r.seconds);
        context.info(line);
        // The breakdown is for -v: by default every tool prints one or two lines.
        for (const auto& [why, count] : r.skipped_reasons) context.debug("  " + std::to_string(count) + " pairs left alone: " + why);
        for (const auto& [why, count] : r.rejected_reasons) context.debug("  " + std::to_string(count) + " updates rejected: " + why);
        if (options.measure_quality) {
            std::snprintf(line, sizeof line,
                          "aspect ratio of the %d-times refined surface: max %.3g -> %.3g, 99%% %.3g -> %.3g, "
                          "mean %.3g -> %.3g",
                          options.quality_levels, r.before.max_aspect_ratio, r.after.max_aspect_ratio,
                          r.before.p99_aspect_ratio, r.after.p99_aspect_ratio, r.before.mean_aspect_ratio,
                          r.after.mean_aspect_ratio);
            context.info(line);
        }
        return int(bpm::tools::kOk);
    });
}
