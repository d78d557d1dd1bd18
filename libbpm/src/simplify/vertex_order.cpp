#include "simplify/vertex_order.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace bpm::detail {

namespace {

constexpr int kBitsPerAxis = 21;  // 3 x 21 bits: one 63-bit key

// The bits of x spread to every third bit (bit b to bit 3b).
uint64_t spread_bits(uint64_t x) {
    x &= (uint64_t(1) << kBitsPerAxis) - 1;
    x = (x | (x << 32)) & 0x1f00000000ffffULL;
    x = (x | (x << 16)) & 0x1f0000ff0000ffULL;
    x = (x | (x << 8)) & 0x100f00f00f00f00fULL;
    x = (x | (x << 4)) & 0x10c30c30c30c30c3ULL;
    x = (x | (x << 2)) & 0x1249249249249249ULL;
    return x;
}

// In place, by following the permutation's cycles, without a second array: a large
// array allocated and freed here (the input's size) raised glibc's mmap threshold, and
// the simplifier's later arrays then came from the heap and stayed resident (peak RSS
// 2 MB higher on armadillo, measured).
// gather: values[i] = old values[from[i]] (the elements in the new order), in rows of `stride`.
template <class T>
void gather(std::vector<T>& values, const std::vector<int32_t>& from, size_t stride = 1) {
    std::vector<bool> done(from.size(), false);
    std::vector<T> row(stride);
    for (size_t start = 0; start < from.size(); ++start) {
        if (done[start]) continue;
        std::copy_n(values.begin() + std::ptrdiff_t(start * stride), stride, row.begin());
        size_t i = start;
        for (;;) {
            done[i] = true;
            const size_t j = size_t(from[i]);
            if (j == start) break;
            std::copy_n(values.begin() + std::ptrdiff_t(j * stride), stride, values.begin() + std::ptrdiff_t(i * stride));
            i = j;
        }
        std::copy_n(row.begin(), stride, values.begin() + std::ptrdiff_t(i * stride));
    }
}

// scatter: values[to[i]] = old values[i], the inverse of gather(values, to).
template <class T>
void scatter(std::vector<T>& values, const std::vector<int32_t>& to, size_t stride = 1) {
    std::vector<bool> done(to.size(), false);
    std::vector<T> row(stride), next(stride);
    for (size_t start = 0; start < to.size(); ++start) {
        if (done[start]) continue;
        // Carry the row that belongs at to[i] along the cycle.
        std::copy_n(values.begin() + std::ptrdiff_t(start * stride), stride, row.begin());
        size_t i = start;
        while (!done[i]) {
            done[i] = true;
            const size_t j = size_t(to[i]);
            std::copy_n(values.begin() + std::ptrdiff_t(j * stride), stride, next.begin());
            std::copy_n(row.begin(), stride, values.begin() + std::ptrdiff_t(j * stride));
            row.swap(next);
            i = j;
        }
    }
}

std::vector<int32_t> inverse(const std::vector<int32_t>& permutation) {
    std::vector<int32_t> inv(permutation.size());
    for (size_t i = 0; i < permutation.size(); ++i) inv[size_t(permutation[i])] = int32_t(i);
    return inv;
}

void rename_corners(std::vector<Tri>& triangles, const std::vector<int32_t>& id) {
    for (Tri& t : triangles)
        for (int32_t& v : t) v = id[size_t(v)];
}

}  // namespace

InputOrder morton_order(const Surface& surface) {
    const size_t nv = surface.vertices.size(), nt = surface.triangles.size();
    Vec3 lo{}, hi{};
    bool any = false;
    for (const Vec3& x : surface.vertices) {
        if (!(std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]))) continue;
        for (int k = 0; k < 3; ++k) {
            lo[k] = any ? std::min(lo[k], x[k]) : x[k];
            hi[k] = any ? std::max(hi[k], x[k]) : x[k];
        }
        any = true;
    }
    const double size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    const double scale = size > 0 ? double((uint64_t(1) << kBitsPerAxis) - 1) / size : 0.0;
    std::vector<std::pair<uint64_t, int32_t>> keyed(nv);
    for (size_t v = 0; v < nv; ++v) {
        const Vec3& x = surface.vertices[v];
        uint64_t key = 0;
        for (int k = 0; k < 3; ++k) {
            const double q = (x[k] - lo[k]) * scale;  // NaN for a non-finite coordinate: key part 0
            const uint64_t cell = q >= 1 ? uint64_t(std::min(q, double((uint64_t(1) << kBitsPerAxis) - 1))) : 0;
            key |= spread_bits(cell) << k;
        }
        keyed[v] = {key, int32_t(v)};
    }
    std::sort(keyed.begin(), keyed.end());
    InputOrder order;
    order.user_vertex.resize(nv);
    for (size_t i = 0; i < nv; ++i) order.user_vertex[i] = keyed[i].second;
    const std::vector<int32_t> internal_vertex = inverse(order.user_vertex);
    std::vector<std::pair<int32_t, int32_t>> by_corner(nt);
    for (size_t t = 0; t < nt; ++t) {
        int32_t first = std::numeric_limits<int32_t>::max();
        for (int32_t v : surface.triangles[t])
            if (v >= 0 && size_t(v) < nv) first = std::min(first, internal_vertex[size_t(v)]);
        by_corner[t] = {first, int32_t(t)};
    }
    std::sort(by_corner.begin(), by_corner.end());
    order.user_triangle.resize(nt);
    for (size_t i = 0; i < nt; ++i) order.user_triangle[i] = by_corner[i].second;
    return order;
}

