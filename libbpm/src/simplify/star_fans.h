#pragma once
// The star of a coarse vertex v split into fans, the unit that vertex removal flattens
// and retriangulates (Krause & Sander §2.2.4, §2.4): the whole disk of a vertex off
// the feature lines, or the half-disks between the two feature edges of a vertex on a
// feature line. classify_star() decides which, or why v is kept.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "bpm/geometry.h"
#include "simplify/coarse_mesh.h"

namespace bpm::detail {

enum class VertexClass : uint8_t {
    Regular,      // manifold vertex off every feature line: removed as a disk
    FeatureLine,  // exactly two feature edges: removed half-disk by half-disk
    Feature,      // kept
};

// Why a corner (CoarseMesh::Corner) is kept: the reasons SimplifyResult::blocked counts.
inline constexpr const char* kCornerJunctionReason = "feature vertex: three or more feature edges meet (a corner)";
inline constexpr const char* kCornerConeEndReason = "feature vertex: a crease ends at a sharp cone";

inline int32_t mod(int32_t i, int32_t n) {
    // Nearly always one step outside [0, n): no division then.
    if (i >= 0 && i < n) return i;
    if (i < 0 && i >= -n) return i + n;
    if (i >= n && i - n < n) return i - n;
    return ((i % n) + n) % n;
}

// One fan of triangles around the removed vertex v: the whole disk of a regular
// vertex (closed) or one half-disk between the two feature edges (open).
// Triangle i is (v, link[i], link[i+1]) (indices mod n when closed), counter-clockwise
// in the stored orientation. Its polygon (the hole left by v) has the corners link[0..n-1]
// and side i from link[i] to link[i+1]; an open fan's side n-1 (from link[n-1] back to
// link[0]) is the new feature edge, which passes through where v was.
struct Fan {
    bool closed = true;
    std::vector<int32_t> link;
    std::vector<int32_t> triangles;

    int32_t corners() const { return static_cast<int32_t>(link.size()); }
    // Polygon corner index of a coarse vertex, or -1.
    int32_t corner_index(int32_t vertex) const {
        for (int32_t i = 0; i < corners(); ++i)
            if (link[i] == vertex) return i;
        return -1;
    }
    // Index of coarse triangle t in this fan, or -1.
    int32_t triangle_index(int32_t t) const {
        for (size_t i = 0; i < triangles.size(); ++i)
            if (triangles[i] == t) return static_cast<int32_t>(i);
        return -1;
    }
    // Is spoke i (the edge v -- link[i]) inside the fan? In an open fan the first and the
    // last spoke are the feature edges, on its boundary.
    bool is_interior_spoke(int32_t i) const { return closed || (i > 0 && i < corners() - 1); }
    // Spoke index of coarse edge (x, y) if it is a spoke of centre v, or -1.
    int32_t spoke_index(int32_t v, int32_t x, int32_t y) const {
        const int32_t other = x == v ? y : (y == v ? x : -1);
        return other < 0 ? -1 : corner_index(other);
    }
    // Polygon side of link edge (x, y), or -1 (an open fan's new edge is not a link edge).
    int32_t link_side(int32_t x, int32_t y) const {
        const int32_t n = corners();
        const int32_t sides = closed ? n : n - 1;
        for (int32_t i = 0; i < sides; ++i) {
            const int32_t a = link[i], b = link[mod(i + 1, n)];
            if ((a == x && b == y) || (a == y && b == x)) return i;
        }
        return -1;
    }
};

// Buffers of classify_star() (see RemovalScratch in vertex_removal.cpp).
struct StarScratch {
    std::vector<int32_t> hard, crease, features, starts;
    std::vector<Tri> corners;  // of the star's triangles, read once
    std::vector<std::array<int32_t, 2>> by_corner;  // (corner, index in corners), sorted: large stars only
};

// Splits the star of v into fans and classifies v. Regular: one closed fan with all the
// triangles of v. FeatureLine: one open fan per sheet between the two feature edges
// (hard ones, or exactly two creases unless `force_disk`; `crease_line` tells the latter),
// each counter-clockwise from one feature neighbour to the other. Feature: v is kept,
// `why` says why (corner, end or junction of feature lines, non-manifold or
// inconsistently oriented star); `fans` is then unspecified. `fans` keeps its elements'
// buffers between calls.
VertexClass classify_star(const CoarseMesh& mesh, int32_t v, bool force_disk, std::vector<Fan>& fans,
                          bool& crease_line, std::string& why, StarScratch& scratch);

}  // namespace bpm::detail
