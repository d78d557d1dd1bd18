#pragma once
// Internal (not public API): the part of a .bpm file that bpm-info reports (bpm/bpm_info.h),
// read without the datasets whose size is all it reports. phi, the original surface's
// coordinates and triangles and the tet mesh's geometry are known by the extents of their
// HDF5 dataspaces only, and a plain file is opened in place (HDF5 reads only what is
// asked for): armadillo at 10 %, 6.3 MB: 0.10 s and 8 MB instead of read_bpm's 1.0 s and
// 58 MB (spec/info-report.md "Cost").
//
// Implemented in bpm_read.cpp with read_bpm's reader: the same checks of what is read
// (datatypes, shapes, storage bounds against the file size, index ranges of the coarse
// surface, /patch_info and /provenance as read_bpm checks them) and the same isolation
// from HDF5 crashes. What is not read is not checked: bpm-check validates.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/patch_info.h"
#include "bpm/surface.h"

namespace bpm::detail {

struct BpmTetMeshOutline {
    int64_t vertices = 0, tetrahedra = 0, faces = 0;
    int32_t level = 0;
    std::vector<int32_t> regions;          // per tetrahedron, 1..R
    std::vector<int32_t> region_material;  // #R or empty
    std::vector<std::string> material_names;
};

struct BpmOutline {
    BpmFormatVersion format_version;
    std::string units;
    int64_t original_vertices = 0;
    std::vector<int32_t> original_patches;  // per original triangle: its size is #T0
    std::vector<std::string> original_point_data;  // names of the /original/point_data arrays
    Surface coarse;                        // whole (vertices, triangles, patches): bpm-info derives its features
    int64_t phi_nodes = 0, phi_pieces = 0;
    std::optional<BpmTetMeshOutline> tetmesh;
    std::optional<int64_t> simplification_steps;  // rows of /simplification_steps/vertex
    std::vector<PatchInfo> patch_info;
    std::vector<ProvenanceStep> provenance;
};

// Reads `path` as read_bpm does ("-" = standard input, .gz decompressed, isolation from
// HDF5 crashes when set_hdf5_isolation is on). \throw bpm::InputError as read_bpm.
BpmOutline read_bpm_outline(const std::string& path);

// The same outline of a file already in memory (all of it read and checked).
BpmOutline outline_of(const BpmFile& file);

}  // namespace bpm::detail
