#pragma once
// The components of a set of triangles through shared vertices (two triangles are in one
// component when a chain of triangles, each sharing a vertex with the next, joins them).
// Removals and flips never change them (their new triangles join the same link
// vertices), so the simplifier's island guard numbers them once, and bpm-check's
// junctions check compares each component of S with its component of S0. A union-find
// with path halving; the triangles come one by one (add()), so a caller with dead slots
// (the coarse mesh) needs no copy of its alive ones. Internal to libbpm.

#include <cstdint>
#include <vector>

#include "bpm/geometry.h"

namespace bpm::detail {

class VertexComponents {
public:
    // For vertices 0 .. vertex_count - 1.
    explicit VertexComponents(size_t vertex_count);

    // Joins t's corners (each in [0, vertex_count)).
    void add(const Tri& t);

    // The number of components; `component` gets one entry per vertex: its component,
    // numbered 0, 1, ... in the order of each component's smallest vertex, or -1 for a
    // vertex of no added triangle.
    int32_t number(std::vector<int32_t>& component);

private:
    int32_t root(int32_t x);

    std::vector<int32_t> parent_;  // the smaller root wins a union
    std::vector<char> used_;       // per vertex: a corner of an added triangle
};

}  // namespace bpm::detail