void to_internal_order(Surface& surface, const InputOrder& order) {
    gather(surface.vertices, order.user_vertex);
    for (VertexArray& a : surface.vertex_data) gather(a.values, order.user_vertex, size_t(a.components));
    gather(surface.triangles, order.user_triangle);
    if (surface.patches.size() == surface.triangles.size()) gather(surface.patches, order.user_triangle);
    rename_corners(surface.triangles, inverse(order.user_vertex));
}

void to_user_order(Surface& surface, const InputOrder& order) {
    scatter(surface.vertices, order.user_vertex);
    for (VertexArray& a : surface.vertex_data) scatter(a.values, order.user_vertex, size_t(a.components));
    rename_corners(surface.triangles, order.user_vertex);
    scatter(surface.triangles, order.user_triangle);
    if (surface.patches.size() == surface.triangles.size()) scatter(surface.patches, order.user_triangle);
}

void phi_to_user_order(Parametrization& p, const InputOrder& order) {
    // p.original is already in the caller's order (the edge crossings' images below).
    // The coarse vertices sorted by the caller's id, as the coarse mesh sorts them by id.
    const size_t nc = p.coarse_vertex_origin.size();
    std::vector<int32_t> sorted(nc);  // new coarse vertex -> old
    for (size_t i = 0; i < nc; ++i) sorted[i] = int32_t(i);
    for (int32_t& v : p.coarse_vertex_origin) v = order.user_vertex[size_t(v)];
    std::sort(sorted.begin(), sorted.end(),
              [&](int32_t a, int32_t b) { return p.coarse_vertex_origin[size_t(a)] < p.coarse_vertex_origin[size_t(b)]; });
    std::vector<int32_t> coarse_id(nc);  // old coarse vertex -> new
    for (size_t i = 0; i < nc; ++i) coarse_id[size_t(sorted[i])] = int32_t(i);
    gather(p.coarse_vertex_origin, sorted);
    gather(p.coarse.vertices, sorted);
    for (VertexArray& a : p.coarse.vertex_data) gather(a.values, sorted, size_t(a.components));
    rename_corners(p.coarse.triangles, coarse_id);

    for (int32_t& v : p.node_original_vertex)
        if (v >= 0) v = order.user_vertex[size_t(v)];
    for (size_t n = 0; n < p.node_original_edge.size(); ++n) {
        auto& e = p.node_original_edge[n];
        if (e[0] < 0) continue;
        e = {order.user_vertex[size_t(e[0])], order.user_vertex[size_t(e[1])]};
        if (e[0] > e[1]) {
            std::swap(e[0], e[1]);
            p.node_edge_parameter[n] = 1.0 - p.node_edge_parameter[n];
            // 1 - s may round: the image again from the parameter, so that it is what
            // node_image_from_kind gives to the bit (as the export writes it), moved by
            // at most a rounding of the coordinates.
            const Vec3& a = p.original.vertices[size_t(e[0])];
            const Vec3& b = p.original.vertices[size_t(e[1])];
            const double s = p.node_edge_parameter[n];
            p.node_image[n] = (1 - s) * a + s * b;
        }
    }
    for (int32_t& t : p.piece_original_triangle) t = order.user_triangle[size_t(t)];
}

void steps_to_user_order(SimplificationSteps& steps, const InputOrder& order) {
    for (int32_t& v : steps.vertex) v = order.user_vertex[size_t(v)];
    rename_corners(steps.triangles, order.user_vertex);
}

}  // namespace bpm::detail
