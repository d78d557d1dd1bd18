#pragma once
// Writing a triangulated surface with named point and cell data as VTK XML
// UnstructuredGrid (.vtu), e.g. a refined surface with the data carried over from the
// original (bpm-refine --data). Tetrahedral meshes: write_tetmesh (bpm/write_tetmesh.h).

#include <string>
#include <vector>

#include "bpm/mesh_encoding.h"
#include "bpm/surface.h"

namespace bpm {

// A named data array: one row of `components` values per point or cell.
struct VtuArray {
    std::string name;
    int components = 1;
    std::vector<double> values;  // #elements * components, row-major
};

// Writes the triangles (VTK cell type 5) atomically ("-" = standard output), ASCII or
// binary (appended raw data, optionally zlib-compressed: bpm/mesh_encoding.h); patch ids
// as the Int32 cell array "patch", the given arrays as Float64 point and cell data.
// Binary files write the Int64 connectivity and offsets as Int32 when they fit.
// \throw bpm::OutputError for an unwritable path, an index out of range, patches not one
//        per triangle, or an array whose size is not #elements * components.
void write_surface_vtu(const std::string& path, const Surface& surface, const std::vector<VtuArray>& point_data,
                       const std::vector<VtuArray>& cell_data, MeshEncoding encoding = MeshEncoding::Ascii);

}  // namespace bpm
