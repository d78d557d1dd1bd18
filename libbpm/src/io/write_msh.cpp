// Gmsh MSH output, for surfaces and tetrahedral meshes. The two are described as one
// model (physical names, entities, one node block, element blocks) and written by one
// function per version (4.1 ASCII and binary, 2.2 ASCII), so the format's syntax is in one
// place. Text doubles with 17 significant digits (they read back to the same bits),
// independent of the C locale; binary little endian, as Gmsh writes it on the usual hosts.

#include <algorithm>
#include <cstdint>
#include <map>

#include "bpm/errors.h"
#include "bpm/tetmesh_materials.h"
#include "core/number_text.h"
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

void append_point(std::string& out, const Vec3& p) {
    for (int k = 0; k < 3; ++k) {
        if (k > 0) out += ' ';
        append_round_trip_text(out, p[k]);
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

std::string physical_names_section(const MshModel& m) {
    if (m.physical_names.empty()) return {};
    std::string out = "$PhysicalNames\n" + num(static_cast<int64_t>(m.physical_names.size())) + "\n";
    for (const MshPhysicalName& p : m.physical_names)
        out += num(p.dim) + " " + num(p.tag) + " \"" + p.name + "\"\n";
    return out + "$EndPhysicalNames\n";
}

int64_t elements_of(const MshBlock& b) { return static_cast<int64_t>(b.nodes.size()) / b.nodes_per_element; }

int64_t element_count(const MshModel& m) {
    int64_t ne = 0;
    for (const MshBlock& b : m.blocks) ne += elements_of(b);
    return ne;
}

std::string bpm_patch_ids_section(const MshModel& m) {
    return "$BpmPatchIds\n" + num(m.patch_offset) + "\n$EndBpmPatchIds\n";
}

std::string write_msh41_ascii(const MshModel& m) {
    std::string out = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n" + physical_names_section(m);
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
    const int64_t ne = element_count(m);
    if (ne == 0) {
        out += "0 0 0 0\n";
    } else {
        out += num(static_cast<int64_t>(m.blocks.size())) + " " + num(ne) + " 1 " + num(ne) + "\n";
    }
    int64_t tag = 1;
    for (const MshBlock& b : m.blocks) {
        out += num(b.dim) + " " + num(b.entity) + " " + num(b.type) + " " + num(elements_of(b)) + "\n";
        for (size_t i = 0; i < b.nodes.size(); i += size_t(b.nodes_per_element)) {
            out += num(tag++);
            for (int k = 0; k < b.nodes_per_element; ++k) out += " " + num(b.nodes[i + size_t(k)]);
            out += '\n';
        }
    }
    return out + "$EndElements\n" + bpm_patch_ids_section(m);
}

// MSH 4.1 binary (file type 1, data size 8): the same sections with int as int32 and
// size_t as uint64; $PhysicalNames and the section headers stay text, and every binary
// part ends with a line end before its $End line, as Gmsh writes it.
std::string write_msh41_binary(const MshModel& m) {
    std::string out = "$MeshFormat\n4.1 1 8\n";
    append_le<int32_t>(out, 1);
    out += "\n$EndMeshFormat\n" + physical_names_section(m);
    uint64_t count[4] = {0, 0, 0, 0};
    for (const MshEntity& e : m.entities) ++count[e.dim];
    out += "$Entities\n";
    for (uint64_t c : count) append_le<uint64_t>(out, c);
    for (const MshEntity& e : m.entities) {
        append_le<int32_t>(out, e.tag);
        for (double x : e.lo) append_le<double>(out, x);
        if (e.dim > 0)
            for (double x : e.hi) append_le<double>(out, x);
        append_le<uint64_t>(out, 1);
        append_le<int32_t>(out, static_cast<int32_t>(e.physical));
        if (e.dim > 0) append_le<uint64_t>(out, 0);  // no bounding entities
    }
    out += "\n$EndEntities\n$Nodes\n";
    const uint64_t nv = m.nodes->size();
    append_le<uint64_t>(out, nv == 0 ? 0 : 1);
    append_le<uint64_t>(out, nv);
    append_le<uint64_t>(out, nv == 0 ? 0 : 1);
    append_le<uint64_t>(out, nv);
    if (nv > 0) {
        append_le<int32_t>(out, m.node_dim);
        append_le<int32_t>(out, 1);
        append_le<int32_t>(out, 0);
        append_le<uint64_t>(out, nv);
        for (uint64_t i = 1; i <= nv; ++i) append_le<uint64_t>(out, i);
        append_le_array(out, m.nodes->front().data(), 3 * nv);
    }
    out += "\n$EndNodes\n$Elements\n";
    const int64_t ne = element_count(m);
    append_le<uint64_t>(out, ne == 0 ? 0 : m.blocks.size());
    append_le<uint64_t>(out, uint64_t(ne));
    append_le<uint64_t>(out, ne == 0 ? 0 : 1);
    append_le<uint64_t>(out, uint64_t(ne));
    uint64_t tag = 1;
    for (const MshBlock& b : m.blocks) {
        append_le<int32_t>(out, b.dim);
        append_le<int32_t>(out, b.entity);
        append_le<int32_t>(out, b.type);
        append_le<uint64_t>(out, uint64_t(elements_of(b)));
        std::vector<uint64_t> record;  // tag and node tags of every element, in one write
        record.reserve(b.nodes.size() + size_t(elements_of(b)));
        for (size_t i = 0; i < b.nodes.size(); i += size_t(b.nodes_per_element)) {
            record.push_back(tag++);
            for (int k = 0; k < b.nodes_per_element; ++k) record.push_back(uint64_t(b.nodes[i + size_t(k)]));
        }
        append_le_array(out, record.data(), record.size());
    }
    return out + "\n$EndElements\n" + bpm_patch_ids_section(m);
}

// MSH 2.2 ASCII, for readers of that version only (DUNE 2.9's GmshReader, older tools):
// no entities section; every element carries two tags, its physical tag and its entity
// (elementary) tag. $PhysicalNames comes after $Elements, not before $Nodes as Gmsh puts
// it: the format does not fix the order of sections (Gmsh, meshio and bpm read any), and
// DUNE 2.9's GmshReader expects $Nodes right after $MeshFormat and stops reading after
// $EndElements, so it sees neither $PhysicalNames nor $BpmPatchIds.
std::string write_msh22_ascii(const MshModel& m) {
    std::map<std::pair<int, int>, int64_t> physical_of_entity;
    for (const MshEntity& e : m.entities) physical_of_entity[{e.dim, e.tag}] = e.physical;
    std::string out = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n";
    const int64_t nv = static_cast<int64_t>(m.nodes->size());
    out += num(nv) + "\n";
    for (int64_t i = 0; i < nv; ++i) {
        out += num(i + 1) + " ";
        append_point(out, (*m.nodes)[size_t(i)]);
        out += '\n';
    }
    out += "$EndNodes\n$Elements\n" + num(element_count(m)) + "\n";
    int64_t tag = 1;
    for (const MshBlock& b : m.blocks) {
        const std::string tags =
            " " + num(b.type) + " 2 " + num(physical_of_entity.at({b.dim, b.entity})) + " " + num(b.entity);
        for (size_t i = 0; i < b.nodes.size(); i += size_t(b.nodes_per_element)) {
            out += num(tag++) + tags;
            for (int k = 0; k < b.nodes_per_element; ++k) out += " " + num(b.nodes[i + size_t(k)]);
            out += '\n';
        }
    }
    return out + "$EndElements\n" + physical_names_section(m) + bpm_patch_ids_section(m);
}

std::string write_msh(const MshModel& m, MshVersion version, MeshEncoding encoding) {
    if (version == MshVersion::V22) {
        if (encoding != MeshEncoding::Ascii) throw OutputError("<msh>", "MSH 2.2 is written as ASCII only");
        return write_msh22_ascii(m);
    }
    switch (encoding) {
        case MeshEncoding::Ascii: return write_msh41_ascii(m);
        case MeshEncoding::Binary: return write_msh41_binary(m);
        case MeshEncoding::BinaryZlib: break;
    }
    throw OutputError("<msh>", "MSH has no compressed form (zlib compression is for VTU)");
}

// A name for a quoted MSH string (Gmsh names cannot hold '"' or line ends).
std::string msh_name(std::string name) {
    for (char& c : name)
        if (c == '"' || c == '\n' || c == '\r') c = '\'';
    return name;
}

}  // namespace

std::string msh_of_surface(const Surface& s, const std::vector<PatchInfo>& patch_info, MshVersion version,
                           MeshEncoding encoding) {
    std::map<int32_t, int> entity_of_patch;
    for (int32_t p : s.patches) entity_of_patch.emplace(p, 0);
    int next_entity = 1;
    for (auto& [patch, entity] : entity_of_patch) entity = next_entity++;

    MshModel m;
    for (const auto& [patch, entity] : entity_of_patch) {
        const PatchInfo* info = find_patch_info(patch_info, patch);
        m.physical_names.push_back(
            {2, patch + 1, info && !info->name.empty() ? msh_name(info->name) : "patch_" + num(patch)});
    }
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
    return write_msh(m, version, encoding);
}

// The faces of `mesh` that bound a single tetrahedron, i.e. all but the interfaces between
// regions.
std::vector<size_t> outer_faces(const TetMesh& mesh) {
    auto sorted = [](Tri t) {
        std::sort(t.begin(), t.end());
        return t;
    };
    std::vector<Tri> tet_faces;
    tet_faces.reserve(4 * mesh.tetrahedra.size());
    for (const Tet& t : mesh.tetrahedra)
        for (int k = 0; k < 4; ++k) tet_faces.push_back(sorted({t[k], t[(k + 1) % 4], t[(k + 2) % 4]}));
    std::sort(tet_faces.begin(), tet_faces.end());
    std::vector<size_t> out;
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto [lo, hi] = std::equal_range(tet_faces.begin(), tet_faces.end(), sorted(mesh.faces[f]));
        if (hi - lo < 2) out.push_back(f);
    }
    return out;
}

