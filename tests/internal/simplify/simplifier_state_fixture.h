#pragma once
// A test fixture of the internal simplifier tests: the simplifier's live state (coarse
// mesh, embedding, orientation signs) for an original surface, with a few removals and
// the export, so that one phase can be tested without running the whole Simplifier.
#include <algorithm>
#include <vector>

#include "bpm/surface.h"
#include "simplify/coarse_mesh.h"
#include "simplify/embedding.h"
#include "simplify/export_phi.h"
#include "simplify/planning_pool.h"
#include "simplify/vertex_removal.h"

namespace bpm::detail::test {

// The simplifier's state for `original`, before any removal.
struct LiveState {
    CoarseMesh mesh;
    Embedding embedding;
    std::vector<int8_t> sign;
    std::vector<Vec3> no_normals;  // VertexRemover keeps a reference: no normal deviation
    std::vector<float> no_ridges;  // ... and no ridge guard
    // `feature_angle`: creases above it are feature edges (180: none, only boundaries and
    // patch borders).
    explicit LiveState(const Surface& original, double feature_angle = 60.0) : mesh(original) {
        mesh.mark_feature_edges(feature_angle);
        sign.resize(original.triangles.size());
        for (int32_t t = 0; t < original.num_triangles(); ++t) sign[t] = mesh.flipped_initially(t) ? -1 : 1;
        embedding.init_identity(original, mesh.triangle_capacity());
    }
    // Removes up to `count` vertices, every `stride`th one whose full plan is valid.
    int remove_some(int count, int stride) {
        VertexRemover remover(mesh, embedding, sign, no_normals, no_ridges);
        RemovalPlan plan;
        int removed = 0;
        for (int32_t v = 0; v < int32_t(sign.size()) && removed < count; v += stride) {
            if (v >= int32_t(mesh.positions().size()) || !mesh.vertex_alive(v)) continue;
            remover.plan(v, true, plan);
            if (!plan.valid) continue;
            commit_removal(mesh, embedding, plan);
            ++removed;
        }
        return removed;
    }
    // phi of the current state, as the simplifier exports it (one thread).
    Parametrization exported(const Surface& original) {
        PlanningPool pool(1);
        Parametrization out;
        export_parametrization(original, mesh, embedding, sign, pool, out);
        return out;
    }
    // The alive triangles, each rotated to start at its smallest corner, sorted.
    std::vector<Tri> sorted_triangles() const {
        std::vector<Tri> tris;
        for (int32_t t = 0; t < mesh.triangle_capacity(); ++t) {
            if (!mesh.alive(t)) continue;
            Tri c = mesh.triangle(t);
            std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
            tris.push_back(c);
        }
        std::sort(tris.begin(), tris.end());
        return tris;
    }
};

}  // namespace bpm::detail::test
