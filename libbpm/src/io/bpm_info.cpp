// bpm-info's summary of a .bpm file (bpm/bpm_info.h): counts and names as stored, the
// features of the coarse surface, and phi's distortion when asked for.
#include "bpm/bpm_info.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <system_error>

#include "bpm/check.h"
#include "bpm/errors.h"
#include "core/crease_chains.h"
#include "core/file_util.h"
#include "io/bpm_outline.h"

namespace bpm {

namespace {

// One summary for both ways in (read_bpm_outline, or a whole file in memory).
BpmInfo summarize(const detail::BpmOutline& file, const BpmInfoOptions& options) {
    BpmInfo info;
    info.format_version = file.format_version;
    info.units = file.units;
    info.original_vertices = file.original_vertices;
    info.original_triangles = static_cast<int64_t>(file.original_patches.size());
    info.coarse_vertices = file.coarse.num_vertices();
    info.coarse_triangles = file.coarse.num_triangles();
    info.phi_nodes = file.phi_nodes;
    info.phi_pieces = file.phi_pieces;
    info.original_point_data = file.original_point_data;

    std::map<int32_t, BpmPatchSummary> patches;
    for (const int32_t id : file.original_patches) ++patches[id].original_triangles;
    for (const int32_t id : file.coarse.patches) ++patches[id].coarse_triangles;
    for (const PatchInfo& pi : file.patch_info) patches[pi.patch].info = pi;
    std::set<std::string> materials;
    for (auto& [id, summary] : patches) {
        summary.id = id;
        if (summary.info) {
            if (!summary.info->front.empty()) materials.insert(summary.info->front);
            if (!summary.info->back.empty()) materials.insert(summary.info->back);
        }
        info.patches.push_back(summary);
    }
    info.materials.assign(materials.begin(), materials.end());
    info.features = summarize_features(file.coarse, options.feature_angle_degrees, options.crease_chain_angle_degrees,
                                       options.crease_chain_length);

    if (file.tetmesh) {
        const detail::BpmTetMeshOutline& m = *file.tetmesh;
        BpmTetMeshSummary t;
        t.vertices = m.vertices;
        t.tetrahedra = m.tetrahedra;
        t.boundary_faces = m.faces;
        t.level = m.level;
        t.materials = m.material_names;
        int32_t regions = 0;  // TetMesh::num_regions: the largest region id
        for (const int32_t r : m.regions) regions = std::max(regions, r);
        t.regions.resize(static_cast<size_t>(regions));
        for (int32_t r = 0; r < regions; ++r) {
            t.regions[size_t(r)].id = r + 1;
            if (size_t(r) < m.region_material.size()) {
                const int32_t material = m.region_material[size_t(r)];
                if (material >= 1 && size_t(material) <= m.material_names.size())
                    t.regions[size_t(r)].material = m.material_names[size_t(material) - 1];
            }
        }
        for (const int32_t r : m.regions)
            if (r >= 1 && r <= regions) ++t.regions[size_t(r) - 1].tetrahedra;
        info.tetmesh = std::move(t);
    }
    info.simplification_steps = file.simplification_steps;
    info.provenance = file.provenance;
    return info;
}

// check_distortion's counts and measures, by the names spec/check-report.md gives them.
BpmDistortionSummary distortion_of(const BpmFile& file, const std::string& where) {
    const CheckResult r = check_distortion(file.param);
    if (!r.passed) throw InputError(where, "cannot measure phi's distortion: " + r.summary);
    BpmDistortionSummary d;
    d.pieces = r.count("pieces");
    d.degenerate_pieces = r.count("degenerate_pieces");
    d.pieces_turned_over_60_degrees = r.count("pieces_turned_over_60_degrees");
    d.pieces_turned_over_90_degrees = r.count("pieces_turned_over_90_degrees");
    d.coarse_triangles_with_pieces_over_60_degrees = r.count("coarse_triangles_with_pieces_over_60_degrees");
    d.coarse_triangles_with_pieces_over_90_degrees = r.count("coarse_triangles_with_pieces_over_90_degrees");
    for (const WorstValue& m : r.measures) {
        if (m.name == "area_squeeze_p50") d.area_squeeze_p50 = m.value;
        if (m.name == "area_squeeze_p99") d.area_squeeze_p99 = m.value;
        if (m.name == "area_squeeze_max") d.area_squeeze_max = m.value;
        if (m.name == "normal_deviation_degrees_p50") d.normal_deviation_degrees_p50 = m.value;
        if (m.name == "normal_deviation_degrees_p99") d.normal_deviation_degrees_p99 = m.value;
        if (m.name == "normal_deviation_degrees_max") d.normal_deviation_degrees_max = m.value;
    }
    return d;
}

}  // namespace

BpmInfo summarize_bpm(const BpmFile& file, const BpmInfoOptions& options) {
    BpmInfo info = summarize(detail::outline_of(file), options);
    if (options.distortion) info.distortion = distortion_of(file, "<memory>");
    return info;
}

BpmInfo read_bpm_info(const std::string& path, const BpmInfoOptions& options) {
    // Before the file is read: a bad option is the caller's error whatever the file holds.
    detail::check_crease_rule_numbers(options.feature_angle_degrees, options.crease_chain_angle_degrees,
                                      options.crease_chain_length);
    BpmInfo info;
    if (options.distortion) {
        const BpmFile file = read_bpm(path);
        info = summarize(detail::outline_of(file), options);
        info.distortion = distortion_of(file, detail::display_name(path));
    } else {
        info = summarize(detail::read_bpm_outline(path), options);
    }
    info.file = path;
    if (path != "-") {
        std::error_code ec;
        const auto size = std::filesystem::file_size(path, ec);
        if (!ec) info.file_bytes = static_cast<int64_t>(size);
    }
    return info;
}

}  // namespace bpm