// Volume entity r = region r (physical tag = its material id, or r without materials),
// surface entity i+1 = i-th patch in increasing order (physical tag = patch id + 1, named
// as the input named it, else "patch_<id>": Gmsh and its readers (meshio, DUNE's
// GmshReader) take tag 0 as "no physical group"). All nodes in one block of volume
// entity 1 (the format allows nodes to be classified on any entity).
// MSH 2.2 is for DUNE's GmshReader, which hands every triangle to the grid as a boundary
// segment, and UGGrid refuses segments inside the grid: it gets the outer boundary faces
// only (the interfaces between regions are where the element ids change).
std::string msh_of_tetmesh(const TetMesh& mesh, const std::vector<PatchInfo>& patch_info, MshVersion version,
                           MeshEncoding encoding) {
    const int32_t nr = mesh.num_regions();
    const bool materials = !mesh.region_material.empty();
    std::vector<size_t> faces;  // the faces written
    if (version == MshVersion::V22) {
        faces = outer_faces(mesh);
    } else {
        for (size_t f = 0; f < mesh.faces.size(); ++f) faces.push_back(f);
    }
    std::map<int32_t, int> entity_of_patch;
    for (size_t f : faces) entity_of_patch.emplace(mesh.face_patches[f], 0);
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
        for (size_t f : faces)
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
        for (size_t f : faces)
            if (mesh.face_patches[f] == patch)
                for (int32_t v : mesh.faces[f]) b.nodes.push_back(int64_t(v) + 1);
        m.blocks.push_back(std::move(b));
    }
    return write_msh(m, version, encoding);
}

}  // namespace bpm::detail
