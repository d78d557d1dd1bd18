#include "bpm/parametrization.h"

#include <limits>
#include <stdexcept>

namespace bpm {

Parametrization make_identity_parametrization(const Surface& original) {
    Parametrization p;
    p.original = original;
    p.coarse = original;
    const int32_t nv = original.num_vertices();
    const int32_t nt = original.num_triangles();
    p.coarse_vertex_origin.resize(static_cast<size_t>(nv));
    for (int32_t v = 0; v < nv; ++v) p.coarse_vertex_origin[static_cast<size_t>(v)] = v;

    // One piece per coarse triangle whose nodes are the three corners, in corner
    // order, so that node barycentrics are exact unit vectors and phi(b) evaluates to
    // exactly barycentric_point(x0, x1, x2, b).
    const size_t n = 3 * static_cast<size_t>(nt);
    p.node_offsets.resize(static_cast<size_t>(nt) + 1);
    p.piece_offsets.resize(static_cast<size_t>(nt) + 1);
    p.node_barycentric.reserve(n);
    p.node_image.reserve(n);
    p.node_kind.assign(n, NodeKind::CoarseCorner);
    p.node_original_vertex.reserve(n);
    p.node_original_edge.assign(n, {-1, -1});
    p.node_edge_parameter.assign(n, std::numeric_limits<double>::quiet_NaN());
    p.pieces.assign(static_cast<size_t>(nt), Tri{0, 1, 2});
    p.piece_original_triangle.resize(static_cast<size_t>(nt));
    for (int32_t t = 0; t < nt; ++t) {
        p.node_offsets[static_cast<size_t>(t)] = 3 * int64_t(t);
        p.piece_offsets[static_cast<size_t>(t)] = t;
        const Tri& tri = original.triangles[static_cast<size_t>(t)];
        for (int k = 0; k < 3; ++k) {
            Vec3 b{0, 0, 0};
            b[static_cast<size_t>(k)] = 1;
            p.node_barycentric.push_back(b);
            p.node_image.push_back(original.vertices[static_cast<size_t>(tri[static_cast<size_t>(k)])]);
            p.node_original_vertex.push_back(tri[static_cast<size_t>(k)]);
        }
        p.piece_original_triangle[static_cast<size_t>(t)] = t;
    }
    p.node_offsets[static_cast<size_t>(nt)] = 3 * int64_t(nt);
    p.piece_offsets[static_cast<size_t>(nt)] = nt;
    return p;
}

Vec3 node_image_from_kind(const Parametrization& p, int64_t node) {
    if (node < 0 || node >= p.num_nodes()) throw std::out_of_range("node_image_from_kind: node index out of range");
    const size_t i = static_cast<size_t>(node);
    const auto& x = p.original.vertices;
    switch (p.node_kind[i]) {
        case NodeKind::OriginalVertex:
        case NodeKind::CoarseCorner:
            return x.at(static_cast<size_t>(p.node_original_vertex[i]));
        case NodeKind::EdgeCrossing: {
            const auto& e = p.node_original_edge[i];
            const double s = p.node_edge_parameter[i];
            // Same expression as the spec, so writers and readers agree to the bit.
            return (1 - s) * x.at(static_cast<size_t>(e[0])) + s * x.at(static_cast<size_t>(e[1]));
        }
    }
    throw std::invalid_argument("node_image_from_kind: invalid node kind");
}

std::vector<Vec3> node_images_from_kinds(const Parametrization& p) {
    std::vector<Vec3> images(static_cast<size_t>(p.num_nodes()));
    for (int64_t n = 0; n < p.num_nodes(); ++n) images[static_cast<size_t>(n)] = node_image_from_kind(p, n);
    return images;
}

}  // namespace bpm
