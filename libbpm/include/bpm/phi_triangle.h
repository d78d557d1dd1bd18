#pragma once
// A read view of phi on one coarse triangle: its nodes and its pieces, indexed locally
// (0 .. count-1, the numbering the piece corners use), so that callers do not compute
// CSR ranges themselves. The global index of a node or piece, the one bpm-check reports
// and the one arrays parallel to Parametrization's use, is first_node() + i and
// first_piece() + j.
//
// The view holds a reference to the Parametrization and two offsets; it is cheap to
// make and must not outlive the parametrization or survive a change of its arrays.

#include <array>
#include <cstdint>

#include "bpm/geometry.h"
#include "bpm/parametrization.h"

namespace bpm {

class PhiTriangle {
public:
    // \pre the layout of `p` is valid (bpm-check's format check, or a file read by
    //      read_bpm) and 0 <= t < p.num_coarse_triangles(). Not checked.
    PhiTriangle(const Parametrization& p, int32_t t)
        : p_(&p),
          triangle_(t),
          node0_(p.node_offsets[static_cast<size_t>(t)]),
          nodes_(p.node_offsets[static_cast<size_t>(t) + 1] - node0_),
          piece0_(p.piece_offsets[static_cast<size_t>(t)]),
          pieces_(p.piece_offsets[static_cast<size_t>(t) + 1] - piece0_) {}

    int32_t triangle() const { return triangle_; }
    // The corners of the coarse triangle (coarse vertex ids); barycentric coordinates
    // refer to them in this order.
    const Tri& corners() const { return p_->coarse.triangles[static_cast<size_t>(triangle_)]; }

    // --- nodes, i in [0, num_nodes()) ---
    int64_t num_nodes() const { return nodes_; }
    int64_t first_node() const { return node0_; }  // global index of local node 0
    const Vec3& barycentric(int64_t i) const { return p_->node_barycentric[at(node0_, i)]; }
    const Vec3& image(int64_t i) const { return p_->node_image[at(node0_, i)]; }  // phi(node), on S0
    NodeKind kind(int64_t i) const { return p_->node_kind[at(node0_, i)]; }
    // Original vertex for OriginalVertex/CoarseCorner, -1 for EdgeCrossing.
    int32_t original_vertex(int64_t i) const { return p_->node_original_vertex[at(node0_, i)]; }
    // Original edge (u, w), u < w, for EdgeCrossing; {-1, -1} otherwise.
    const std::array<int32_t, 2>& original_edge(int64_t i) const { return p_->node_original_edge[at(node0_, i)]; }
    // s with image = (1-s) x_u + s x_w for EdgeCrossing; NaN otherwise.
    double edge_parameter(int64_t i) const { return p_->node_edge_parameter[at(node0_, i)]; }

    // --- pieces, j in [0, num_pieces()) ---
    int64_t num_pieces() const { return pieces_; }
    int64_t first_piece() const { return piece0_; }  // global index of local piece 0
    // Three local node indices, counter-clockwise in the parameter triangle.
    const Tri& piece(int64_t j) const { return p_->pieces[at(piece0_, j)]; }
    // Global node index of corner k (0..2) of piece j.
    int64_t piece_node(int64_t j, int k) const { return node0_ + piece(j)[static_cast<size_t>(k)]; }
    // The original triangle piece j maps into.
    int32_t original_triangle(int64_t j) const { return p_->piece_original_triangle[at(piece0_, j)]; }

private:
    static size_t at(int64_t first, int64_t local) { return static_cast<size_t>(first + local); }

    const Parametrization* p_;
    int32_t triangle_;
    int64_t node0_, nodes_, piece0_, pieces_;
};

}  // namespace bpm
