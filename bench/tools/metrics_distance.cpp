// Sampled two-sided distances between two triangulated surfaces (bench/README.md).
// The only file of the benchmark tools that includes CGAL.
//
// Closest points come from a CGAL AABB tree over the triangles of the target surface
// (CGAL::Epick, double precision). The sample set of a surface is: all its vertices, all
// its edge midpoints, and max(min_per_triangle, round(area_samples * area / total area))
// uniformly distributed random points per triangle (Turk's square-root mapping), drawn
// from one std::mt19937_64 with a fixed seed, so runs are reproducible.

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "metrics.h"

namespace bpm::bench {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Triangle = K::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<K, TriangleIterator>;
using Traits = CGAL::AABB_traits<K, Primitive>;
using Tree = CGAL::AABB_tree<Traits>;

Point to_point(const Vec3& v) { return Point(v[0], v[1], v[2]); }

// Calls `visit(point, triangle)` for every sample of `surface` (see the file comment),
// with a triangle of `surface` that contains the point.
template <class Visit>
void for_each_sample(const Surface& surface, const SamplingOptions& options, Visit&& visit) {
    // A triangle of every used vertex (-1 = unused), reported with the sample.
    std::vector<int32_t> used(surface.vertices.size(), -1);
    for (size_t i = 0; i < surface.triangles.size(); ++i)
        for (int32_t v : surface.triangles[i]) used[static_cast<size_t>(v)] = static_cast<int32_t>(i);
    for (size_t v = 0; v < surface.vertices.size(); ++v)
        if (used[v] >= 0) visit(surface.vertices[v], used[v]);

    // Edge midpoints, each edge once.
    std::vector<std::array<int32_t, 3>> edges;  // (u, w, a triangle of the edge)
    edges.reserve(surface.triangles.size() * 3);
    for (size_t i = 0; i < surface.triangles.size(); ++i) {
        const Tri& t = surface.triangles[i];
        for (int k = 0; k < 3; ++k)
            edges.push_back({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3]), static_cast<int32_t>(i)});
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end(),
                            [](const auto& a, const auto& b) { return a[0] == b[0] && a[1] == b[1]; }),
                edges.end());
    for (const auto& e : edges) visit(0.5 * (surface.vertices[e[0]] + surface.vertices[e[1]]), e[2]);

    double total_area = 0.0;
    for (const Tri& t : surface.triangles)
        total_area += triangle_area(surface.vertices[t[0]], surface.vertices[t[1]], surface.vertices[t[2]]);
    std::mt19937_64 rng(options.seed);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (size_t ti = 0; ti < surface.triangles.size(); ++ti) {
        const Tri& t = surface.triangles[ti];
        const Vec3& a = surface.vertices[t[0]];
        const Vec3& b = surface.vertices[t[1]];
        const Vec3& c = surface.vertices[t[2]];
        const double share = total_area > 0.0 ? triangle_area(a, b, c) / total_area : 0.0;
        const int64_t count = std::max<int64_t>(options.min_per_triangle,
                                                std::llround(static_cast<double>(options.area_samples) * share));
        for (int64_t i = 0; i < count; ++i) {
            const double r1 = std::sqrt(uniform(rng));
            const double r2 = uniform(rng);
            visit(barycentric_point(a, b, c, {1.0 - r1, r1 * (1.0 - r2), r1 * r2}), static_cast<int32_t>(ti));
        }
    }
}

// The q-quantile of `values` (nearest rank; reorders them).
double percentile(std::vector<double>& values, double q) {
    const size_t rank = std::min(values.size() - 1, static_cast<size_t>(q * static_cast<double>(values.size())));
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(rank), values.end());
    return values[rank];
}

OneSidedDistance one_sided(const Surface& from, const Surface& to, const SamplingOptions& options) {
    std::vector<Triangle> triangles;
    triangles.reserve(to.triangles.size());
    for (const Tri& t : to.triangles)
        triangles.emplace_back(to_point(to.vertices[t[0]]), to_point(to.vertices[t[1]]), to_point(to.vertices[t[2]]));
    OneSidedDistance d;
    if (triangles.empty()) return d;
    Tree tree(triangles.begin(), triangles.end());
    tree.accelerate_distance_queries();

    double sum = 0.0, sum_sq = 0.0;
    std::vector<double> distances;
    for_each_sample(from, options, [&](const Vec3& p, int32_t triangle) {
        const Point q = to_point(p);
        const double dist = std::sqrt(CGAL::to_double(tree.squared_distance(q)));
        distances.push_back(dist);
        ++d.samples;
        sum += dist;
        sum_sq += dist * dist;
        if (dist > d.max) {
            d.max = dist;
            d.max_at = p;
            d.max_triangle = triangle;
        }
    });
    if (d.samples > 0) {
        d.mean = sum / static_cast<double>(d.samples);
        d.rms = std::sqrt(sum_sq / static_cast<double>(d.samples));
        d.p99 = percentile(distances, 0.99);
        d.p999 = percentile(distances, 0.999);
    }
    return d;
}

}  // namespace

DistanceReport compute_distances(const Surface& original, const Surface& coarse, const SamplingOptions& options) {
    DistanceReport r;
    r.original_to_coarse = one_sided(original, coarse, options);
    r.coarse_to_original = one_sided(coarse, original, options);
    r.hausdorff = std::max(r.original_to_coarse.max, r.coarse_to_original.max);
    return r;
}

}  // namespace bpm::bench
