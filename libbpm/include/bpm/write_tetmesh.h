#pragma once
// Writing a tetrahedral mesh (bpm/tetmesh.h) for solvers and viewers: Gmsh MSH, VTK XML
// UnstructuredGrid and INRIA MEDIT. The .bpm file, which holds the mesh with its
// parametrization, is written by write_bpm (bpm/bpm_file.h).

#include <optional>
#include <string>
#include <vector>

#include "bpm/mesh_encoding.h"
#include "bpm/patch_info.h"
#include "bpm/tetmesh.h"

namespace bpm {

// Msh: Gmsh MSH 4.1; Msh22: Gmsh MSH 2.2 (for readers of that version only, such as DUNE
// 2.9's Dune::GmshReader; ASCII only).
enum class TetMeshFormat { Bpm, Msh, Msh22, Vtu, Medit };
// "bpm", "msh", "msh22", "vtu", "mesh" (case-insensitive) -> format; nullopt otherwise.
// From a path: the extension (.msh is Msh, MSH 4.1).
std::optional<TetMeshFormat> tetmesh_format_from_name(const std::string& name);
std::optional<TetMeshFormat> tetmesh_format_from_path(const std::string& path);
// The name tetmesh_format_from_name takes: "bpm", "msh", "msh22", "vtu", "mesh".
const char* tetmesh_format_name(TetMeshFormat format);

// Writes `mesh` atomically ("-" = standard output) as
//   Msh    Gmsh MSH 4.1, ASCII or binary: one volume entity per region, its physical tag the region's
//          material id named by the material (without materials: tag = region id, name
//          "region_<id>"); one surface entity per patch (physical tag = patch id + 1, as
//          Gmsh and its readers take tag 0 for "no physical group"; named by
//          `patch_info`'s name if it has one, else "patch_<id>"); tets (type 4) and
//          boundary triangles (type 2); node tags = index+1; a last section
//          $BpmPatchIds (other readers skip it) from which bpm's MSH reader takes
//          patch = physical tag - 1 (see bpm/surface_io.h)
//   Msh22  Gmsh MSH 2.2 ASCII, for DUNE's Dune::GmshReader: every element tagged with
//          the physical tag of Msh and its entity; triangles only on the outer boundary
//          (GmshReader makes every triangle a boundary segment, and UGGrid refuses the
//          interfaces between regions: they are where the element ids change; MSH 4.1
//          keeps them); $PhysicalNames and $BpmPatchIds after $Elements, where DUNE 2.9's
//          GmshReader (which stops at $EndElements) does not see them. DUNE gets the
//          material ids as element ids and patch + 1 as boundary ids
//   Vtu    VTK XML UnstructuredGrid, ASCII or appended binary (zlib too): tetrahedra (type 10) with cell data "region"
//          and, with materials, "material" (the id; the names are in the .bpm, MSH
//          and MEDIT outputs: meshio 5 refuses a VTK string array); "ancestor" if
//          present; point data "coarse_vertex"
//   Medit  INRIA .mesh (MeshVersionFormatted 2): Vertices (ref 1 on S, 0 inside),
//          Tetrahedra with ref = material id (region id without materials; comment lines
//          "# material <id> <name>" name them), Triangles with ref = patch
// `encoding` (bpm/mesh_encoding.h) applies to Msh and Vtu; Medit and Msh22 are ASCII only.
// The .bpm format needs the whole BpmFile: use write_bpm (bpm/bpm_file.h).
// \throw OutputError (unwritable path, format Bpm, or an encoding the format lacks).
void write_tetmesh(const std::string& path, const TetMesh& mesh, TetMeshFormat format,
                   const std::vector<PatchInfo>& patch_info = {}, MeshEncoding encoding = MeshEncoding::Ascii);
std::string write_tetmesh_to_string(const TetMesh& mesh, TetMeshFormat format,
                                    const std::vector<PatchInfo>& patch_info = {},
                                    MeshEncoding encoding = MeshEncoding::Ascii);

}  // namespace bpm
