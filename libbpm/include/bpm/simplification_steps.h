#pragma once
// The sequence of point removals that turned the original surface S0 into the coarse
// surface S, recorded by the simplifier on request (SimplifyOptions::record_steps,
// bpm-simplify --record-steps) and stored in the optional /simplification_steps group
// of a bpm file (spec/bpm-format.md §10.1). bpm-check --replay re-applies the removals
// to the connectivity of S0 and checks each one (bpm/check.h, check_replay).
//
// Layout (CSR, the in-memory twin of the HDF5 datasets of the same names):
//   step s removed original vertex `vertex[s]` together with all triangles around it,
//   and filled the hole with triangles triangle_offsets[s] .. triangle_offsets[s+1]-1
//   of `triangles` (original vertex indices, in the simplifier's orientation) with the
//   patch ids `triangle_patches`.

#include <cstdint>
#include <vector>

#include "bpm/geometry.h"

namespace bpm {

struct SimplificationSteps {
    std::vector<int32_t> vertex;                // #S removed original vertex of each step, in removal order
    std::vector<int64_t> triangle_offsets{0};   // #S + 1, CSR into triangles; triangle_offsets[0] == 0
    std::vector<Tri> triangles;                 // #R new triangles, original vertex indices
    std::vector<int32_t> triangle_patches;      // #R patch id of each new triangle

    int64_t num_steps() const { return static_cast<int64_t>(vertex.size()); }
    int64_t num_triangles() const { return static_cast<int64_t>(triangles.size()); }

    // Appends one removal: `removed` and the triangles (with their patches) that replaced its star.
    void append(int32_t removed, const std::vector<Tri>& new_triangles, const std::vector<int32_t>& new_patches) {
        vertex.push_back(removed);
        triangles.insert(triangles.end(), new_triangles.begin(), new_triangles.end());
        triangle_patches.insert(triangle_patches.end(), new_patches.begin(), new_patches.end());
        triangle_offsets.push_back(static_cast<int64_t>(triangles.size()));
    }
};

}  // namespace bpm
