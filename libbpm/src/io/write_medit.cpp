// INRIA MEDIT (.mesh, MeshVersionFormatted 2) output of tetrahedral meshes; doubles with
// 17 significant digits.

#include <algorithm>

#include "bpm/tetmesh_materials.h"
#include "core/number_text.h"
#include "io/mesh_writers.h"

namespace bpm::detail {

namespace {

void append_point(std::string& out, const Vec3& p) {
    append_round_trip_text(out, p[0]);
    out += ' ';
    append_round_trip_text(out, p[1]);
    out += ' ';
    append_round_trip_text(out, p[2]);
}
std::string num(int64_t v) { return std::to_string(v); }

}  // namespace

std::string medit_of_tetmesh(const TetMesh& m) {
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

}  // namespace bpm::detail
