#pragma once
// The simplifier's live form of phi (CoarseMesh + Embedding) written out in the file form,
// Parametrization (bpm/parametrization.h): per coarse triangle its nodes and pieces, from
// the overlay of the original surface on it (overlay.h). Internal to libbpm.

#include <cstdint>
#include <vector>

#include "bpm/parametrization.h"
#include "bpm/surface.h"
#include "simplify/coarse_mesh.h"
#include "simplify/embedding.h"
#include "simplify/planning_pool.h"

namespace bpm::detail {

// Replaces `out` with: original = `original` (not copied if it is out.original); coarse = the alive triangles of `mesh` in id
// order (CoarseMesh::to_surface, with coarse_vertex_origin); for each coarse triangle the
// nodes of its overlay (barycentric coordinates, image, kind, original vertex or edge and
// edge parameter) and its pieces, in CSR (node_offsets, piece_offsets).
// `orientation_sign[T]`: -1 where original triangle T is reversed in the coarse mesh's
// orientation (CoarseMesh::flipped_initially), else 1. The triangles are shared by the
// pool's threads in chunks; the output does not depend on the number of threads.
// Returns the largest distance between a node's image and its position on its coarse
// triangle (model units): the error max |phi(x) - x| of the coarse surface.
// \throw AlgorithmError (an internal error) if the overlay of a coarse triangle is invalid.
double export_parametrization(const Surface& original, const CoarseMesh& mesh, const Embedding& embedding,
                              const std::vector<int8_t>& orientation_sign, PlanningPool& pool, Parametrization& out);

}  // namespace bpm::detail
