#pragma once
// Floater's shape-preserving map as the repair of a transfer (Krause & Sander §2.2.4):
// when the straightened original graph flips or squeezes a piece in the new triangles,
// its free nodes are repositioned so that every one is a convex combination of its
// neighbours, with mean value weights from the original surface's geometry, and the
// polygon boundary fixed. On a convex polygon this embeds the graph without flips
// (Floater 1997, 2003).

#include <string>

#include "simplify/embedding.h"
#include "simplify/star_graph.h"

namespace bpm::detail {

// Moves the free nodes of `graph` (nodes and segments gathered, star_graph.h); the fixed
// nodes stay. A graph without free nodes is left as it is. Fails with `why` (and the
// positions unchanged) when a free node has fewer than two neighbours, a neighbour at
// its own 3D position, or the linear system cannot be solved.
bool floater_repair(const Embedding& emb, StarGraph& graph, std::string& why);

}  // namespace bpm::detail
