// The ridge guard of the simplifier (simplify/ridge_guard.h).

#include "simplify/ridge_guard.h"

#include <algorithm>
#include <cmath>

#include "core/crease.h"
#include "core/directed_edge.h"

namespace bpm::detail {

std::vector<float> vertex_ridge_angles(const Surface& original, const Embedding& embedding) {
    std::vector<float> ridge(original.vertices.size(), 180.0f);
    for (int32_t e = 0; e < int32_t(embedding.edges.size()); ++e) {
        const int32_t first = embedding.edge_triangle_offsets[e];
        if (embedding.edge_triangle_offsets[e + 1] - first != 2) continue;
        const auto [u, w] = embedding.edges[e];
        const float angle = float(ridge_angle_degrees(original.vertices,
                                                      original.triangles[embedding.edge_triangles[first]],
                                                      original.triangles[embedding.edge_triangles[first + 1]], u, w));
        ridge[u] = std::min(ridge[u], angle);
        ridge[w] = std::min(ridge[w], angle);
    }
    return ridge;
}

namespace {

// The cosine between the normals `n0` of t0 and `n1` of t1 at their shared edge (u, w),
// the second turned over when both run the edge the same way (as ridge_angle_degrees
// compares them); 1 (flat) when either normal is zero (a degenerate triangle).
double oriented_cosine(const Vec3& n0, const Tri& t0, const Vec3& n1, const Tri& t1, int32_t u, int32_t w) {
    if (dot(n0, n0) == 0 || dot(n1, n1) == 0) return 1.0;
    const double c = dot(n0, n1);
    return runs_from(t0, u, w) == runs_from(t1, u, w) ? -c : c;
}

Vec3 normal_of(const std::vector<Vec3>& x, const Tri& t) {
    return triangle_normal(x[size_t(t[0])], x[size_t(t[1])], x[size_t(t[2])]);
}

}  // namespace

double sharpest_changed_ridge(const CoarseMesh& mesh, const std::vector<int32_t>& removed,
                              const std::vector<Tri>& added, int32_t feature_a, int32_t feature_b,
                              RidgeScratch& scratch, const std::vector<int32_t>& hole_sides) {
    // Compared as cosines (the ridge angle falls as the cosine does), one acos at the end:
    // planning runs this for every plan, cheap ones included. The result is the smallest
    // cosine over the counted edges, so the edges may be judged in any order: the sides of
    // the hole are judged after the diagonals, in three passes whose loads are asked for
    // (prefetch) one pass ahead. Walked one side at a time, the triangle lists of its ends,
    // the triangle outside and that triangle's third corner were cache misses one after
    // another (most of this function's time).
    const auto& x = mesh.positions();
    for (const Tri& t : added)
        for (int32_t u : t) mesh.prefetch_vertex(u);
    double lowest = 2.0;  // the smallest cosine of a counted edge; 2: none
    const auto is_removed = [&](int32_t t) { return std::find(removed.begin(), removed.end(), t) != removed.end(); };
    const auto has_edge = [](const Tri& t, int32_t u, int32_t w) {
        return (t[0] == u || t[1] == u || t[2] == u) && (t[0] == w || t[1] == w || t[2] == w);
    };
    // Each added triangle's normal once: a diagonal's two triangles are both added.
    auto& normals = scratch.normals;
    normals.resize(added.size());
    for (size_t i = 0; i < added.size(); ++i) normals[i] = normal_of(x, added[i]);
    auto& sides = scratch.sides;
    sides.clear();
    for (size_t i = 0; i < added.size(); ++i) {
        const Tri& t = added[i];
        for (int k = 0; k < 3; ++k) {
            const int32_t u = t[k], w = t[(k + 1) % 3];
            if ((u == feature_a && w == feature_b) || (u == feature_b && w == feature_a)) continue;
            if (mesh.is_feature_edge(u, w)) continue;
            const int32_t known = hole_sides.empty() ? -1 : hole_sides[3 * i + size_t(k)];
            if (known < -1) {
                // A diagonal the caller named with its other triangle.
                const size_t twin = size_t(-2 - known);
                if (twin > i) continue;
                lowest = std::min(lowest, oriented_cosine(normals[i], t, normals[twin], added[twin], u, w));
                continue;
            }
            if (known >= 0) {
                // A side the caller named, with its removed triangle: the other triangle on
                // it is the one the two lists share besides that one (exactly one, and not
                // removed, as below).
                // A merge of the two sorted lists whose steps are selects, not branches
                // (which list moves on depends on the data: a branch there is mispredicted
                // about every other step); the common triangles come in increasing order.
                int32_t outside = -1, common = 0;
                bool has_inside = false;
                const auto lu = mesh.triangles_of(u), lw = mesh.triangles_of(w);
                for (const int32_t *p = lu.begin(), *q = lw.begin(); p != lu.end() && q != lw.end();) {
                    const int32_t a = *p, b = *q;
                    const bool same = a == b;
                    common += same;
                    has_inside |= same && a == known;
                    outside = same && a != known ? a : outside;
                    p += a <= b;
                    q += b <= a;
                }
                if (common != 2 || !has_inside || is_removed(outside)) continue;
                mesh.prefetch_triangle(outside);
                sides.push_back({int32_t(i), k, outside, known});
                continue;
            }
            // Another added triangle on the edge: a new diagonal, judged once (by the later one).
            int32_t twins = 0, twin = -1;
            for (size_t j = 0; j < added.size(); ++j)
                if (j != i && has_edge(added[j], u, w)) {
                    ++twins;
                    twin = int32_t(j);
                }
            if (twins > 1) continue;
            if (twins == 1) {
                if (size_t(twin) > i) continue;
                lowest = std::min(lowest, oriented_cosine(normals[i], t, normals[size_t(twin)], added[size_t(twin)], u, w));
                continue;
            }
            // A side of the hole: one triangle outside, one removed. The alive triangles on
            // both u and w, by merging their sorted lists (no scattered reads of corners).
            int32_t outside = -1, inside = -1, others = 0;
            const auto lu = mesh.triangles_of(u), lw = mesh.triangles_of(w);
            for (const int32_t *p = lu.begin(), *q = lw.begin(); p != lu.end() && q != lw.end();) {
                if (*p < *q) {
                    ++p;
                } else if (*q < *p) {
                    ++q;
                } else {
                    if (is_removed(*p)) {
                        if (inside < 0) inside = *p;
                        else ++others;
                    } else if (outside < 0) {
                        outside = *p;
                    } else {
                        ++others;
                    }
                    ++p;
                    ++q;
                }
            }
            if (outside < 0 || inside < 0 || others > 0) continue;
            mesh.prefetch_triangle(outside);
            sides.push_back({int32_t(i), k, outside, inside});
        }
    }
    // The outside triangles' corners are on their way: ask for their positions (two of
    // them, on the link, are at hand already).
    for (const HoleSide& side : sides)
        for (int32_t c : mesh.triangle(side.outside)) __builtin_prefetch(x.data() + c);
    for (const HoleSide& side : sides) {
        const Tri& t = added[size_t(side.added)];
        const int32_t u = t[side.k], w = t[(side.k + 1) % 3];
        const Tri& o = mesh.triangle(side.outside);
        const Vec3 no = normal_of(x, o);
        const double after = oriented_cosine(no, o, normals[size_t(side.added)], t, u, w);
        if (after >= lowest) continue;  // cannot be the sharpest: skip the one before
        const Tri& r = mesh.triangle(side.inside);
        if (after < oriented_cosine(no, o, normal_of(x, r), r, u, w)) lowest = after;
    }
    if (lowest > 1.0) return 180.0;
    return 180.0 - std::acos(std::clamp(lowest, -1.0, 1.0)) * (180.0 / M_PI);
}

}  // namespace bpm::detail
