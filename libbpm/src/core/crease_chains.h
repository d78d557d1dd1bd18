#pragma once
// Creases with chains (issue 19): which edges of a surface are creases, as the simplifier
// (simplify/coarse_mesh.cpp, mark_feature_edges), the smoother (smooth/smooth.cpp) and
// bpm-info (io/bpm_info_features.cpp) all decide it. An edge is a crease where
//   - its two triangles' normals are more than the feature angle apart (CreaseTest,
//     core/crease.h), or
//   - they are more than the chain angle apart (but not more than the feature angle) and
//     the edge belongs to a chain of at least kChainMinEdges such shallow edges and at
//     least `min_chain_length` long.
// A chain runs through a vertex only where the vertex has exactly two shallow edges among
// the given edges and none sharper than the feature angle, where the line turns little (at
// most kChainTurnDegrees between the two edges' directions) and where the two edges' angles
// agree (the larger at most kChainAngleRatio times the smaller): the curved 22-32 degree
// creases of a CAD part (fandisk: chains of 10 to 29 edges, 13 to 37 % of the diagonal)
// pass; the kinks of a scanned surface, which meet, end, zigzag and change their angle from
// one edge to the next, break into short pieces (femur, elephant, armadillo: at most 7 edges
// and at most 10 % of the diagonal, never both 5 edges and 10 %; mech-holes-shark's few
// shallow edges: at most 2 in a row). Measured: bench/results/manual/crease-chains.md.
//
// Inputs: the corner positions and every edge that two triangles of one sheet and one
// patch share, each once, with the two triangles as stored (any orientation; as CreaseTest
// takes them). Edges that are feature lines anyway (boundaries, patch borders, 3 or more
// sheets) are not given: a chain does not see them, so each caller must leave out the same
// ones. The result does not depend on the order of the edges.

#include <cstdint>
#include <string>
#include <vector>

#include "bpm/geometry.h"
#include "bpm/surface.h"

namespace bpm::detail {

// At a vertex of a chain, the two edges' directions may turn by at most this (degrees):
// a crease line of a CAD part bends gently from edge to edge, noise goes anywhere.
constexpr double kChainTurnDegrees = 20.0;
// ... and the larger of the two edges' normal angles is at most this times the smaller.
constexpr double kChainAngleRatio = 1.3;
// A chain counts only with at least this many edges: a line the mesh resolves, not a few
// edges that happen to line up. On a latitude-longitude grid with noise (a scan-like
// sphere whose edges lie in straight rows) 3 kinks in a row reached 15 % of the diagonal;
// the scans' chains (femur, elephant, armadillo) have at most 7 edges, fandisk's creases 10
// to 29.
constexpr int32_t kChainMinEdges = 8;

// An edge (u, w) of one sheet and the two triangles that share it, corners as stored.
struct SheetEdge {
    int32_t u = 0, w = 0;
    Tri t0{}, t1{};
};

// How shallow creases are found; chain_angle_degrees >= feature_angle_degrees finds none
// beyond CreaseTest's (then the answer is CreaseTest's for every edge).
struct CreaseRule {
    double feature_angle_degrees = 60.0;
    double chain_angle_degrees = 180.0;  // shallow edges: normals more than this apart
    double min_chain_length = 0.0;       // model units
};

// 1 for each of `edges` that is a crease, 0 otherwise (in the order given).
std::vector<uint8_t> find_creases(const std::vector<Vec3>& positions, const std::vector<SheetEdge>& edges,
                                  const CreaseRule& rule);

// Throws bpm::OptionError unless both angles are in [0, 180] degrees and the chain length
// (a fraction of the diagonal) in [0, 1]; NaN is refused. The one check of the rule's
// numbers for every call that takes them (simplify, smooth, bpm-info's summary); the
// message starts with `who` ("smooth: ") and names the option's field.
void check_crease_rule_numbers(double feature_angle_degrees, double chain_angle_degrees, double chain_length,
                               const std::string& who = "");

}  // namespace bpm::detail
