// Dihedral angles of a tetrahedron (core/tetrahedron_quality.h).
//
// The angle at edge e between faces k and l (the faces opposite the two corners not on e)
// from their outward normals n_k, n_l (|n| = 2 area): cos = -n_k.n_l / (|n_k| |n_l|) and
// sin = 6 volume |e| / (|n_k| |n_l|) (from V = 2 A_k A_l sin / (3 |e|)). The
// common factor cancels in atan2, so no division, accurate for slivers (unlike acos of a
// normalised dot product near 1), and signed by the volume.

#include "core/tetrahedron_quality.h"

#include <algorithm>
#include <cmath>

namespace bpm::detail {

namespace {

constexpr double kPi = 3.14159265358979323846;
// Faces opposite each corner, outward for a positive tetrahedron (as kTetFaces in
// tetmesh/tetmesh_internal.h).
constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
// Edge (i, j) and the corners k, l opposite the two faces that share it.
constexpr int kEdge[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2}, {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};

// The sine and cosine of every angle, both times |n_k| |n_l|.
void scaled_sines_and_cosines(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double sine[6],
                              double cosine[6]) {
    const Vec3* p[4] = {&a, &b, &c, &d};
    Vec3 n[4];  // outward face normals, |n_k| = 2 area_k
    for (int k = 0; k < 4; ++k)
        n[k] = cross(*p[kFace[k][1]] - *p[kFace[k][0]], *p[kFace[k][2]] - *p[kFace[k][0]]);
    const double det = dot(b - a, cross(c - a, d - a)) + 0.0;  // 6 volume, signed (+ 0.0: never -0)
    for (int e = 0; e < 6; ++e) {
        sine[e] = det * distance(*p[kEdge[e][0]], *p[kEdge[e][1]]);
        cosine[e] = -dot(n[kEdge[e][2]], n[kEdge[e][3]]);
    }
}

}  // namespace

void dihedral_angles(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double out[6]) {
    double sine[6], cosine[6];
    scaled_sines_and_cosines(a, b, c, d, sine, cosine);
    // + 0.0 on the cosine: a face of zero area gives -0, and atan2(0, -0) would be pi.
    for (int e = 0; e < 6; ++e) out[e] = std::atan2(sine[e], cosine[e] + 0.0);
}

double min_dihedral(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    double angles[6];
    dihedral_angles(a, b, c, d, angles);
    return *std::min_element(angles, angles + 6);
}

double min_dihedral_degrees(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return min_dihedral(a, b, c, d) * 180 / kPi;
}

void dihedral_pseudo_angles(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double out[6]) {
    double sine[6], cosine[6];
    scaled_sines_and_cosines(a, b, c, d, sine, cosine);
    for (int e = 0; e < 6; ++e) {
        const double r = std::sqrt(sine[e] * sine[e] + cosine[e] * cosine[e]);
        if (!(r > 0)) {
            out[e] = 0;
            continue;
        }
        const double s = sine[e] / r;
        out[e] = cosine[e] >= 0 ? s : (s >= 0 ? 2 - s : -2 - s);
    }
}

double min_dihedral_pseudo(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    double angles[6];
    dihedral_pseudo_angles(a, b, c, d, angles);
    return *std::min_element(angles, angles + 6);
}

double pseudo_from_radians(double angle) {
    if (angle >= kPi / 2) return 2 - std::sin(angle);
    if (angle <= -kPi / 2) return -2 - std::sin(angle);
    return std::sin(angle);
}

double radians_from_pseudo(double q) {
    if (q > 1) return kPi - std::asin(std::min(1.0, 2 - q));
    if (q < -1) return -kPi - std::asin(std::max(-1.0, -2 - q));
    return std::asin(q);
}

}  // namespace bpm::detail
