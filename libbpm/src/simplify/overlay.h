#pragma once
// The overlay of the original surface on one coarse triangle: the part of the graph
// G (embedding.h) inside the triangle, its faces, and their triangulation into the
// pieces of the file format. The same code validates a proposed retriangulation
// before it is committed and exports the final parametrization, so what the
// simplifier accepts is exactly what bpm-check verifies.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "bpm/geometry.h"
#include "bpm/parametrization.h"
#include "simplify/embedding.h"

namespace bpm::detail {

struct GraphNode {
    Vec3 bary{};            // in the coarse triangle; exact zeros on its edges
    int8_t on_edge = -1;    // local edge k (corner k -> corner k+1) the node lies on, or -1
    int8_t corner = -1;     // 0..2 for a corner of the coarse triangle, else -1
    NodeKind kind = NodeKind::OriginalVertex;
    int32_t vertex = -1;    // original vertex (OriginalVertex, CoarseCorner)
    int32_t edge = -1;      // original edge id (EdgeCrossing)
    double sigma = 0.0;     // EdgeCrossing: position on the original edge
};

// The node at corner k of a coarse triangle whose corner is original vertex `vertex`.
inline GraphNode corner_node(int k, int32_t vertex) {
    GraphNode g;
    g.corner = static_cast<int8_t>(k);
    g.kind = NodeKind::CoarseCorner;
    g.vertex = vertex;
    g.bary = {0.0, 0.0, 0.0};
    g.bary[k] = 1.0;
    return g;
}

struct GraphSegment {
    int32_t n0, n1;  // node indices
    int32_t edge;    // original edge id this segment is part of
};

// Nodes and interior segments of one coarse triangle (segments along the triangle's
// edges are implied by the nodes on them).
struct TriangleGraph {
    std::vector<GraphNode> nodes;
    std::vector<GraphSegment> segments;
    // Buffers of build_triangle_graph(), kept with the graph so that a graph reused for
    // many triangles (the export of phi, the edge flips) does not allocate for each.
    struct Buffers {
        std::vector<std::pair<int32_t, int32_t>> vertex_node;    // (original vertex, node)
        std::vector<std::pair<uint64_t, int32_t>> crossing_node;  // (edge << 32 | crossing index, node)
        std::vector<int32_t> list, candidates;
        std::vector<SurfacePoint> points;
        std::vector<double> sigmas;
    } buffers;
};

struct OverlayFace {
    std::vector<int32_t> corners;   // node indices, counter-clockwise
    int32_t original_triangle = -1;
};

// Faces of the graph with the original triangle each lies in. Returns false (with a
// reason) when the graph is not a valid subdivision: a face that is not strictly
// convex and counter-clockwise in (b1,b2) coordinates (exact predicates), segments
// that cross, or a face whose original triangle cannot be identified.
// `orientation_sign[T]` is +1/-1: the orientation the coarse surface has relative to
// original triangle T; faces whose image has the other orientation are rejected.
bool compute_faces(const TriangleGraph& graph, const Embedding& embedding,
                   const std::vector<int8_t>& orientation_sign, std::vector<OverlayFace>& faces,
                   std::string* why = nullptr);

// compute_faces() for validation only: `scratch` keeps the buffers of its elements
// between calls (this runs for every new triangle of every full removal plan); its
// contents afterwards are unspecified.
bool check_faces(const TriangleGraph& graph, const Embedding& embedding, const std::vector<int8_t>& orientation_sign,
                 std::vector<OverlayFace>& scratch, std::string* why = nullptr);
// The same, telling how many faces it found: on success scratch[0 .. face_count) are the
// faces with their original triangles, as compute_faces() would return them.
bool check_faces(const TriangleGraph& graph, const Embedding& embedding, const std::vector<int8_t>& orientation_sign,
                 std::vector<OverlayFace>& scratch, size_t& face_count, std::string* why = nullptr);

// Splits every face into triangles that are positively oriented both in the
// parameter triangle and (times the orientation sign) in the original triangle.
bool triangulate_faces(const TriangleGraph& graph, const Embedding& embedding,
                       const std::vector<int8_t>& orientation_sign, const std::vector<OverlayFace>& faces,
                       std::vector<Tri>& pieces, std::vector<int32_t>& piece_triangle, std::string* why = nullptr);

// Barycentric coordinates of node n's image in original triangle T (exact from what
// the node is); false if the node is not on T.
bool image_barycentric(const GraphNode& n, const Embedding& embedding, int32_t original_triangle, Vec3& beta);

// Barycentric coordinates, in triangle `corners`, of the point at parameter s from lo
// to hi on the coarse edge {lo, hi}, which must be local edge k of the triangle. Exact
// zero opposite. Every producer of on-edge nodes goes through this one function so
// that what the simplifier validates is bit for bit what it stores.
inline Vec3 bary_on_side(const Tri& corners, int k, int32_t lo, double s) {
    const double from_first = corners[k] == lo ? s : 1.0 - s;
    Vec3 bary{0.0, 0.0, 0.0};
    bary[k] = 1.0 - from_first;
    bary[(k + 1) % 3] = from_first;
    return bary;
}

// Local edge of `corners` joining vertices x and y, or -1.
inline int local_edge(const Tri& corners, int32_t x, int32_t y) {
    for (int k = 0; k < 3; ++k) {
        const int32_t a = corners[k], b = corners[(k + 1) % 3];
        if ((a == x && b == y) || (a == y && b == x)) return k;
    }
    return -1;
}

// The image of a node on S0.
Vec3 node_image(const GraphNode& n, const Embedding& embedding);

// Builds the graph of coarse triangle t from the committed embedding.
void build_triangle_graph(const CoarseMesh& mesh, const Embedding& embedding, int32_t t, TriangleGraph& graph);

}  // namespace bpm::detail
