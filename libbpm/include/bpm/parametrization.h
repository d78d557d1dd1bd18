#pragma once
// A parametrized surface: the original surface S0, the coarse surface S and the
// bijective piecewise-linear map phi: S -> S0 (Krause & Sander, §2.2.3).
//
// phi is stored per coarse triangle as a small triangulation of its parameter
// triangle into "pieces" on which phi is affine. Every piece maps into exactly one
// original triangle. This is the in-memory twin of the HDF5 layout in
// spec/bpm-format.md; the names match the dataset names there.
//
// Conventions (normative, repeated in the spec):
// - A coarse triangle t = (c0, c1, c2) has parameter triangle with corners c0, c1, c2.
//   A node's barycentric coordinates (b0, b1, b2) refer to those corners in that
//   order, b0 + b1 + b2 = 1, all >= 0. Its parameter point is b0*c0 + b1*c1 + b2*c2.
// - Local edge k of a coarse triangle runs from corner k to corner (k+1) % 3; a node on
//   it has b[(k+2) % 3] == 0 exactly.
// - Node ranges and piece ranges are CSR: the nodes of coarse triangle t are
//   node_offsets[t] .. node_offsets[t+1]-1, its pieces piece_offsets[t] .. piece_offsets[t+1]-1,
//   and piece corners are node indices local to t (0 .. count-1).
// - A node that sits on a coarse edge or corner appears once in every coarse triangle
//   that contains that point, with the same image.

#include <cstdint>
#include <string>
#include <vector>

#include "bpm/geometry.h"
#include "bpm/surface.h"

namespace bpm {

enum class NodeKind : uint8_t {
    OriginalVertex = 0,  // an original vertex strictly inside a coarse triangle or on a coarse edge
    EdgeCrossing = 1,    // a point where an original edge crosses a coarse edge
    CoarseCorner = 2,    // a corner of the coarse triangle (always an original vertex too)
};

struct Parametrization {
    Surface original;  // S0
    Surface coarse;    // S
    // For each coarse vertex, the original vertex it is (point removal keeps vertices).
    std::vector<int32_t> coarse_vertex_origin;  // #S.V

    // --- phi, CSR per coarse triangle ---
    std::vector<int64_t> node_offsets;         // #S.T + 1, node_offsets[0] == 0
    std::vector<Vec3> node_barycentric;        // #N barycentric coordinates in the coarse triangle
    std::vector<Vec3> node_image;              // #N phi(node), a point on S0
    std::vector<NodeKind> node_kind;           // #N
    std::vector<int32_t> node_original_vertex; // #N original vertex for OriginalVertex/CoarseCorner, -1 otherwise
    std::vector<std::array<int32_t, 2>> node_original_edge;  // #N original edge (u, w), u < w, for EdgeCrossing; {-1,-1} otherwise
    std::vector<double> node_edge_parameter;   // #N for EdgeCrossing: image = (1-s)*x_u + s*x_w; NaN otherwise
    std::vector<int64_t> piece_offsets;        // #S.T + 1
    std::vector<Tri> pieces;                   // #P three local node indices, counter-clockwise in the parameter triangle
    std::vector<int32_t> piece_original_triangle;  // #P the original triangle the piece maps into

    int32_t num_coarse_triangles() const { return coarse.num_triangles(); }
    int64_t num_nodes() const { return static_cast<int64_t>(node_kind.size()); }
    int64_t num_pieces() const { return static_cast<int64_t>(pieces.size()); }
};

// phi = identity: coarse surface = original surface, one piece per triangle whose three
// nodes are the corners. Usable before any simplification.
Parametrization make_identity_parametrization(const Surface& original);

// The image of a node recomputed from what the node is (vertex position, or the point
// at the edge parameter on the original edge), with the expression of spec/bpm-format.md
// §6.2 so that every reader gets the same bits. Throws std::out_of_range for a node or
// vertex index out of range.
Vec3 node_image_from_kind(const Parametrization& p, int64_t node);

// node_image_from_kind of every node: what Parametrization::node_image holds. Format 2.0
// files do not store the images; read_bpm fills node_image with this.
std::vector<Vec3> node_images_from_kinds(const Parametrization& p);

}  // namespace bpm
