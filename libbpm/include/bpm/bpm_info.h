#pragma once
// What a .bpm file holds, in numbers and names, for bpm-info (a `gdalinfo` for .bpm
// files): format version, sizes of the surfaces and of phi, patches and materials, the
// feature lines and vertices of the coarse surface, the tetrahedral mesh, the record of
// steps, the provenance and, on request, phi's distortion. Nothing is validated
// (bpm-check does that).
//
// Counts and names are read from the file, and only what is reported is read: phi, the
// original surface and the tet mesh's geometry are known by the extents of their
// datasets, not read (armadillo subdivided to 416k vertices, 93.5 MB at 10 %: 0.7 s and
// 23 MB instead of read_bpm's 17.7 s and 704 MB; spec/info-report.md "Cost"). Two things
// are computed from geometry, deliberately:
//   * the feature structure of the coarse surface (BpmFeatureSummary): the file does not
//     store features, they follow from the surface (boundaries, non-manifold edges, patch
//     borders, as bpm-check's topology check finds them) and from its dihedral angles
//     (creases); the coarse surface is small, so this is always done;
//   * phi's distortion (check_distortion, as bpm-check reports it), only with
//     BpmInfoOptions::distortion: it needs phi and the original surface, i.e. the whole
//     file (read_bpm), which costs as much as bpm-check's reading.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/surface.h"

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

// The feature lines and vertices of the coarse surface S. Feature edges:
//   boundary      1 incident triangle
//   non-manifold  3 or more incident triangles
//   interface     2 triangles of different patches (a patch border)
//   crease        2 triangles of one patch whose normals (as oriented, the second turned
//                 over if the two run the edge the same way) are more than
//                 feature_angle_degrees apart, or more than crease_chain_angle_degrees
//                 apart on a long, even line of such edges (the rule bpm-simplify and
//                 bpm-smooth use, SimplifyOptions::crease_chain_angle_degrees: the same
//                 code, here applied to the coarse surface)
// The first three are what bpm-check's topology check compares with S0 (feature vertices
// by original id): phi keeps them. Creases are geometry; bpm-simplify keeps the corners of
// creases (its --feature-angle, also 60 by default) as coarse vertices.
// Feature vertices: bpm-check's (a vertex that is not regular: neither no feature edge with
// one closed fan of triangles, nor exactly two feature edges with every fan running from
// one to the other), and every vertex at a crease with a number of feature edges other than
// two (a crease ends or meets another feature line there: the 8 corners of a cube). These
// are not the corners bpm-simplify kept (decided on the original surface, with a length
// filter for creases and a cone test for crease ends): spec/info-report.md compares them.
// Feature lines: maximal chains of feature edges whose inner vertices are not feature
// vertices; closed ones (without any feature vertex) are also counted as loops.
struct BpmFeatureSummary {
    double feature_angle_degrees = 60.0;
    double crease_chain_angle_degrees = 20.0;
    double crease_chain_length = 0.10;  // fraction of the coarse surface's bounding-box diagonal
    int64_t boundary_edges = 0, non_manifold_edges = 0, interface_edges = 0, crease_edges = 0;
    int64_t chain_crease_edges = 0;  // of crease_edges, those not over feature_angle_degrees (on long lines)
    int64_t feature_edges = 0;  // the sum of the four
    int64_t feature_vertices = 0;
    int64_t feature_lines = 0;
    int64_t feature_loops = 0;  // closed feature lines (included in feature_lines)
    // The topological ones: feature vertices and lines of the boundary, non-manifold and
    // patch-border edges alone (no creases), what bpm-check's topology check counts and
    // compares (bpm/surface_topology.h). Equal to the original's for a file that passes it.
    int64_t topological_feature_vertices = 0;
    int64_t topological_feature_lines = 0;
};

// The feature structure of `surface` (see BpmFeatureSummary; 180 degrees = no creases;
// crease_chain_angle_degrees 180 = no creases on long lines below the feature angle).
// \pre triangle indices in range.
// \throw bpm::OptionError for an angle outside [0, 180] or a length outside [0, 1] (NaN too).
BpmFeatureSummary summarize_features(const Surface& surface, double feature_angle_degrees = 60.0,
                                     double crease_chain_angle_degrees = 20.0, double crease_chain_length = 0.10);

// phi's distortion, as bpm-check's distortion check reports it (spec/check-report.md,
// "distortion"): per piece the area squeeze (max(s, 1/s) >= 1) and the normal deviation in
// degrees, percentiles by nearest rank; the pieces turned over more than 60 and 90 degrees
// and the coarse triangles that carry them.
struct BpmDistortionSummary {
    int64_t pieces = 0, degenerate_pieces = 0;
    double area_squeeze_p50 = 1, area_squeeze_p99 = 1, area_squeeze_max = 1;
    double normal_deviation_degrees_p50 = 0, normal_deviation_degrees_p99 = 0, normal_deviation_degrees_max = 0;
    int64_t pieces_turned_over_60_degrees = 0, pieces_turned_over_90_degrees = 0;
    int64_t coarse_triangles_with_pieces_over_60_degrees = 0, coarse_triangles_with_pieces_over_90_degrees = 0;
};

struct BpmInfoOptions {
    double feature_angle_degrees = 60.0;  // creases of the coarse surface (BpmFeatureSummary)
    double crease_chain_angle_degrees = 20.0;  // ... and on long lines (BpmFeatureSummary)
    double crease_chain_length = 0.10;
    bool distortion = false;              // also measure phi's distortion (reads the whole file)
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
    BpmFeatureSummary features;                    // of the coarse surface
    // The materials the patches separate (/patch_info front and back), sorted, distinct.
    std::vector<std::string> materials;
    std::optional<BpmTetMeshSummary> tetmesh;
    std::optional<int64_t> simplification_steps;   // number of recorded removals, if recorded
    std::vector<ProvenanceStep> provenance;        // oldest first, as stored
    std::optional<BpmDistortionSummary> distortion;  // with BpmInfoOptions::distortion only
};

// Reads `path` ("-" = standard input; gzip-compressed files are read too), only what is
// reported unless options.distortion asks for the whole file (read_bpm).
// \throw bpm::InputError as read_bpm does (missing file, not HDF5, truncated, ...); with
// options.distortion also when phi cannot be measured safely (indices out of range);
// bpm::OptionError (before reading) for options out of range, as summarize_features.
BpmInfo read_bpm_info(const std::string& path, const BpmInfoOptions& options = {});

// The summary of a file already in memory (file and file_bytes left as given).
BpmInfo summarize_bpm(const BpmFile& file, const BpmInfoOptions& options = {});

}  // namespace bpm
