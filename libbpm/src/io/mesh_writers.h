// The mesh writers behind the public ones (write_surface, write_surface_vtu,
// write_tetmesh): one file per format owns the format's syntax (write_msh.cpp,
// write_vtu.cpp, write_medit.cpp); Gmsh MSH and VTU write surfaces and tetrahedral meshes
// with one writer each. The public functions validate their input and call these.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "bpm/mesh_encoding.h"
#include "bpm/patch_info.h"
#include "bpm/surface.h"
#include "bpm/tetmesh.h"
#include "bpm/write_vtu.h"

namespace bpm::detail {

inline bool host_is_little_endian() {
    const uint16_t probe = 1;
    unsigned char first;
    std::memcpy(&first, &probe, 1);
    return first == 1;
}

// Appends `count` values of an arithmetic type little endian (binary MSH, VTU, STL, PLY).
template <class T>
void append_le_array(std::string& out, const T* values, size_t count) {
    const size_t at = out.size();
    out.resize(at + count * sizeof(T));
    if (count == 0) return;
    std::memcpy(&out[at], values, count * sizeof(T));
    if (!host_is_little_endian())
        for (size_t i = 0; i < count; ++i) std::reverse(&out[at + i * sizeof(T)], &out[at + (i + 1) * sizeof(T)]);
}

template <class T>
void append_le(std::string& out, T value) {
    append_le_array(out, &value, 1);
}

enum class MshVersion { V41, V22 };

// Gmsh MSH 4.1 (ASCII or binary) or 2.2 (ASCII only; 4.1 without $Entities, each element
// tagged with its physical and entity tag; $PhysicalNames after $Elements for DUNE 2.9's
// GmshReader); zlib or binary 2.2 throw OutputError.
// Surface and tet mesh alike give patch p the physical tag p + 1
// (Gmsh and its readers take tag 0 as "no physical group") and end with the section
// $BpmPatchIds holding 1, from which bpm's reader takes the patch ids back. Surface: one
// surface entity per patch (tags 1, 2, ... in increasing patch order), physical names as
// `patch_info` names the patches (the input's names, e.g. "pair_0_1"), else "patch_<id>",
// one element block per run of consecutive triangles of one patch, so that the triangle
// order is kept exactly.
std::string msh_of_surface(const Surface& surface, const std::vector<PatchInfo>& patch_info, MshVersion version,
                           MeshEncoding encoding);
// Tetrahedral mesh: see write_tetmesh in bpm/write_tetmesh.h (2.2: outer boundary faces only).
std::string msh_of_tetmesh(const TetMesh& mesh, const std::vector<PatchInfo>& patch_info, MshVersion version,
                           MeshEncoding encoding);

// VTK XML UnstructuredGrid, ASCII, or appended raw data (binary, optionally zlib blocks:
// see bpm/mesh_encoding.h). Surface: triangles, Int32 cell data "patch", the
// given arrays as Float64 (sizes checked: OutputError naming `where`).
std::string vtu_of_surface(const Surface& surface, const std::vector<VtuArray>& point_data,
                           const std::vector<VtuArray>& cell_data, const std::string& where,
                           MeshEncoding encoding);
// Tetrahedral mesh: see write_tetmesh in bpm/write_tetmesh.h.
std::string vtu_of_tetmesh(const TetMesh& mesh, MeshEncoding encoding);

// INRIA MEDIT, tetrahedral meshes only: see write_tetmesh.
std::string medit_of_tetmesh(const TetMesh& mesh);

}  // namespace bpm::detail
