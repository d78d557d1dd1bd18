// Gmsh MSH 4.1 output, for surfaces and tetrahedral meshes. The two are described as one
// model (physical names, entities, one node block, element blocks) and written by one
// function, so the format's syntax is in one place. Doubles with 17 significant digits
// (they read back to the same bits), independent of the C locale.

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <map>

#include "bpm/tetmesh_materials.h"
#include "io/mesh_writers.h"

namespace bpm::detail {

namespace {

struct MshPhysicalName {
    int dim;
    int64_t tag;
    std::string name;
};

// A point/curve/surface/volume entity with one physical tag.
struct MshEntity {
    int dim;
    int tag;
    Vec3 lo, hi;  // bounding box
    int64_t physical;
};

// Elements of one type on one entity; `nodes` holds node tags (1-based), row-major.
struct MshBlock {
    int dim;
    int entity;
    int type;  // 2 triangle, 4 tetrahedron
    int nodes_per_element;
    std::vector<int64_t> nodes;
};

struct MshModel {
    std::vector<MshPhysicalName> physical_names;  // no $PhysicalNames section when empty
    std::vector<MshEntity> entities;              // sorted by dimension
    const std::vector<Vec3>* nodes = nullptr;     // all in one block, on entity (node_dim, 1)
    int node_dim = 0;
    std::vector<MshBlock> blocks;  // element tags 1, 2, ... in block order
    // The physical tag of patch 0, written as the section $BpmPatchIds that bpm's reader
    // uses to give back the patch ids (io/read_msh.cpp) and other readers skip.
    int patch_offset = 1;
};

std::string num(int64_t v) { return std::to_string(v); }

void append_double(std::string& out, double x) {
    char buffer[40];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, x, std::chars_format::general, 17);
    out.append(buffer, result.ptr);
}

void append_point(std::string& out, const Vec3& p) {
    for (int k = 0; k < 3; ++k) {
        if (k > 0) out += ' ';
        append_double(out, p[k]);
    }
}

// Grows [lo, hi] by p; `first` starts a new box.
void extend_box(Vec3& lo, Vec3& hi, bool& first, const Vec3& p) {
    for (int k = 0; k < 3; ++k) {
        lo[k] = first ? p[k] : std::min(lo[k], p[k]);
        hi[k] = first ? p[k] : std::max(hi[k], p[k]);
    }
    first = false;
}

std::string write_msh41(const MshModel& m) {
    std::string out = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
    if (!m.physical_names.empty()) {
        out += "$PhysicalNames\n" + num(static_cast<int64_t>(m.physical_names.size())) + "\n";
        for (const MshPhysicalName& p : m.physical_names)
            out += num(p.dim) + " " + num(p.tag) + " \"" + p.name + "\"\n";
        out += "$EndPhysicalNames\n";
    }
    int64_t count[4] = {0, 0, 0, 0};
    for (const MshEntity& e : m.entities) ++count[e.dim];
    out += "$Entities\n" + num(count[0]) + " " + num(count[1]) + " " + num(count[2]) + " " + num(count[3]) + "\n";
    for (const MshEntity& e : m.entities) {
        out += num(e.tag) + " ";
        append_point(out, e.lo);
        out += ' ';
        append_point(out, e.hi);
        out += " 1 " + num(e.physical) + " 0\n";
    }
    out += "$EndEntities\n$Nodes\n";
    const int64_t nv = static_cast<int64_t>(m.nodes->size());
    if (nv == 0) {
        out += "0 0 0 0\n";
    } else {
        out += "1 " + num(nv) + " 1 " + num(nv) + "\n" + num(m.node_dim) + " 1 0 " + num(nv) + "\n";
        for (int64_t i = 1; i <= nv; ++i) out += num(i) + "\n";
        for (const Vec3& p : *m.nodes) {
            append_point(out, p);
            out += '\n';
        }
    }
    out += "$EndNodes\n$Elements\n";
    int64_t ne = 0;
    for (const MshBlock& b : m.blocks) ne += static_cast<int64_t>(b.nodes.size()) / b.nodes_per_element;
    if (ne == 0) {
        out += "0 0 0 0\n";
    } else {
        out += num(static_cast<int64_t>(m.blocks.size())) + " " + num(ne) + " 1 " + num(ne) + "\n";
    }
    int64_t tag = 1;
    for (const MshBlock& b : m.blocks) {
        out += num(b.dim) + " " + num(b.entity) + " " + num(b.type) + " " +
               num(static_cast<int64_t>(b.nodes.size()) / b.nodes_per_element) + "\n";
        for (size_t i = 0; i < b.nodes.size(); i += size_t(b.nodes_per_element)) {
            out += num(tag++);
            for (int k = 0; k < b.nodes_per_element; ++k) out += " " + num(b.nodes[i + size_t(k)]);
            out += '\n';
        }
    }
    out += "$EndElements\n$BpmPatchIds\n" + num(m.patch_offset) + "\n$EndBpmPatchIds\n";
    return out;
}

// A name for a quoted MSH string (Gmsh names cannot hold '"' or line ends).
std::string msh_name(std::string name) {
    for (char& c : name)
        if (c == '"' || c == '\n' || c == '\r') c = '\'';
    return name;
}

}  // namespace

