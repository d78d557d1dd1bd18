#pragma once
// Transfer of phi onto the new triangles of one fan (Krause & Sander §2.2.4): the free
// nodes of the star graph (star_graph.h) are located in the new triangulation, the
// straightened original edges are re-cut where they cross the new diagonals, and the
// deviation |phi(x) - x| of the result is measured. This is the cost of a removal; the
// exact validation of the resulting overlays is removal_validation.h.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "bpm/geometry.h"
#include "simplify/embedding.h"
#include "simplify/fan_retriangulation.h"
#include "simplify/star_fans.h"
#include "simplify/star_graph.h"

namespace bpm::detail {

// Where a straightened segment crosses a diagonal.
struct NewCrossing {
    int32_t diagonal;
    int32_t lo, hi;  // the diagonal as a coarse edge, lo < hi
    double s;        // along it from lo
    double sigma;    // along the original edge
    int32_t edge;
    double lambda;   // along the straightened segment
};

struct RecutEdges {
    std::vector<NewCrossing> crossings;  // per segment in graph order, along it by lambda
    std::vector<int32_t> cut_begin;      // segment i's crossings: [cut_begin[i], cut_begin[i+1])
};

// Sets new_triangle and bary, or diagonal and its (edge_lo, edge_hi, edge_s), of every
// free node of `graph` in the triangulation `tri` of polygon q. A node within 1e-9
// (barycentric) of a diagonal is put on it. With `check_inside`, first refuses a free
// node not strictly inside the polygon. Fails with `why` when a node is outside every
// new triangle, or (almost) on a coarse vertex or a link edge (unless the node and the
// link edge are an original sliver, see original_sliver). `boxes` is a buffer.
bool locate_free_nodes(const Embedding& emb, const Fan& fan, const std::vector<Vec2>& q, const FanTriangulation& tri, bool check_inside,
                       StarGraph& graph, std::vector<std::array<double, 4>>& boxes, std::string& why);

// Cuts every straightened segment of `graph` (its free nodes located) along the diagonals
// of `tri`, with exact predicates for whether they cross. Fails with `why` when a segment
// is degenerate or passes through a polygon corner, a cut falls within 1e-9 of a
// segment's or diagonal's end (unless an original sliver puts it there, see
// original_sliver), or two cuts of one segment coincide.
bool cut_segments(const Embedding& emb, const Fan& fan, const std::vector<Vec2>& q, const FanTriangulation& tri, const StarGraph& graph,
                  RecutEdges& cuts, std::string& why);

// Whether the original vertices u, w, c form an original triangle that is itself about as
// thin as the transfer's rounding margin or thinner (height over longest edge below 1e-6):
// an input sliver. Pieces of phi on such a triangle are as thin as the triangle whatever the
// removal does, so a node or a cut that comes (almost) onto a side only because of it
// makes no piece thinner, relative to the original triangle it maps onto, than the
// input already is; refusing it kept every sliver of the input in the coarse surface
// (a vertex 1e-12 off the line of its opposite edge stayed as a coarse triangle of
// R/r 1e21). Other near-degenerate transfers are still refused.
bool original_sliver(const Embedding& emb, int32_t u, int32_t w, int32_t c);

// The largest |phi(x) - x| over the moved nodes and the new crossings (phi is piecewise
// linear, so that is its maximum over the fan; the nodes on link edges keep their
// deviation). `x`: the coarse (= original) vertex positions.
double transfer_deviation(const std::vector<Vec3>& x, const Embedding& emb, const Fan& fan,
                          const FanTriangulation& tri, const StarGraph& graph, const RecutEdges& cuts);

}  // namespace bpm::detail
