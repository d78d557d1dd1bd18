// Exact coordinates of piece corners in their original triangle; see phi_corner_code.h.

#include "phi/phi_corner_code.h"

namespace bpm::detail {

namespace {

int nearest_corner(const Parametrization& p, const Vec3& y, const Tri& tri) {
    int best = 0;
    for (int c = 1; c < 3; ++c)
        if (distance(y, p.original.vertices[static_cast<size_t>(tri[c])]) <
            distance(y, p.original.vertices[static_cast<size_t>(tri[best])]))
            best = c;
    return best;
}

}  // namespace

CornerCode corner_code(const Parametrization& p, int64_t nb, const Tri& piece, int64_t q) {
    CornerCode code{};
    const Tri& tri = p.original.triangles[static_cast<size_t>(p.piece_original_triangle[static_cast<size_t>(q)])];
    const auto corner_of = [&](int32_t v) -> int {
        for (int c = 0; c < 3; ++c)
            if (tri[c] == v) return c;
        return -1;
    };
    for (int k = 0; k < 3; ++k) {
        const size_t n = static_cast<size_t>(nb + piece[k]);
        int a = -1, b = -1;
        double s = 0;
        if (p.node_kind[n] == NodeKind::EdgeCrossing) {
            a = corner_of(p.node_original_edge[n][0]);
            b = corner_of(p.node_original_edge[n][1]);
            s = p.node_edge_parameter[n];
        } else {
            a = b = corner_of(p.node_original_vertex[n]);
        }
        if (a < 0 || b < 0) {
            a = b = nearest_corner(p, p.node_image[n], tri);
            s = 0;
        }
        code.a[k] = static_cast<uint8_t>(a);
        code.b[k] = static_cast<uint8_t>(b);
        code.s[k] = s;
    }
    return code;
}

Mat3 to_original_matrix(const CornerCode& code) {
    Mat3 m;
    m.fill(0.0);
    for (int k = 0; k < 3; ++k) {
        m[static_cast<size_t>(3 * code.a[k] + k)] += 1 - code.s[k];
        m[static_cast<size_t>(3 * code.b[k] + k)] += code.s[k];
    }
    return m;
}

}  // namespace bpm::detail
