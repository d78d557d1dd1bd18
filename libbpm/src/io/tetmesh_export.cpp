// Writers for tetrahedral meshes: Gmsh MSH 4.1 ASCII, VTK XML UnstructuredGrid (.vtu),
// INRIA MEDIT (.mesh). One function per format; all deterministic, doubles with 17
// significant digits.

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <map>

#include "bpm/errors.h"
#include "bpm/tetmesh.h"
#include "bpm/tetmesh_materials.h"
#include "core/file_util.h"

namespace bpm {

namespace {

void append_double(std::string& out, double v) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.17g", v);
    out += buffer;
}
void append_point(std::string& out, const Vec3& p) {
    append_double(out, p[0]);
    out += ' ';
    append_double(out, p[1]);
    out += ' ';
    append_double(out, p[2]);
}
std::string num(int64_t v) { return std::to_string(v); }

void bounding_box(const TetMesh& m, const std::vector<int32_t>& vertices, std::string& out) {
    Vec3 lo{0, 0, 0}, hi{0, 0, 0};
    bool first = true;
    for (int32_t v : vertices) {
        for (int k = 0; k < 3; ++k) {
            lo[k] = first ? m.vertices[v][k] : std::min(lo[k], m.vertices[v][k]);
            hi[k] = first ? m.vertices[v][k] : std::max(hi[k], m.vertices[v][k]);
        }
        first = false;
    }
    append_point(out, lo);
    out += ' ';
    append_point(out, hi);
}

// A name for a quoted MSH string (Gmsh names cannot hold '"' or line ends).
std::string msh_name(std::string name) {
    for (char& c : name)
        if (c == '"' || c == '\n' || c == '\r') c = '\'';
    return name;
}

// Gmsh MSH 4.1: volume entity r = region r (physical tag = its material id, or r without
// materials), surface entity i+1 = i-th patch in increasing order (physical tag = patch
// id + 1, named as the input named it, else "patch_<id>": Gmsh and its readers (meshio,
// DUNE's GmshReader) take tag 0 as "no physical group"). All nodes in one block of volume entity 1 (the format
// allows nodes to be classified on any entity).
std::string write_msh(const TetMesh& m, const std::vector<PatchInfo>& patch_info) {
    const int32_t nr = m.num_regions();
    const bool materials = !m.region_material.empty();
    auto volume_tag = [&](int32_t r) { return materials ? m.region_material[size_t(r - 1)] : r; };
    auto patch_name = [&](int32_t patch) {
        const PatchInfo* info = find_patch_info(patch_info, patch);
        return info && !info->name.empty() ? msh_name(info->name) : "patch_" + num(patch);
    };
    const int64_t volume_names = materials ? static_cast<int64_t>(m.material_names.size()) : nr;
    std::map<int32_t, int> entity_of_patch;
    for (int32_t p : m.face_patches) entity_of_patch.emplace(p, 0);
    int next = 1;
    for (auto& [patch, entity] : entity_of_patch) entity = next++;

    std::string out = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n";
    out += num(volume_names + static_cast<int64_t>(entity_of_patch.size())) + "\n";
    for (const auto& [patch, entity] : entity_of_patch) out += "2 " + num(patch + 1) + " \"" + patch_name(patch) + "\"\n";
    if (materials) {
        for (size_t i = 0; i < m.material_names.size(); ++i)
            out += "3 " + num(int64_t(i) + 1) + " \"" + msh_name(m.material_names[i]) + "\"\n";
    } else {
        for (int32_t r = 1; r <= nr; ++r) out += "3 " + num(r) + " \"region_" + num(r) + "\"\n";
    }
    out += "$EndPhysicalNames\n$Entities\n";
    out += "0 0 " + num(static_cast<int64_t>(entity_of_patch.size())) + " " + num(nr) + "\n";
    for (const auto& [patch, entity] : entity_of_patch) {
        std::vector<int32_t> used;
        for (size_t f = 0; f < m.faces.size(); ++f)
            if (m.face_patches[f] == patch) used.insert(used.end(), m.faces[f].begin(), m.faces[f].end());
        out += num(entity) + " ";
        bounding_box(m, used, out);
        out += " 1 " + num(patch + 1) + " 0\n";
    }
    for (int32_t r = 1; r <= nr; ++r) {
        std::vector<int32_t> used;
        for (size_t t = 0; t < m.tetrahedra.size(); ++t)
            if (m.regions[t] == r) used.insert(used.end(), m.tetrahedra[t].begin(), m.tetrahedra[t].end());
        if (used.empty()) used.push_back(0);
        out += num(r) + " ";
        bounding_box(m, used, out);
        out += " 1 " + num(volume_tag(r)) + " 0\n";
    }
    out += "$EndEntities\n$Nodes\n";
    const int64_t nv = m.num_vertices();
    if (nv == 0) {
        out += "0 0 0 0\n";
    } else {
        out += "1 " + num(nv) + " 1 " + num(nv) + "\n3 1 0 " + num(nv) + "\n";
        for (int64_t i = 1; i <= nv; ++i) out += num(i) + "\n";
        for (const Vec3& p : m.vertices) {
            append_point(out, p);
            out += '\n';
        }
    }
    out += "$EndNodes\n$Elements\n";
    const int64_t ne = m.num_tetrahedra() + static_cast<int64_t>(m.faces.size());
    int64_t blocks = 0;
    for (int32_t r = 1; r <= nr; ++r) blocks += std::count(m.regions.begin(), m.regions.end(), r) > 0;
    blocks += static_cast<int64_t>(entity_of_patch.size());
    out += num(blocks) + " " + num(ne) + " 1 " + num(ne) + "\n";
    int64_t tag = 1;
    for (int32_t r = 1; r <= nr; ++r) {
        const int64_t count = std::count(m.regions.begin(), m.regions.end(), r);
        if (count == 0) continue;
        out += "3 " + num(r) + " 4 " + num(count) + "\n";
        for (size_t t = 0; t < m.tetrahedra.size(); ++t) {
            if (m.regions[t] != r) continue;
            const Tet& x = m.tetrahedra[t];
            out += num(tag++) + " " + num(x[0] + 1) + " " + num(x[1] + 1) + " " + num(x[2] + 1) + " " +
                   num(x[3] + 1) + "\n";
        }
    }
    for (const auto& [patch, entity] : entity_of_patch) {
        const int64_t count = std::count(m.face_patches.begin(), m.face_patches.end(), patch);
        out += "2 " + num(entity) + " 2 " + num(count) + "\n";
        for (size_t f = 0; f < m.faces.size(); ++f) {
            if (m.face_patches[f] != patch) continue;
            const Tri& x = m.faces[f];
            out += num(tag++) + " " + num(x[0] + 1) + " " + num(x[1] + 1) + " " + num(x[2] + 1) + "\n";
        }
    }
    out += "$EndElements\n";
    return out;
}

std::string write_vtu(const TetMesh& m) {
    const int64_t nv = m.num_vertices(), nt = m.num_tetrahedra();
    std::string out =
        "<?xml version=\"1.0\"?>\n"
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
        "  <UnstructuredGrid>\n";
    // Material names are not written as a VTK string array (FieldData): meshio 5 refuses
    // the whole file on one ("Illegal data type 'String'"); the names are in the .bpm, MSH
    // and MEDIT outputs, the VTU has the material ids.
    out += "    <Piece NumberOfPoints=\"" + num(nv) + "\" NumberOfCells=\"" + num(nt) + "\">\n";
    out += "      <PointData Scalars=\"coarse_vertex\">\n"
           "        <DataArray type=\"Int32\" Name=\"coarse_vertex\" format=\"ascii\">\n";
    for (int32_t v : m.vertex_coarse_vertex) out += num(v) + "\n";
    out += "        </DataArray>\n      </PointData>\n";
    out += "      <CellData Scalars=\"region\">\n        <DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n";
    for (int32_t r : m.regions) out += num(r) + "\n";
    out += "        </DataArray>\n";
    if (!m.region_material.empty()) {
        out += "        <DataArray type=\"Int32\" Name=\"material\" format=\"ascii\">\n";
        for (int32_t id : tet_materials(m)) out += num(id) + "\n";
        out += "        </DataArray>\n";
    }
    if (!m.tet_ancestor.empty()) {
        out += "        <DataArray type=\"Int32\" Name=\"ancestor\" format=\"ascii\">\n";
        for (int32_t a : m.tet_ancestor) out += num(a) + "\n";
        out += "        </DataArray>\n";
    }
    out += "      </CellData>\n      <Points>\n"
           "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const Vec3& p : m.vertices) {
        append_point(out, p);
        out += '\n';
    }
    out += "        </DataArray>\n      </Points>\n      <Cells>\n"
           "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (const Tet& x : m.tetrahedra)
        out += num(x[0]) + " " + num(x[1]) + " " + num(x[2]) + " " + num(x[3]) + "\n";
    out += "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (int64_t t = 1; t <= nt; ++t) out += num(4 * t) + "\n";
    out += "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (int64_t t = 0; t < nt; ++t) out += "10\n";
    out += "        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
    return out;
}

