#pragma once
// What a .bpm file holds, in numbers and names, for bpm-info (a `gdalinfo` for .bpm
// files): format version, sizes of the surfaces and of phi, patches and materials, the
// tetrahedral mesh, the record of steps and the provenance. Read from the file, never
// computed from the geometry (no check, no distortion measure: bpm-check does those).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bpm/bpm_file.h"

namespace bpm {

struct BpmPatchSummary {
    int32_t id = 0;
    int64_t original_triangles = 0;
    int64_t coarse_triangles = 0;
    std::optional<PatchInfo> info;  // its /patch_info row, if the file has one
};

struct BpmRegionSummary {
    int32_t id = 0;             // 1..R
    int64_t tetrahedra = 0;
    std::string material;       // its material's name; empty when materials are not assigned
};

struct BpmTetMeshSummary {
    int64_t vertices = 0;
    int64_t tetrahedra = 0;
    int64_t boundary_faces = 0;  // faces on the coarse surface (boundary and interfaces)
    int32_t level = 0;           // refinement level (0 = TetGen's mesh)
    std::vector<BpmRegionSummary> regions;   // by id
    std::vector<std::string> materials;      // TetMesh::material_names, in id order
};

struct BpmInfo {
    std::string file;           // as given ("-" for standard input)
    int64_t file_bytes = -1;    // size of the file as stored (compressed if .gz); -1 for standard input
    BpmFormatVersion format_version;
    std::string units;          // empty if not recorded
    int64_t original_vertices = 0, original_triangles = 0;
    int64_t coarse_vertices = 0, coarse_triangles = 0;
    int64_t phi_nodes = 0, phi_pieces = 0;
    std::vector<std::string> original_point_data;  // names of /original/point_data arrays
    std::vector<BpmPatchSummary> patches;          // every patch id used or described, ascending
    // The materials the patches separate (/patch_info front and back), sorted, distinct.
    std::vector<std::string> materials;
    std::optional<BpmTetMeshSummary> tetmesh;
    std::optional<int64_t> simplification_steps;   // number of recorded removals, if recorded
    std::vector<ProvenanceStep> provenance;        // oldest first, as stored
};

// Reads `path` ("-" = standard input; gzip-compressed files are read too) with read_bpm.
// \throw bpm::InputError as read_bpm does (missing file, not HDF5, truncated, ...).
BpmInfo read_bpm_info(const std::string& path);

// The summary of a file already in memory (file and file_bytes left as given).
BpmInfo summarize_bpm(const BpmFile& file);

}  // namespace bpm
