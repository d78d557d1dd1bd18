// check_topology: the coarse surface has the topological type of the original one
// (§2.3) and the same non-manifold structure (§2.4). Components are matched through
// phi (the original triangles the pieces of a coarse triangle map into), vertices
// through coarse_vertex_origin; invariants are compared by compare_topology.
#include <algorithm>

#include "bpm/check.h"
#include "bpm/surface_topology.h"
#include "check/check_internal.h"

namespace bpm {

namespace {
void add_topology_counts(CheckResult& r, const std::string& prefix, const SurfaceTopology& t) {
    r.add_count(prefix + "components", static_cast<int64_t>(t.components.size()));
    r.add_count(prefix + "euler_characteristic", t.euler_characteristic);
    r.add_count(prefix + "betti0", t.betti0);
    r.add_count(prefix + "betti1", t.betti1);
    r.add_count(prefix + "betti2", t.betti2);
    r.add_count(prefix + "boundary_loops", t.boundary_loops);
    r.add_count(prefix + "orientable", t.orientable ? 1 : 0);
    r.add_count(prefix + "manifold", t.manifold ? 1 : 0);
    // Topological feature vertices and lines: of boundary, non-manifold and patch-border
    // edges, no creases (spec/check-report.md, "topology"). The 0.1 names feature_vertices
    // and feature_lines, which bpm-info uses for all feature lines, creases included, stay
    // until 0.2 with the same values.
    r.add_count(prefix + "topological_feature_vertices", static_cast<int64_t>(t.feature_vertices.size()));
    r.add_count(prefix + "topological_feature_lines", static_cast<int64_t>(t.feature_lines.size()));
    r.add_count(prefix + "feature_vertices", static_cast<int64_t>(t.feature_vertices.size()));
    r.add_count(prefix + "feature_lines", static_cast<int64_t>(t.feature_lines.size()));
    r.add_count(prefix + "contact_vertices", static_cast<int64_t>(t.contact_vertices.size()));
}
}  // namespace

CheckResult check_topology(const Parametrization& p, const CheckOptions& options, const Context& context) {
    CheckResult r;
    r.name = "topology";
    if (auto why = detail::parametrization_unsafe(p)) {
        detail::refuse(r, *why);
        return r;
    }
    context.report(0.0, "computing topology of the original surface");
    const SurfaceTopology original = compute_topology(p.original);
    context.report(0.5, "computing topology of the coarse surface");
    const SurfaceTopology coarse = compute_topology(p.coarse);
    add_topology_counts(r, "", original);

    // Component correspondence through phi, and patch agreement.
    TopologyCorrespondence corr;
    corr.vertex_map = p.coarse_vertex_origin;
    corr.component_map.assign(coarse.components.size(), -1);
    bool component_map_ok = true;
    for (int32_t t = 0; t < p.coarse.num_triangles(); ++t) {
        const int32_t c = coarse.triangle_component[t];
        for (int64_t q = p.piece_offsets[t]; q < p.piece_offsets[t + 1]; ++q) {
            const int32_t o = p.piece_original_triangle[q];
            const int32_t oc = original.triangle_component[o];
            if (corr.component_map[c] < 0) {
                corr.component_map[c] = oc;
            } else if (corr.component_map[c] != oc) {
                component_map_ok = false;
                r.add_problem({{{"coarse_triangle", t}, {"piece", q}},
                               "maps into original component " + std::to_string(oc) + ", but coarse component " +
                                   std::to_string(c) + " also maps into original component " +
                                   std::to_string(corr.component_map[c])},
                              options.max_problems);
            }
            if (p.original.patches[o] != p.coarse.patches[t])
                r.add_problem({{{"coarse_triangle", t}, {"piece", q}},
                               "coarse patch " + std::to_string(p.coarse.patches[t]) + " but original triangle " +
                                   std::to_string(o) + " has patch " + std::to_string(p.original.patches[o])},
                              options.max_problems);
        }
    }
    if (!component_map_ok) corr.component_map.clear();
    for (int32_t c : corr.component_map)
        if (c < 0) {  // a component without pieces: compare by invariants only
            corr.component_map.clear();
            break;
        }
    for (const std::string& d : compare_topology(original, coarse, corr, options.max_problems))
        r.add_problem({{}, d}, options.max_problems);
    r.summary = describe_topology(original);
    if (r.passed) r.summary += "; coarse surface agrees";
    context.report(1.0, "topology");
    return r;
}

CheckResult check_topology(const Surface& surface, const CheckOptions& options, const Context& context) {
    (void)options;
    CheckResult r;
    r.name = "topology";
    if (auto why = detail::surface_unsafe(surface)) {
        detail::refuse(r, *why);
        return r;
    }
    context.report(0.0, "computing topology");
    const SurfaceTopology t = compute_topology(surface);
    add_topology_counts(r, "", t);
    r.summary = describe_topology(t);
    context.report(1.0, "computing topology");
    return r;
}

}  // namespace bpm
