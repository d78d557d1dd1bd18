// Writing tetrahedral meshes: the format names, the checks that keep a file readable,
// and the choice of writer (one file per format: write_msh.cpp, write_vtu.cpp,
// write_medit.cpp).

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <map>

#include "bpm/errors.h"
#include "bpm/tetmesh_materials.h"
#include "bpm/write_tetmesh.h"
#include "core/file_util.h"
#include "io/mesh_writers.h"

namespace bpm {

namespace {

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

}  // namespace

std::optional<TetMeshFormat> tetmesh_format_from_name(const std::string& name) {
    const std::string n = lower(name);
    if (n == "bpm") return TetMeshFormat::Bpm;
    if (n == "msh") return TetMeshFormat::Msh;
    if (n == "msh22") return TetMeshFormat::Msh22;
    if (n == "vtu") return TetMeshFormat::Vtu;
    if (n == "mesh") return TetMeshFormat::Medit;
    return std::nullopt;
}

const char* tetmesh_format_name(TetMeshFormat format) {
    switch (format) {
        case TetMeshFormat::Bpm: return "bpm";
        case TetMeshFormat::Msh: return "msh";
        case TetMeshFormat::Msh22: return "msh22";
        case TetMeshFormat::Vtu: return "vtu";
        case TetMeshFormat::Medit: return "mesh";
    }
    return "?";
}

std::optional<TetMeshFormat> tetmesh_format_from_path(const std::string& path) {
    const size_t dot = path.find_last_of('.');
    const size_t slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return std::nullopt;
    return tetmesh_format_from_name(path.substr(dot + 1));
}

std::string write_tetmesh_to_string(const TetMesh& mesh, TetMeshFormat format, const std::vector<PatchInfo>& patch_info,
                                    MeshEncoding encoding) {
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
    const bool ascii_only = format == TetMeshFormat::Msh22 || format == TetMeshFormat::Medit;
    if (ascii_only && encoding != MeshEncoding::Ascii)
        throw OutputError("<tetmesh>", std::string(format == TetMeshFormat::Msh22 ? "MSH 2.2" : "MEDIT") +
                                           " is written as ASCII only (binary: MSH 4.1 or VTU)");
    if (format == TetMeshFormat::Msh && encoding == MeshEncoding::BinaryZlib)
        throw OutputError("<tetmesh>", "MSH has no compressed form (zlib compression is for VTU)");
    switch (format) {
        case TetMeshFormat::Msh: return detail::msh_of_tetmesh(mesh, patch_info, detail::MshVersion::V41, encoding);
        case TetMeshFormat::Msh22: return detail::msh_of_tetmesh(mesh, patch_info, detail::MshVersion::V22, encoding);
        case TetMeshFormat::Vtu: return detail::vtu_of_tetmesh(mesh, encoding);
        case TetMeshFormat::Medit: return detail::medit_of_tetmesh(mesh);
        case TetMeshFormat::Bpm: break;
    }
    throw OutputError("<tetmesh>", "the .bpm format holds a whole parametrization: use write_bpm");
}

void write_tetmesh(const std::string& path, const TetMesh& mesh, TetMeshFormat format,
                   const std::vector<PatchInfo>& patch_info, MeshEncoding encoding) {
    std::string text;
    try {
        text = write_tetmesh_to_string(mesh, format, patch_info, encoding);
    } catch (const OutputError& e) {
        throw OutputError(path == "-" ? "<stdout>" : path, e.what());
    }
    detail::write_file_atomically(path, text);
}

}  // namespace bpm
