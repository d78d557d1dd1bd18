#pragma once
// The simplifier's own numbering of the input (issue 21): bpm::simplify renumbers the
// input's vertices in Morton (Z-order) order of their positions, and its triangles by
// their smallest new vertex id, runs the whole simplification on that numbering, and
// maps every output back to the caller's numbering at the end. Internal to libbpm.
//
// Why: the removal loop is bound by memory latency, spread over many functions (the
// planner, the embedding's paths, the grid, the coarse mesh's per-vertex and per-triangle
// arrays): all of them are indexed by vertex or triangle id, and a removal touches a star
// and its neighbourhood. In the order of a scanner or a subdivision, neighbours on the
// surface are far apart in memory; in Morton order they mostly share cache lines and
// pages. Measured outside bpm (renumbered OFF files, bench/results/manual/loop4.md): 9-10 %
// less CPU on 208k triangles, 20-25 % on 832k; inside bpm: bench/results/manual/morton.md.
//
// What the caller sees is unchanged in kind: Parametrization::original is the input as
// given (same vertex, triangle and patch order, same vertex data), and every id in the
// output (coarse_vertex_origin, node_original_vertex, node_original_edge with its
// parameter, piece_original_triangle, the recorded steps, the slivers' corners, the
// messages) is the caller's. The coarse vertices stay sorted by the caller's id. The
// removal order does change (ties of the cost and the queue are broken by vertex id, and
// the first candidates of a step are taken in id order), so the coarse surface is
// another valid one, not the same.
//
// Deterministic: the order depends only on the positions and the caller's ids (ties of
// the key by the caller's id), never on the thread count.

#include <cstdint>
#include <vector>

#include "bpm/parametrization.h"
#include "bpm/simplification_steps.h"
#include "bpm/surface.h"

namespace bpm::detail {

// Held through the run: 4 bytes per vertex and per triangle (the inverse of user_vertex
// is made only where needed, so that it is not held too).
struct InputOrder {
    std::vector<int32_t> user_vertex;    // internal vertex id -> the caller's
    std::vector<int32_t> user_triangle;  // internal triangle id -> the caller's
};

// The Morton order of `surface`'s vertices (positions quantised to 21 bits per axis in
// the bounding cube; ties and non-finite coordinates by the caller's id) and its
// triangles sorted by their smallest corner in that order (ties by the caller's id).
InputOrder morton_order(const Surface& surface);

// Renumbers `surface` (vertices, vertex data, triangles and their corners, patches) in
// place from the caller's numbering into `order`'s, and back. Exact: to_user_order after
// to_internal_order gives the same bytes.
void to_internal_order(Surface& surface, const InputOrder& order);
void to_user_order(Surface& surface, const InputOrder& order);

// The ids of a parametrization made on the internal numbering, in the caller's: the
// coarse vertices re-sorted by the caller's id (the coarse triangles' corners follow,
// their order and rotation are kept, so phi's barycentric coordinates stay valid),
// coarse_vertex_origin, node_original_vertex, node_original_edge (kept u < w: where the
// caller's ids swap an edge's ends, its parameter s becomes 1 - s, the same for every
// copy of the node, and its image is computed again from 1 - s as node_image_from_kind
// does) and piece_original_triangle. `p.original` must already be back in the caller's
// order (to_user_order); it is not touched.
void phi_to_user_order(Parametrization& p, const InputOrder& order);

// The removed vertices and the new triangles' corners in the caller's ids.
void steps_to_user_order(SimplificationSteps& steps, const InputOrder& order);

}  // namespace bpm::detail
