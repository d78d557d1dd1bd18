#pragma once
// The sides of a surface's triangles grouped by edge (internal to libbpm): one pass of
// reading a surface answers from it both whether the triangles are consistently oriented
// (io/surface_io.cpp) and which edges are boundary edges (find_open_seam). A counting sort
// by the smaller vertex of each side, then the few sides of each vertex by the larger
// one: on 832k triangles a fifth of the time of the hash map of edges it replaces, and of
// the sort of 64-bit edge keys that find_open_seam made on its own.

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "bpm/surface.h"

namespace bpm::detail {

class EdgeUses {
public:
    // Every side a -> b of every triangle with 0 <= a, b < num_vertices and a != b (others
    // are skipped: left for validate_surface()).
    explicit EdgeUses(const Surface& surface);

    // One use of an edge, as for_each_edge hands it over.
    struct Use {
        int32_t larger;  // the larger vertex of its edge
        uint32_t code;   // triangle * 2 + (whether the triangle runs from the smaller vertex to the larger)
        int32_t triangle() const { return int32_t(code >> 1); }
        bool ascending() const { return (code & 1u) != 0; }
    };

    // Calls visit(a, b, uses, count) for every edge {a < b}, in increasing (a, b) order;
    // its `count` uses in triangle order (a triangle with a repeated corner, which
    // validate_surface() refuses, has two sides on one edge: in corner order).
    template <class Visit>
    void for_each_edge(Visit&& visit) const {
        for (size_t a = 0; a + 1 < offsets_.size(); ++a)
            for (size_t i = offsets_[a], end = offsets_[a + 1]; i < end;) {
                size_t j = i + 1;
                while (j < end && uses_[j].larger == uses_[i].larger) ++j;
                visit(int32_t(a), uses_[i].larger, &uses_[i], j - i);
                i = j;
            }
    }

    // The number of distinct edges (calls of for_each_edge's visit).
    size_t num_edges() const { return num_edges_; }
    // The number of uses (sides kept), over all edges.
    size_t num_uses() const { return uses_.size(); }

    // The edges with one use, (smaller, larger) in increasing order.
    std::vector<std::pair<int32_t, int32_t>> boundary_edges() const;

private:
    std::vector<size_t> offsets_;  // per smaller vertex, into uses_ (CSR)
    std::vector<Use> uses_;        // by smaller vertex, larger vertex, triangle
    size_t num_edges_ = 0;
};

// find_open_seam(surface, max_gap) with the surface's boundary edges given
// (EdgeUses::boundary_edges()), for a caller that has counted the edges already.
std::optional<OpenSeam> find_open_seam(const Surface& surface, const std::vector<std::pair<int32_t, int32_t>>& boundary,
                                       double max_gap);

}  // namespace bpm::detail