std::string write_medit(const TetMesh& m) {
    std::string out = "MeshVersionFormatted 2\nDimension 3\n";
    for (size_t i = 0; i < m.material_names.size(); ++i) {
        std::string name = m.material_names[i];
        std::replace(name.begin(), name.end(), '\n', ' ');
        out += "# material " + num(int64_t(i) + 1) + " " + name + "\n";
    }
    const std::vector<int32_t> material = tet_materials(m);
    out += "\nVertices\n" + num(m.num_vertices()) + "\n";
    for (int32_t v = 0; v < m.num_vertices(); ++v) {
        append_point(out, m.vertices[v]);
        out += m.vertex_parameter_points[v].valid() ? " 1\n" : " 0\n";
    }
    out += "\nTetrahedra\n" + num(m.num_tetrahedra()) + "\n";
    for (size_t t = 0; t < m.tetrahedra.size(); ++t) {
        const Tet& x = m.tetrahedra[t];
        out += num(x[0] + 1) + " " + num(x[1] + 1) + " " + num(x[2] + 1) + " " + num(x[3] + 1) + " " +
               num(material.empty() ? m.regions[t] : material[t]) + "\n";
    }
    out += "\nTriangles\n" + num(static_cast<int64_t>(m.faces.size())) + "\n";
    for (size_t f = 0; f < m.faces.size(); ++f) {
        const Tri& x = m.faces[f];
        out += num(x[0] + 1) + " " + num(x[1] + 1) + " " + num(x[2] + 1) + " " + num(m.face_patches[f]) + "\n";
    }
    out += "\nEnd\n";
    return out;
}

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

}  // namespace

