// The mesh writers behind the public ones (write_surface, write_surface_vtu,
// write_tetmesh): one file per format owns the format's syntax (write_msh.cpp,
// write_vtu.cpp, write_medit.cpp); Gmsh MSH and VTU write surfaces and tetrahedral meshes
// with one writer each. The public functions validate their input and call these.
#pragma once

#include <string>
#include <vector>

#include "bpm/patch_info.h"
#include "bpm/surface.h"
#include "bpm/tetmesh.h"
#include "bpm/write_vtu.h"

namespace bpm::detail {

// Gmsh MSH 4.1 ASCII; surface and tet mesh alike give patch p the physical tag p + 1
// (Gmsh and its readers take tag 0 as "no physical group") and end with the section
// $BpmPatchIds holding 1, from which bpm's reader takes the patch ids back. Surface: one
// surface entity per patch (tags 1, 2, ... in increasing patch order), physical names
// "patch_<id>", one element block per run of consecutive triangles of one patch, so that
// the triangle order is kept exactly.
std::string msh_of_surface(const Surface& surface);
// Tetrahedral mesh: see write_tetmesh in bpm/write_tetmesh.h.
std::string msh_of_tetmesh(const TetMesh& mesh, const std::vector<PatchInfo>& patch_info);

// VTK XML UnstructuredGrid, ASCII. Surface: triangles, Int32 cell data "patch", the
// given arrays as Float64 (sizes checked: OutputError naming `where`).
std::string vtu_of_surface(const Surface& surface, const std::vector<VtuArray>& point_data,
                           const std::vector<VtuArray>& cell_data, const std::string& where);
// Tetrahedral mesh: see write_tetmesh in bpm/write_tetmesh.h.
std::string vtu_of_tetmesh(const TetMesh& mesh);

// INRIA MEDIT, tetrahedral meshes only: see write_tetmesh.
std::string medit_of_tetmesh(const TetMesh& mesh);

}  // namespace bpm::detail
