// The feature structure bpm-info reports for the coarse surface (bpm/bpm_info.h,
// BpmFeatureSummary): bpm-check's combinatorial feature edges and vertices
// (bpm/surface_topology.h) together with the creases of the surface's geometry.
#include <algorithm>
#include <numeric>
#include <vector>

#include "bpm/bpm_info.h"
#include "bpm/geometry.h"
#include "bpm/surface_topology.h"
#include "core/crease.h"
#include "core/crease_chains.h"

namespace bpm {

namespace {

int32_t find_root(std::vector<int32_t>& parent, int32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

}  // namespace

BpmFeatureSummary summarize_features(const Surface& surface, double feature_angle_degrees,
                                     double crease_chain_angle_degrees, double crease_chain_length) {
    detail::check_crease_rule_numbers(feature_angle_degrees, crease_chain_angle_degrees, crease_chain_length);
    BpmFeatureSummary out;
    out.feature_angle_degrees = feature_angle_degrees;
    out.crease_chain_angle_degrees = crease_chain_angle_degrees;
    out.crease_chain_length = crease_chain_length;
    const SurfaceTopology topology = compute_topology(surface);
    out.topological_feature_vertices = static_cast<int64_t>(topology.feature_vertices.size());
    out.topological_feature_lines = static_cast<int64_t>(topology.feature_lines.size());
    const SurfaceConnectivity& c = topology.connectivity;
    const int32_t ne = c.num_edges();
    const detail::CreaseTest sharp_test(feature_angle_degrees);

    // The creases: core/crease_chains.h over the edges of two triangles of one patch, as
    // the simplifier decides them on the original surface.
    std::vector<char> feature(static_cast<size_t>(ne), 0), crease(static_cast<size_t>(ne), 0);
    std::vector<detail::SheetEdge> sheet;
    std::vector<int32_t> sheet_edge;  // per sheet edge: its edge id
    for (int32_t e = 0; e < ne; ++e) {
        switch (topology.edge_class[e]) {
            case EdgeClass::Boundary: ++out.boundary_edges; feature[e] = 1; continue;
            case EdgeClass::NonManifold: ++out.non_manifold_edges; feature[e] = 1; continue;
            case EdgeClass::Interface: ++out.interface_edges; feature[e] = 1; continue;
            case EdgeClass::Regular: break;
        }
        if (c.edge_degree(e) != 2) continue;
        const auto [u, w] = c.edges[e];
        sheet.push_back({u, w, surface.triangles[c.edge_triangles[c.edge_triangle_offsets[e]]],
                         surface.triangles[c.edge_triangles[c.edge_triangle_offsets[e] + 1]]});
        sheet_edge.push_back(e);
    }
    detail::CreaseRule rule;
    rule.feature_angle_degrees = feature_angle_degrees;
    rule.chain_angle_degrees = crease_chain_angle_degrees;
    rule.min_chain_length = crease_chain_length * bounding_box_diagonal(surface);
    const std::vector<uint8_t> is_crease = detail::find_creases(surface.vertices, sheet, rule);
    for (size_t i = 0; i < sheet.size(); ++i) {
        if (!is_crease[i]) continue;
        const int32_t e = sheet_edge[i];
        ++out.crease_edges;
        if (!sharp_test.is_crease(surface.vertices, sheet[i].t0, sheet[i].t1, sheet[i].u, sheet[i].w))
            ++out.chain_crease_edges;
        feature[e] = crease[e] = 1;
    }
    out.feature_edges = out.boundary_edges + out.non_manifold_edges + out.interface_edges + out.crease_edges;

    // Feature edges and creases at each vertex.
    const size_t nv = surface.vertices.size();
    std::vector<int32_t> degree(nv, 0), creases(nv, 0);
    for (int32_t e = 0; e < ne; ++e) {
        if (!feature[e]) continue;
        for (const int32_t v : c.edges[e]) {
            ++degree[size_t(v)];
            creases[size_t(v)] += crease[e];
        }
    }
    std::vector<char> corner(nv, 0);
    for (const int32_t v : topology.feature_vertices) corner[size_t(v)] = 1;
    for (size_t v = 0; v < nv; ++v)
        if (creases[v] > 0 && degree[v] != 2) corner[v] = 1;
    out.feature_vertices = std::count(corner.begin(), corner.end(), char(1));

    // Lines: feature edges joined at the vertices that are not feature vertices (those
    // have exactly two feature edges: every other count makes a feature vertex above).
    std::vector<int32_t> parent(static_cast<size_t>(ne)), first(nv, -1);
    std::iota(parent.begin(), parent.end(), 0);
    for (int32_t e = 0; e < ne; ++e) {
        if (!feature[e]) continue;
        for (const int32_t v : c.edges[e]) {
            if (corner[size_t(v)]) continue;
            if (first[size_t(v)] < 0) first[size_t(v)] = e;
            else parent[size_t(find_root(parent, e))] = find_root(parent, first[size_t(v)]);
        }
    }
    std::vector<char> open(static_cast<size_t>(ne), 0);
    for (int32_t e = 0; e < ne; ++e)
        if (feature[e] && (corner[size_t(c.edges[e][0])] || corner[size_t(c.edges[e][1])]))
            open[size_t(find_root(parent, e))] = 1;
    for (int32_t e = 0; e < ne; ++e) {
        if (!feature[e] || find_root(parent, e) != e) continue;
        ++out.feature_lines;
        out.feature_loops += open[size_t(e)] ? 0 : 1;
    }
    return out;
}

}  // namespace bpm