std::optional<TetMeshFormat> tetmesh_format_from_name(const std::string& name) {
    const std::string n = lower(name);
    if (n == "bpm") return TetMeshFormat::Bpm;
    if (n == "msh") return TetMeshFormat::Msh;
    if (n == "vtu") return TetMeshFormat::Vtu;
    if (n == "mesh") return TetMeshFormat::Medit;
    return std::nullopt;
}

std::optional<TetMeshFormat> tetmesh_format_from_path(const std::string& path) {
    const size_t dot = path.find_last_of('.');
    const size_t slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return std::nullopt;
    return tetmesh_format_from_name(path.substr(dot + 1));
}

std::string write_tetmesh_to_string(const TetMesh& mesh, TetMeshFormat format, const std::vector<PatchInfo>& patch_info) {
    const int64_t nv = mesh.num_vertices();
    if (mesh.regions.size() != mesh.tetrahedra.size() || mesh.face_patches.size() != mesh.faces.size() ||
        mesh.vertex_coarse_vertex.size() != mesh.vertices.size() ||
        mesh.vertex_parameter_points.size() != mesh.vertices.size())
        throw OutputError("<tetmesh>", "cannot write an inconsistent tetrahedral mesh (array sizes differ)");
    for (const Tet& t : mesh.tetrahedra)
        for (int32_t v : t)
            if (v < 0 || v >= nv) throw OutputError("<tetmesh>", "cannot write: a tetrahedron corner is out of range");
    if (const std::string problem = find_material_inconsistency(mesh); !problem.empty())
        throw OutputError("<tetmesh>", "cannot write an inconsistent tetrahedral mesh: " + problem);
    switch (format) {
        case TetMeshFormat::Msh: return write_msh(mesh, patch_info);
        case TetMeshFormat::Vtu: return write_vtu(mesh);
        case TetMeshFormat::Medit: return write_medit(mesh);
        case TetMeshFormat::Bpm: break;
    }
    throw OutputError("<tetmesh>", "the .bpm format holds a whole parametrization: use write_bpm");
}

void write_tetmesh(const std::string& path, const TetMesh& mesh, TetMeshFormat format,
                   const std::vector<PatchInfo>& patch_info) {
    std::string text;
    try {
        text = write_tetmesh_to_string(mesh, format, patch_info);
    } catch (const OutputError& e) {
        throw OutputError(path == "-" ? "<stdout>" : path, e.what());
    }
    detail::write_file_atomically(path, text);
}

}  // namespace bpm
