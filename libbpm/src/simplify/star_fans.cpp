#include "simplify/star_fans.h"

#include <algorithm>
#include <array>

namespace bpm::detail {

namespace {

// Rotates a triangle so that v is first; returns the other two in order.
inline bool rotate_to(const Tri& t, int32_t v, int32_t& x, int32_t& y) {
    for (int k = 0; k < 3; ++k)
        if (t[k] == v) {
            x = t[(k + 1) % 3];
            y = t[(k + 2) % 3];
            return true;
        }
    return false;
}

// Other triangle on edge (v,x), or -1 unless the edge has exactly two: the alive
// triangles of v containing x, in the order of CoarseMesh::edge_triangles().
// `corners[i]`: the corners of tris[i]; `by_corner`: empty, or (corner, i) for every
// corner other than v of every corners[i], sorted (index_corners()).
int32_t other_triangle_across(VertexTriangleLists::View tris, const std::vector<Tri>& corners,
                              const std::vector<std::array<int32_t, 2>>& by_corner, int32_t t, int32_t x) {
    int32_t found[2] = {-1, -1};
    int count = 0;
    if (!by_corner.empty()) {
        // The same triangles in the same order (by i), found in O(log n).
        for (auto it = std::lower_bound(by_corner.begin(), by_corner.end(), std::array<int32_t, 2>{x, -1});
             it != by_corner.end() && (*it)[0] == x; ++it) {
            if (count < 2) found[count] = tris[size_t((*it)[1])];
            ++count;
        }
    } else {
        for (size_t i = 0; i < corners.size(); ++i) {
            const Tri& c = corners[i];
            if (c[0] == x || c[1] == x || c[2] == x) {
                if (count < 2) found[count] = tris[i];
                ++count;
            }
        }
    }
    if (count != 2) return -1;
    return found[0] == t ? found[1] : found[0];
}

// The walks look for the triangles on an edge (v, x) once per triangle: a scan of the
// star each time is quadratic, which a star of a few dozen triangles does not notice but
// the centre of a CAD disc (thousands of triangles, re-classified each time a corner
// goes) does. Above kIndexedStar triangles they are looked up in a sorted list.
constexpr size_t kIndexedStar = 64;
void index_corners(int32_t v, const std::vector<Tri>& corners, std::vector<std::array<int32_t, 2>>& by_corner) {
    by_corner.clear();
    if (corners.size() <= kIndexedStar) return;
    for (size_t i = 0; i < corners.size(); ++i)
        for (int32_t x : corners[i])
            if (x != v) by_corner.push_back({x, int32_t(i)});  // v is in all: never looked up
    std::sort(by_corner.begin(), by_corner.end());
}

// The closed fan of a vertex off the feature lines, from its smallest triangle id.
VertexClass walk_disk(const CoarseMesh& mesh, int32_t v, const std::vector<Tri>& corners,
                      const std::vector<std::array<int32_t, 2>>& by_corner, std::vector<Fan>& fans, std::string& why) {
    const auto& tris = mesh.triangles_of(v);
    fans.resize(1);
    Fan& fan = fans[0];
    fan.closed = true;
    fan.link.clear();
    fan.triangles.clear();
    const int32_t t0 = *std::min_element(tris.begin(), tris.end());
    int32_t x = -1, y = -1;
    rotate_to(mesh.triangle(t0), v, x, y);
    fan.link.push_back(x);
    fan.triangles.push_back(t0);
    int32_t t = t0, last = y;
    while (true) {
        const int32_t n = other_triangle_across(tris, corners, by_corner, t, last);
        if (n < 0) {
            why = "non-manifold edge without feature mark";
            return VertexClass::Feature;
        }
        if (n == t0) break;
        int32_t nx = -1, ny = -1;
        rotate_to(mesh.triangle(n), v, nx, ny);
        if (nx != last) {
            why = "inconsistent orientation in the star";
            return VertexClass::Feature;
        }
        fan.link.push_back(last);
        fan.triangles.push_back(n);
        t = n;
        last = ny;
        if (fan.triangles.size() > tris.size()) {
            why = "star is not a disk";
            return VertexClass::Feature;
        }
    }
    if (last != fan.link.front() || fan.triangles.size() != tris.size()) {
        why = "star is not a single disk (non-manifold vertex)";
        return VertexClass::Feature;
    }
    return VertexClass::Regular;
}

// The open fans between feature edges v -- f0 and v -- f1, one per sheet.
VertexClass walk_half_disks(const CoarseMesh& mesh, int32_t v, int32_t f0, int32_t f1, const std::vector<Tri>& corners,
                            const std::vector<std::array<int32_t, 2>>& by_corner, std::vector<int32_t>& starts,
                            std::vector<Fan>& fans, std::string& why) {
    const auto& tris = mesh.triangles_of(v);
    // Half-disks: start at every triangle on the first feature edge and walk across
    // non-feature edges until the second feature edge.
    mesh.edge_triangles(v, f0, starts);
    size_t covered = 0;
    fans.resize(starts.size());
    for (size_t i = 0; i < starts.size(); ++i) {
        const int32_t t0 = starts[i];
        Fan& fan = fans[i];
        fan.closed = false;
        int32_t x = -1, y = -1;
        rotate_to(mesh.triangle(t0), v, x, y);
        const bool forward = x == f0;  // the stored orientation runs from f0 around v
        auto& link = fan.link;
        auto& triangles = fan.triangles;
        link.assign(1, f0);
        triangles.assign(1, t0);
        int32_t t = t0, last = forward ? y : x;
        while (true) {
            link.push_back(last);
            if (last == f1 || last == f0) break;
            const int32_t n = other_triangle_across(tris, corners, by_corner, t, last);
            if (n < 0) {
                why = "non-manifold edge without feature mark";
                return VertexClass::Feature;
            }
            int32_t nx = -1, ny = -1;
            rotate_to(mesh.triangle(n), v, nx, ny);
            if ((forward ? nx : ny) != last) {
                why = "inconsistent orientation in the star";
                return VertexClass::Feature;
            }
            triangles.push_back(n);
            t = n;
            last = forward ? ny : nx;
            if (triangles.size() > tris.size()) {
                why = "star is not made of half-disks";
                return VertexClass::Feature;
            }
        }
        if (link.back() != f1) {
            why = "half-disk does not reach the other feature edge";
            return VertexClass::Feature;
        }
        if (!forward) {
            std::reverse(link.begin(), link.end());
            std::reverse(triangles.begin(), triangles.end());
        }
        covered += triangles.size();
    }
    if (covered != tris.size()) {
        why = "star is not made of half-disks";
        return VertexClass::Feature;
    }
    return VertexClass::FeatureLine;
}

}  // namespace

VertexClass classify_star(const CoarseMesh& mesh, int32_t v, bool force_disk, std::vector<Fan>& fans,
                          bool& crease_line, std::string& why, StarScratch& scratch) {
    crease_line = false;
    // `fans` keeps its elements' buffers between calls: resized, never cleared.
    const auto& tris = mesh.triangles_of(v);
    if (tris.empty()) {
        fans.clear();
        why = "vertex already removed";
        return VertexClass::Feature;
    }
    switch (mesh.corner(v)) {
        case CoarseMesh::Corner::Junction:
            why = std::string(kCornerJunctionReason);
            return VertexClass::Feature;
        case CoarseMesh::Corner::ConeEnd:
            why = std::string(kCornerConeEndReason);
            return VertexClass::Feature;
        case CoarseMesh::Corner::None: break;
    }
    auto& hard = scratch.hard;
    auto& crease = scratch.crease;
    auto& features = scratch.features;
    auto& starts = scratch.starts;
    // The corners of the star's triangles, read once: the walks below look up the
    // triangles on an edge (v, x) many times.
    auto& corners = scratch.corners;
    hard.clear();
    crease.clear();
    features.clear();
    starts.clear();
    corners.clear();
    for (int32_t t : tris) corners.push_back(mesh.triangle(t));
    // Most vertices have no feature edge at all: nothing to look up then.
    if (mesh.on_feature_line(v)) {
        for (const Tri& c : corners)
            for (int32_t x : c) {
                if (x == v) continue;
                const auto kind = mesh.feature(v, x);
                if (kind == CoarseMesh::Feature::Hard) hard.push_back(x);
                if (kind == CoarseMesh::Feature::Crease) crease.push_back(x);
            }
        for (auto* list : {&hard, &crease}) {
            std::sort(list->begin(), list->end());
            list->erase(std::unique(list->begin(), list->end()), list->end());
        }
    }
    // Hard feature lines are always kept. Creases are followed when exactly two meet
    // here; otherwise (a crease ending, a junction of creases) the vertex is removed as
    // a disk if the geometric error allows it.
    if (!hard.empty())
        features = hard;
    else if (crease.size() == 2 && !force_disk) {
        features = crease;
        crease_line = true;
    }

    if (!features.empty() && features.size() != 2) {
        why = features.size() == 1 ? "end of a feature line" : "meeting point of feature lines";
        return VertexClass::Feature;
    }
    index_corners(v, corners, scratch.by_corner);
    if (features.empty()) return walk_disk(mesh, v, corners, scratch.by_corner, fans, why);
    return walk_half_disks(mesh, v, features[0], features[1], corners, scratch.by_corner, starts, fans, why);
}

}  // namespace bpm::detail
