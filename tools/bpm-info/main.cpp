// bpm-info: what a .bpm file holds (bpm/bpm_info.h), as text or JSON (spec/info-report.md).
#include <cstdio>
#include <iostream>
#include <sstream>

#include "bpm/bpm_info.h"
#include "common/tool_main.h"

namespace {

using bpm::tools::json_string;

std::string json_or_null(const std::string& text) { return text.empty() ? "null" : json_string(text); }

// Doubles: round-trip precision in JSON, three digits for people.
using bpm::tools::round_trip_text;
using bpm::tools::three_digit_text;

std::string json_strings(const std::vector<std::string>& items) {
    std::string out = "[";
    for (size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + json_string(items[i]);
    return out + "]";
}

// spec/info-report.md: the keys in this order; absent things are null or [].
std::string to_json(const bpm::BpmInfo& info) {
    std::ostringstream o;
    o << "{\"bpm_info\": 1, \"ok\": true, \"file\": " << json_string(info.file) << ", \"file_bytes\": "
      << (info.file_bytes < 0 ? std::string("null") : std::to_string(info.file_bytes)) << ",\n"
      << " \"format_version\": [" << info.format_version.major << ", " << info.format_version.minor
      << "], \"units\": " << json_or_null(info.units) << ",\n"
      << " \"original\": {\"vertices\": " << info.original_vertices << ", \"triangles\": " << info.original_triangles
      << ", \"point_data\": " << json_strings(info.original_point_data) << "},\n"
      << " \"coarse\": {\"vertices\": " << info.coarse_vertices << ", \"triangles\": " << info.coarse_triangles
      << "},\n"
      << " \"phi\": {\"nodes\": " << info.phi_nodes << ", \"pieces\": " << info.phi_pieces << "},\n"
      << " \"patches\": [";
    for (size_t i = 0; i < info.patches.size(); ++i) {
        const bpm::BpmPatchSummary& p = info.patches[i];
        o << (i ? ",\n   " : "\n   ") << "{\"id\": " << p.id << ", \"name\": "
          << (p.info ? json_or_null(p.info->name) : "null")
          << ", \"front_material\": " << (p.info ? json_or_null(p.info->front) : "null")
          << ", \"back_material\": " << (p.info ? json_or_null(p.info->back) : "null")
          << ", \"oriented\": " << (p.info ? (p.info->oriented ? "true" : "false") : "null")
          << ", \"original_triangles\": " << p.original_triangles << ", \"coarse_triangles\": " << p.coarse_triangles
          << "}";
    }
    o << "],\n \"materials\": " << json_strings(info.materials) << ",\n \"tetmesh\": ";
    if (!info.tetmesh) {
        o << "null";
    } else {
        const bpm::BpmTetMeshSummary& t = *info.tetmesh;
        o << "{\"vertices\": " << t.vertices << ", \"tetrahedra\": " << t.tetrahedra
          << ", \"boundary_faces\": " << t.boundary_faces << ", \"level\": " << t.level
          << ", \"materials\": " << json_strings(t.materials) << ", \"regions\": [";
        for (size_t i = 0; i < t.regions.size(); ++i)
            o << (i ? ", " : "") << "{\"id\": " << t.regions[i].id << ", \"tetrahedra\": " << t.regions[i].tetrahedra
              << ", \"material\": " << json_or_null(t.regions[i].material) << "}";
        o << "]}";
    }
    o << ",\n \"simplification_steps\": "
      << (info.simplification_steps ? std::to_string(*info.simplification_steps) : std::string("null"))
      << ",\n \"provenance\": [";
    for (size_t i = 0; i < info.provenance.size(); ++i) {
        const bpm::ProvenanceStep& s = info.provenance[i];
        o << (i ? ",\n   " : "\n   ") << "{\"tool\": " << json_string(s.tool) << ", \"version\": "
          << json_string(s.version) << ", \"arguments\": " << json_string(s.arguments)
          << ", \"timestamp\": " << json_or_null(s.timestamp) << "}";
    }
    const bpm::BpmFeatureSummary& f = info.features;
    o << "],\n \"features\": {\"feature_angle_degrees\": " << round_trip_text(f.feature_angle_degrees)
      << ", \"boundary_edges\": " << f.boundary_edges << ", \"non_manifold_edges\": " << f.non_manifold_edges
      << ", \"interface_edges\": " << f.interface_edges << ", \"crease_edges\": " << f.crease_edges
      << ", \"feature_edges\": " << f.feature_edges << ", \"feature_vertices\": " << f.feature_vertices
      << ", \"feature_lines\": " << f.feature_lines << ", \"feature_loops\": " << f.feature_loops
      << ", \"topological_feature_vertices\": " << f.topological_feature_vertices
      << ", \"topological_feature_lines\": " << f.topological_feature_lines
      << ", \"crease_chain_angle_degrees\": " << round_trip_text(f.crease_chain_angle_degrees)
      << ", \"crease_chain_length\": " << round_trip_text(f.crease_chain_length)
      << ", \"chain_crease_edges\": " << f.chain_crease_edges << "},\n"
      << " \"distortion\": ";
    if (!info.distortion) {
        o << "null";
    } else {
        const bpm::BpmDistortionSummary& d = *info.distortion;
        o << "{\"pieces\": " << d.pieces << ", \"degenerate_pieces\": " << d.degenerate_pieces
          << ",\n  \"area_squeeze_p50\": " << round_trip_text(d.area_squeeze_p50)
          << ", \"area_squeeze_p99\": " << round_trip_text(d.area_squeeze_p99)
          << ", \"area_squeeze_max\": " << round_trip_text(d.area_squeeze_max)
          << ",\n  \"normal_deviation_degrees_p50\": " << round_trip_text(d.normal_deviation_degrees_p50)
          << ", \"normal_deviation_degrees_p99\": " << round_trip_text(d.normal_deviation_degrees_p99)
          << ", \"normal_deviation_degrees_max\": " << round_trip_text(d.normal_deviation_degrees_max)
          << ",\n  \"pieces_turned_over_60_degrees\": " << d.pieces_turned_over_60_degrees
          << ", \"pieces_turned_over_90_degrees\": " << d.pieces_turned_over_90_degrees
          << ", \"coarse_triangles_with_pieces_over_60_degrees\": " << d.coarse_triangles_with_pieces_over_60_degrees
          << ", \"coarse_triangles_with_pieces_over_90_degrees\": " << d.coarse_triangles_with_pieces_over_90_degrees
          << "}";
    }
    o << "}\n";
    return o.str();
}

std::string bytes_text(int64_t bytes) {
    if (bytes < 0) return "standard input";
    char buffer[64];
    if (bytes < 10000) std::snprintf(buffer, sizeof buffer, "%lld bytes", (long long)bytes);
    else if (bytes < 10000000) std::snprintf(buffer, sizeof buffer, "%.1f kB (%lld bytes)", bytes / 1e3, (long long)bytes);
    else std::snprintf(buffer, sizeof buffer, "%.1f MB (%lld bytes)", bytes / 1e6, (long long)bytes);
    return buffer;
}

std::string materials_text(const bpm::PatchInfo& pi) {
    if (pi.front.empty() && pi.back.empty()) return "";
    const std::string front = pi.front.empty() ? "?" : pi.front, back = pi.back.empty() ? "?" : pi.back;
    return pi.oriented ? "front " + front + ", back " + back : "between " + front + " and " + back;
}

std::string to_text(const bpm::BpmInfo& info) {
    std::ostringstream o;
    o << info.file << ": bpm format " << info.format_version.major << "." << info.format_version.minor << ", "
      << bytes_text(info.file_bytes) << ", units " << (info.units.empty() ? "not recorded" : info.units) << "\n";
    o << "original    " << info.original_vertices << " vertices, " << info.original_triangles << " triangles";
    if (!info.original_point_data.empty()) {
        o << "; point data:";
        for (const std::string& name : info.original_point_data) o << " " << name;
    }
    o << "\ncoarse      " << info.coarse_vertices << " vertices, " << info.coarse_triangles << " triangles\n";
    o << "phi         " << info.phi_nodes << " nodes, " << info.phi_pieces << " pieces\n";
    o << "patches     " << info.patches.size() << "\n";
    for (const bpm::BpmPatchSummary& p : info.patches) {
        o << "  " << p.id << ":";
        if (p.info && !p.info->name.empty()) o << " \"" << p.info->name << "\"";
        if (p.info && !materials_text(*p.info).empty()) o << " (" << materials_text(*p.info) << ")";
        o << " " << p.original_triangles << " original, " << p.coarse_triangles << " coarse triangles";
        // Only /patch_info names it: files written before the reader dropped the row of a
        // patch whose triangles --merge-duplicate-triangles all fused into another have one.
        if (p.original_triangles == 0 && p.coarse_triangles == 0)
            o << " (empty: the file names this patch but has no triangles in it, e.g. all were fused into an "
                 "interface patch)";
        o << "\n";
    }
    const bpm::BpmFeatureSummary& f = info.features;
    // Every feature line, creases included, and of them the topological ones, the numbers
    // bpm-check's topology line gives (its "topological feature lines"), so that the two
    // tools' outputs can be read side by side.
    o << "features    " << f.feature_lines << (f.feature_lines == 1 ? " line" : " lines");
    if (f.feature_loops > 0) o << " (" << f.feature_loops << " closed)";
    o << ", " << f.feature_vertices << (f.feature_vertices == 1 ? " vertex" : " vertices") << " of the coarse surface; "
      << f.feature_edges << " feature edges: " << f.crease_edges << " creases ";
    if (f.chain_crease_edges > 0)  // some below the feature angle, on long lines (--crease-chain-angle)
        o << "(" << f.crease_edges - f.chain_crease_edges << " over " << three_digit_text(f.feature_angle_degrees)
          << " degrees, " << f.chain_crease_edges << " over " << three_digit_text(f.crease_chain_angle_degrees)
          << " on long lines)";
    else
        o << "over " << three_digit_text(f.feature_angle_degrees) << " degrees";
    o << ", " << f.interface_edges << " on patch borders, "
      << f.boundary_edges << " boundary, " << f.non_manifold_edges << " non-manifold; without the creases "
      << f.topological_feature_lines << " topological feature " << (f.topological_feature_lines == 1 ? "line" : "lines")
      << " and " << f.topological_feature_vertices << " topological feature "
      << (f.topological_feature_vertices == 1 ? "vertex" : "vertices") << " (bpm-check's)\n";
    o << "materials   ";
    if (info.materials.empty()) o << "none recorded";
    for (size_t i = 0; i < info.materials.size(); ++i) o << (i ? ", " : "") << info.materials[i];
    o << "\ntet mesh    ";
    if (!info.tetmesh) {
        o << "none (bpm-mesh makes one)\n";
    } else {
        const bpm::BpmTetMeshSummary& t = *info.tetmesh;
        o << t.vertices << " vertices, " << t.tetrahedra << " tetrahedra, " << t.boundary_faces
          << " boundary faces, refinement level " << t.level << ", " << t.regions.size()
          << (t.regions.size() == 1 ? " region" : " regions") << "\n";
        for (const bpm::BpmRegionSummary& r : t.regions) {
            o << "  region " << r.id << ": " << r.tetrahedra << " tetrahedra";
            if (!r.material.empty()) o << ", material " << r.material;
            o << "\n";
        }
    }
    o << "steps       "
      << (info.simplification_steps ? std::to_string(*info.simplification_steps) + " removals recorded"
                                    : std::string("not recorded (bpm-simplify --record-steps)"))
      << "\n";
    o << "distortion  ";
    if (!info.distortion) {
        o << "not measured (bpm-info --distortion)\n";
    } else {
        const bpm::BpmDistortionSummary& d = *info.distortion;
        o << d.pieces << " pieces, area squeeze p50 " << three_digit_text(d.area_squeeze_p50) << " p99 "
          << three_digit_text(d.area_squeeze_p99) << " max " << three_digit_text(d.area_squeeze_max)
          << ", normal deviation p50 " << three_digit_text(d.normal_deviation_degrees_p50) << " p99 "
          << three_digit_text(d.normal_deviation_degrees_p99) << " max "
          << three_digit_text(d.normal_deviation_degrees_max)
          << " degrees\n            " << d.pieces_turned_over_60_degrees << " pieces turned over 60 degrees, "
          << d.pieces_turned_over_90_degrees << " over 90 (on " << d.coarse_triangles_with_pieces_over_60_degrees
          << " and " << d.coarse_triangles_with_pieces_over_90_degrees << " coarse triangles)\n";
    }
    o << "provenance  " << info.provenance.size() << (info.provenance.size() == 1 ? " step" : " steps") << "\n";
    for (size_t i = 0; i < info.provenance.size(); ++i) {
        const bpm::ProvenanceStep& s = info.provenance[i];
        o << "  " << i + 1 << ". " << s.version << ", " << (s.timestamp.empty() ? "no date (--deterministic)" : s.timestamp)
          << "\n     " << s.arguments << "\n";
    }
    return o.str();
}

}  // namespace

int main(int argc, char** argv) {
    const std::string tool = "bpm-info";
    CLI::App app{
        "Say what a .bpm file holds: format version, size, the original and the coarse surface, phi, the\n"
        "patches with their names and materials, the tetrahedral mesh (bpm-mesh) with its regions, the\n"
        "recorded simplification steps and the provenance (which tool made it, with which command line, when),\n"
        "the feature lines and vertices of the coarse surface and, with --distortion, how far phi is from an\n"
        "isometry. Reads only what it reports; bpm-check validates.\n"
        "Feature lines are chains of feature edges: boundary, non-manifold and patch-border edges (the\n"
        "topological ones, which bpm-check's topology check compares) and creases over --feature-angle\n"
        "(or over --crease-chain-angle on long, even lines, bpm-simplify's rule applied to the coarse surface).\n"
        "Its feature vertices are the coarse surface's (bpm-check's irregular vertices and every end or junction\n"
        "of a crease), not the vertices bpm-simplify kept as corners: it decides those once, on the original\n"
        "surface, and counts a crease only where it runs 2.5 % of the diagonal from the vertex and ends at a\n"
        "sharp cone or meets two other feature edges. On noisy scans the two differ most (femur at 10 %: 128\n"
        "feature vertices here, 3 kept; bpm-simplify -v says how many it kept).",
        tool};
    std::string input;
    bool json = false, verbose = false, quiet = false;
    bpm::BpmInfoOptions options;
    app.add_option("FILE", input, "Input .bpm file (also .bpm.gz), or - for standard input")->required();
    app.add_flag("--distortion", options.distortion,
                 "Also measure phi's distortion (area squeeze, normal deviation, turned pieces) as bpm-check does; "
                 "reads the whole file");
    app.add_option("--feature-angle", options.feature_angle_degrees,
                   "Edges of the coarse surface sharper than this count as creases, in degrees (180: none)")
        ->default_val(60.0)
        ->check(CLI::Range(0.0, 180.0));
    app.add_option("--crease-chain-angle", options.crease_chain_angle_degrees,
                   "Also count edges sharper than this that line up into one long, smooth, even crease, in degrees "
                   "(180: none; bpm-simplify's rule)")
        ->default_val(20.0)
        ->check(CLI::Range(0.0, 180.0));
    app.add_option("--crease-chain-length", options.crease_chain_length,
                   "How long such a line must be, as a fraction of the bounding-box diagonal")
        ->default_val(0.1)
        ->check(CLI::Range(0.0, 1.0));
    app.add_flag("--json", json, "Print the summary as JSON on standard output (format: spec/info-report.md)");
    app.add_flag("-v,--verbose", verbose, "More detail on standard error (none so far)");
    app.add_flag("-q,--quiet", quiet, "Only errors on standard error (the summary still goes to standard output)");
    bpm::tools::add_version_flag(app, tool);
    bpm::tools::group_options(app, "Measures",
                              {"--distortion", "--feature-angle", "--crease-chain-angle", "--crease-chain-length"});
    bpm::tools::group_options(app, "Output", {"--json", "--verbose", "--quiet"});
    bpm::tools::add_examples(app, {"bpm-info femur.bpm", "bpm-info femur.tet.bpm --json | jq .tetmesh.regions",
                                   "bpm-info femur.bpm --distortion --json | jq .distortion"});

    bpm::tools::set_json_error_report(json, [&](const bpm::tools::ErrorReport& error) {
        return "{\"bpm_info\": 1, \"ok\": false, \"file\": " + bpm::tools::json_string(input) +
               ", \"error\": " + bpm::tools::error_json(error) + "}";
    });
    return bpm::tools::run(tool, argc, argv, app, [&]() {
        bpm::BpmInfo info;
        try {
            info = bpm::read_bpm_info(input, options);
        } catch (const bpm::InputError& e) {
            bpm::tools::rethrow_with_mesh_file_hint(e, input);
        }
        bpm::tools::end_progress_line();
        std::cout << (json ? to_json(info) : to_text(info)) << std::flush;
        return int(bpm::tools::kOk);
    });
}