std::string msh_of_surface(const Surface& s) {
    std::map<int32_t, int> entity_of_patch;
    for (int32_t p : s.patches) entity_of_patch.emplace(p, 0);
    int next_entity = 1;
    for (auto& [patch, entity] : entity_of_patch) entity = next_entity++;

    MshModel m;
    for (const auto& [patch, entity] : entity_of_patch) m.physical_names.push_back({2, patch + 1, "patch_" + num(patch)});
    for (const auto& [patch, entity] : entity_of_patch) {
        MshEntity e{2, entity, {0, 0, 0}, {0, 0, 0}, int64_t(patch) + 1};
        bool first = true;
        for (size_t t = 0; t < s.triangles.size(); ++t) {
            if (s.patches[t] != patch) continue;
            for (int32_t v : s.triangles[t]) extend_box(e.lo, e.hi, first, s.vertices[v]);
        }
        m.entities.push_back(e);
    }
    m.nodes = &s.vertices;
    m.node_dim = 2;
    const size_t nt = s.triangles.size();
    for (size_t t = 0; t < nt;) {
        MshBlock b{2, entity_of_patch[s.patches[t]], 2, 3, {}};
        for (const int32_t patch = s.patches[t]; t < nt && s.patches[t] == patch; ++t)
            for (int32_t v : s.triangles[t]) b.nodes.push_back(int64_t(v) + 1);
        m.blocks.push_back(std::move(b));
    }
    return write_msh41(m);
}

// Volume entity r = region r (physical tag = its material id, or r without materials),
// surface entity i+1 = i-th patch in increasing order (physical tag = patch id + 1, named
// as the input named it, else "patch_<id>": Gmsh and its readers (meshio, DUNE's
// GmshReader) take tag 0 as "no physical group"). All nodes in one block of volume
// entity 1 (the format allows nodes to be classified on any entity).
std::string msh_of_tetmesh(const TetMesh& mesh, const std::vector<PatchInfo>& patch_info) {
    const int32_t nr = mesh.num_regions();
    const bool materials = !mesh.region_material.empty();
    std::map<int32_t, int> entity_of_patch;
    for (int32_t p : mesh.face_patches) entity_of_patch.emplace(p, 0);
    int next = 1;
    for (auto& [patch, entity] : entity_of_patch) entity = next++;

    MshModel m;
    for (const auto& [patch, entity] : entity_of_patch) {
        const PatchInfo* info = find_patch_info(patch_info, patch);
        m.physical_names.push_back(
            {2, patch + 1, info && !info->name.empty() ? msh_name(info->name) : "patch_" + num(patch)});
    }
    if (materials) {
        for (size_t i = 0; i < mesh.material_names.size(); ++i)
            m.physical_names.push_back({3, int64_t(i) + 1, msh_name(mesh.material_names[i])});
    } else {
        for (int32_t r = 1; r <= nr; ++r) m.physical_names.push_back({3, r, "region_" + num(r)});
    }
    for (const auto& [patch, entity] : entity_of_patch) {
        MshEntity e{2, entity, {0, 0, 0}, {0, 0, 0}, int64_t(patch) + 1};
        bool first = true;
        for (size_t f = 0; f < mesh.faces.size(); ++f)
            if (mesh.face_patches[f] == patch)
                for (int32_t v : mesh.faces[f]) extend_box(e.lo, e.hi, first, mesh.vertices[v]);
        m.entities.push_back(e);
    }
    for (int32_t r = 1; r <= nr; ++r) {
        MshEntity e{3, r, {0, 0, 0}, {0, 0, 0}, materials ? mesh.region_material[size_t(r - 1)] : r};
        bool first = true;
        for (size_t t = 0; t < mesh.tetrahedra.size(); ++t)
            if (mesh.regions[t] == r)
                for (int32_t v : mesh.tetrahedra[t]) extend_box(e.lo, e.hi, first, mesh.vertices[v]);
        if (first && !mesh.vertices.empty()) extend_box(e.lo, e.hi, first, mesh.vertices[0]);  // an empty region: the box of vertex 0
        m.entities.push_back(e);
    }
    m.nodes = &mesh.vertices;
    m.node_dim = 3;
    for (int32_t r = 1; r <= nr; ++r) {
        MshBlock b{3, r, 4, 4, {}};
        for (size_t t = 0; t < mesh.tetrahedra.size(); ++t)
            if (mesh.regions[t] == r)
                for (int32_t v : mesh.tetrahedra[t]) b.nodes.push_back(int64_t(v) + 1);
        if (!b.nodes.empty()) m.blocks.push_back(std::move(b));
    }
    for (const auto& [patch, entity] : entity_of_patch) {
        MshBlock b{2, entity, 2, 3, {}};
        for (size_t f = 0; f < mesh.faces.size(); ++f)
            if (mesh.face_patches[f] == patch)
                for (int32_t v : mesh.faces[f]) b.nodes.push_back(int64_t(v) + 1);
        m.blocks.push_back(std::move(b));
    }
    return write_msh41(m);
}

}  // namespace bpm::detail
