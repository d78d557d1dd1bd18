// The ridge guard of the simplifier (simplify/ridge_guard.h).

#include "simplify/ridge_guard.h"

#include <algorithm>

#include "core/crease.h"

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

double sharpest_changed_ridge(const CoarseMesh& mesh, const std::vector<int32_t>& removed,
                              const std::vector<Tri>& added, int32_t feature_a, int32_t feature_b,
                              std::vector<int32_t>& scratch) {
    const auto& x = mesh.positions();
    double sharpest = 180.0;
    const auto is_removed = [&](int32_t t) { return std::find(removed.begin(), removed.end(), t) != removed.end(); };
    const auto has_edge = [](const Tri& t, int32_t u, int32_t w) {
        return (t[0] == u || t[1] == u || t[2] == u) && (t[0] == w || t[1] == w || t[2] == w);
    };
    for (size_t i = 0; i < added.size(); ++i) {
        const Tri& t = added[i];
        for (int k = 0; k < 3; ++k) {
            const int32_t u = t[k], w = t[(k + 1) % 3];
            if ((u == feature_a && w == feature_b) || (u == feature_b && w == feature_a)) continue;
            if (mesh.is_feature_edge(u, w)) continue;
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
                sharpest = std::min(sharpest, ridge_angle_degrees(x, t, added[size_t(twin)], u, w));
                continue;
            }
            // A side of the hole: one triangle outside, one removed.
            mesh.edge_triangles(u, w, scratch);
            int32_t outside = -1, inside = -1, others = 0;
            for (int32_t s : scratch) {
                if (is_removed(s)) {
                    if (inside < 0) inside = s;
                    else ++others;
                } else if (outside < 0) {
                    outside = s;
                } else {
                    ++others;
                }
            }
            if (outside < 0 || inside < 0 || others > 0) continue;
            const Tri& o = mesh.triangle(outside);
            const double after = ridge_angle_degrees(x, o, t, u, w);
            if (after < ridge_angle_degrees(x, o, mesh.triangle(inside), u, w)) sharpest = std::min(sharpest, after);
        }
    }
    return sharpest;
}

}  // namespace bpm::detail
