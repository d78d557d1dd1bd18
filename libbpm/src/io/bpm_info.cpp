// bpm-info's summary of a .bpm file (bpm/bpm_info.h): counts and names as stored.
#include "bpm/bpm_info.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <system_error>

namespace bpm {

BpmInfo summarize_bpm(const BpmFile& file) {
    BpmInfo info;
    const Parametrization& p = file.param;
    info.format_version = file.format_version;
    info.units = file.units;
    info.original_vertices = p.original.num_vertices();
    info.original_triangles = p.original.num_triangles();
    info.coarse_vertices = p.coarse.num_vertices();
    info.coarse_triangles = p.coarse.num_triangles();
    info.phi_nodes = p.num_nodes();
    info.phi_pieces = p.num_pieces();
    for (const VertexArray& a : p.original.vertex_data) info.original_point_data.push_back(a.name);

    std::map<int32_t, BpmPatchSummary> patches;
    for (const int32_t id : p.original.patches) ++patches[id].original_triangles;
    for (const int32_t id : p.coarse.patches) ++patches[id].coarse_triangles;
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

    if (file.tetmesh) {
        const TetMesh& m = *file.tetmesh;
        BpmTetMeshSummary t;
        t.vertices = m.num_vertices();
        t.tetrahedra = m.num_tetrahedra();
        t.boundary_faces = static_cast<int64_t>(m.faces.size());
        t.level = m.level;
        t.materials = m.material_names;
        const int32_t regions = m.num_regions();
        t.regions.resize(static_cast<size_t>(std::max(regions, 0)));
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
    if (file.simplification_steps) info.simplification_steps = static_cast<int64_t>(file.simplification_steps->vertex.size());
    info.provenance = file.provenance;
    return info;
}

BpmInfo read_bpm_info(const std::string& path) {
    BpmInfo info = summarize_bpm(read_bpm(path));
    info.file = path;
    if (path != "-") {
        std::error_code ec;
        const auto size = std::filesystem::file_size(path, ec);
        if (!ec) info.file_bytes = static_cast<int64_t>(size);
    }
    return info;
}

}  // namespace bpm
