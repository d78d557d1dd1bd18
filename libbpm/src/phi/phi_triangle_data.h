#pragma once
// phi on one coarse triangle as an editable value: its nodes and pieces in local
// numbering, the form the algorithms that rebuild phi triangle by triangle work in
// (smoothing replaces the nodes and pieces of the two triangles of a pair; the refinement
// builds one per refined triangle; the simplifier's export one per coarse triangle). The read-only view of the same data inside a Parametrization is PhiTriangle
// (bpm/phi_triangle.h); this is its copy that can be changed and stored back.
//
// Conventions: those of bpm/parametrization.h. Piece corners are indices into this
// triangle's node arrays; the arrays are parallel, one entry per node or per piece.

#include <array>
#include <cstdint>
#include <vector>

#include "bpm/geometry.h"
#include "bpm/parametrization.h"

namespace bpm::detail {

struct PhiTriangleData {
    // --- nodes, parallel arrays (the node_* arrays of Parametrization, for this triangle) ---
    std::vector<Vec3> barycentric;                     // in the coarse triangle's corner order
    std::vector<Vec3> image;                           // phi(node), a point on S0
    std::vector<NodeKind> kind;
    std::vector<int32_t> original_vertex;              // -1 for an edge crossing
    std::vector<std::array<int32_t, 2>> original_edge; // {-1, -1} unless an edge crossing
    std::vector<double> edge_parameter;                // NaN unless an edge crossing
    // --- pieces, parallel arrays ---
    std::vector<Tri> pieces;                           // local node indices, counter-clockwise
    std::vector<int32_t> piece_original_triangle;

    size_t num_nodes() const { return kind.size(); }

    // Empties every array, keeping their memory (for a buffer reused triangle after triangle).
    void clear() {
        barycentric.clear();
        image.clear();
        kind.clear();
        original_vertex.clear();
        original_edge.clear();
        edge_parameter.clear();
        pieces.clear();
        piece_original_triangle.clear();
    }
    size_t num_pieces() const { return pieces.size(); }

    // Appends a node and returns its local index.
    int32_t add_node(const Vec3& b, const Vec3& node_image, NodeKind node_kind, int32_t vertex,
                     const std::array<int32_t, 2>& edge, double s) {
        barycentric.push_back(b);
        image.push_back(node_image);
        kind.push_back(node_kind);
        original_vertex.push_back(vertex);
        original_edge.push_back(edge);
        edge_parameter.push_back(s);
        return static_cast<int32_t>(kind.size() - 1);
    }
    void add_piece(const Tri& corners, int32_t original_triangle) {
        pieces.push_back(corners);
        piece_original_triangle.push_back(original_triangle);
    }
};

// A copy of phi on coarse triangle t of `p`.
// \pre the layout of `p` is valid and 0 <= t < p.num_coarse_triangles() (as PhiTriangle).
PhiTriangleData load_phi_triangle(const Parametrization& p, int32_t t);

// Empties phi in `p` (no nodes, no pieces, both offset arrays {0}), so that the coarse
// triangles can be stored again in order with append_phi_triangle(). The surfaces and
// coarse_vertex_origin are left alone.
void clear_phi(Parametrization& p);

// Stores `t` as phi of the next coarse triangle of `p` (the one numbered
// node_offsets.size() - 1): appends its nodes and pieces and closes both CSR ranges.
void append_phi_triangle(Parametrization& p, const PhiTriangleData& t);

// Stores phi of every coarse triangle of `part` (its own CSR, offsets from 0) after those
// of `p`, in order: what a task that built phi for a run of triangles hands back.
void append_phi(Parametrization& p, const Parametrization& part);

}  // namespace bpm::detail
