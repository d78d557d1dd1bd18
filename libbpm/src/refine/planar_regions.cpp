#include "refine/planar_regions.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "bpm/predicates.h"
#include "core/barycentric_orientation.h"
#include "core/edge_key.h"

namespace bpm::detail {

void LineDeviation::add(const Vec3& a, const Vec3& b, const Vec3& x) {
    const Vec3 d = b - a;
    const double length2 = dot(d, d);
    if (!(length2 > 0)) {
        off = std::max(off, distance(x, a));
        return;
    }
    const double s = dot(x - a, d) / length2;
    off = std::max(off, distance(x, a + s * d));
    overshoot = std::max(overshoot, std::max({0.0, -s, s - 1.0}) * std::sqrt(length2));
}

Vec2 PlanarRegions::project(const PlanarRegion& region, const Vec3& x) {
    return {x[size_t((region.axis + 1) % 3)], x[size_t((region.axis + 2) % 3)]};
}

double PlanarRegions::vertical_offset(const PlanarRegion& region, const Vec3& x) {
    return dot(x - region.origin, region.normal) / region.normal[size_t(region.axis)];
}

namespace {

// Only decides which triangles are grouped: the offsets that enter the bound are
// measured (PlanarRegion::phi_offset, and the refined vertices' in refine.cpp), so a
// looser or tighter value changes how much the bound gains, never whether it holds.
// 1e-6 of the diagonal admits planar faces of float32 inputs (coordinates rounded to
// ~1e-7 of their size).
constexpr double kFlat = 1e-6;

}  // namespace

PlanarRegions planar_regions(const Parametrization& p, double diagonal) {
    const Surface& c = p.coarse;
    const int32_t nt = c.num_triangles();
    PlanarRegions out;
    out.region.assign(size_t(nt), -1);
    out.boundary.assign(size_t(nt), {0, 0, 0});
    out.phi_line.assign(size_t(nt), {});
    const double limit = kFlat * diagonal;

    // Directed coarse edges by undirected key: (triangle, local edge).
    std::unordered_map<uint64_t, std::vector<std::pair<int32_t, int>>> edges;
    for (int32_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k)
            edges[edge_key(c.triangles[size_t(t)][size_t(k)], c.triangles[size_t(t)][size_t((k + 1) % 3)])]
                .push_back({t, k});
    auto from = [&](int32_t t, int k) { return c.triangles[size_t(t)][size_t(k)]; };
    auto to = [&](int32_t t, int k) { return c.triangles[size_t(t)][size_t((k + 1) % 3)]; };

    // Whether triangle t fits region r: corners and node images within `limit` of the
    // plane, and every piece projecting with sign r.piece_sign (set from t if 0).
    auto fits = [&](int32_t t, PlanarRegion& r) {
        const size_t ts = size_t(t);
        for (int k = 0; k < 3; ++k)
            if (!(std::abs(dot(c.vertices[size_t(from(t, k))] - r.origin, r.normal)) <= limit)) return false;
        double offset = r.phi_offset;
        for (int64_t n = p.node_offsets[ts]; n < p.node_offsets[ts + 1]; ++n) {
            const Vec3& x = p.node_image[size_t(n)];
            if (!(std::abs(dot(x - r.origin, r.normal)) <= limit)) return false;
            offset = std::max(offset, std::abs(PlanarRegions::vertical_offset(r, x)));
        }
        int sign = r.piece_sign;
        const int64_t n0 = p.node_offsets[ts];
        for (int64_t q = p.piece_offsets[ts]; q < p.piece_offsets[ts + 1]; ++q) {
            const Tri& pc = p.pieces[size_t(q)];
            const size_t a = size_t(n0 + pc[0]), b = size_t(n0 + pc[1]), d = size_t(n0 + pc[2]);
            const int s = orient2d(PlanarRegions::project(r, p.node_image[a]),
                                   PlanarRegions::project(r, p.node_image[b]),
                                   PlanarRegions::project(r, p.node_image[d])) *
                          orient_barycentric(p.node_barycentric[a], p.node_barycentric[b], p.node_barycentric[d]);
            if (s == 0 || (sign != 0 && s != sign)) return false;
            sign = s;
        }
        r.phi_offset = offset;
        r.piece_sign = sign;
        return true;
    };

    for (int32_t seed = 0; seed < nt; ++seed) {
        if (out.region[size_t(seed)] >= 0) continue;
        const Vec3& a = c.vertices[size_t(from(seed, 0))];
        const Vec3 n = cross(c.vertices[size_t(from(seed, 1))] - a, c.vertices[size_t(from(seed, 2))] - a);
        const double length = norm(n);
        if (!(length > 0)) continue;
        PlanarRegion r;
        r.origin = a;
        r.normal = (1.0 / length) * n;
        r.axis = 0;
        for (int k = 1; k < 3; ++k)
            if (std::abs(r.normal[size_t(k)]) > std::abs(r.normal[size_t(r.axis)])) r.axis = k;
        if (!fits(seed, r)) continue;
        const int32_t id = int32_t(out.regions.size());
        out.region[size_t(seed)] = id;
        std::vector<int32_t> stack{seed};
        while (!stack.empty()) {
            const int32_t t = stack.back();
            stack.pop_back();
            for (int k = 0; k < 3; ++k)
                for (const auto& [u, j] : edges[edge_key(from(t, k), to(t, k))]) {
                    // Consistently oriented: the neighbour runs the edge the other way.
                    if (out.region[size_t(u)] >= 0 || from(u, j) != to(t, k) || to(u, j) != from(t, k)) continue;
                    PlanarRegion trial = r;
                    if (!fits(u, trial)) continue;
                    r = trial;
                    out.region[size_t(u)] = id;
                    stack.push_back(u);
                }
        }
        out.regions.push_back(r);
    }

    // Boundary edges: an edge is inside its region only if exactly one other triangle of
    // the region has it, run the other way (then the two cancel in the boundary chain).
    for (int32_t t = 0; t < nt; ++t) {
        const int32_t g = out.region[size_t(t)];
        if (g < 0) continue;
        const int64_t n0 = p.node_offsets[size_t(t)], n1 = p.node_offsets[size_t(t) + 1];
        for (int k = 0; k < 3; ++k) {
            int opposite = 0, same = 0;
            for (const auto& [u, j] : edges[edge_key(from(t, k), to(t, k))]) {
                if ((u == t && j == k) || out.region[size_t(u)] != g) continue;
                (from(u, j) == to(t, k) ? opposite : same) += 1;
            }
            if (opposite == 1 && same == 0) continue;
            out.boundary[size_t(t)][size_t(k)] = 1;
            // phi's path along the edge: the nodes with a zero coordinate at the opposite
            // corner (exactly 0 on a coarse edge).
            const size_t z = size_t((k + 2) % 3);
            const Vec3& ea = c.vertices[size_t(from(t, k))];
            const Vec3& eb = c.vertices[size_t(to(t, k))];
            for (int64_t m = n0; m < n1; ++m)
                if (p.node_barycentric[size_t(m)][z] == 0)
                    out.phi_line[size_t(t)][size_t(k)].add(ea, eb, p.node_image[size_t(m)]);
        }
    }
    return out;
}

}  // namespace bpm::detail
