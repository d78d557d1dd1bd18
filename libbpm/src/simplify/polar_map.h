#pragma once
// The polar map of a fan (Krause & Sander §2.2.4, after Eck et al.): the fan's polygon
// laid out in the plane around v at the origin, where it is retriangulated and the
// original surface on it re-cut. A closed fan (a disk) goes through z -> z^alpha of
// its geodesic polar coordinates, alpha = 2 pi / (sum of the angles at v); an open fan
// (a half-disk between two feature edges) has its angles scaled to pi and its radii
// kept, with the two feature neighbours on the x axis, so that v lands at the same
// place of the new feature edge in every half-disk.

#include <cstdint>
#include <string>
#include <vector>

#include "bpm/geometry.h"
#include "simplify/star_fans.h"

namespace bpm::detail {

// Angle between two vectors, in [0, pi] (atan2: accurate for small and large angles).
inline double angle_between(const Vec3& a, const Vec3& b) {
    const double c = dot(a, b), s = norm(cross(a, b));
    return std::atan2(s, c);
}

struct PolarMap {
    std::vector<Vec2> q;  // polygon corner i (fan.link[i]) in the plane: a strictly convex polygon, counter-clockwise
    // The polar map's polygon was not convex (a star-shaped, non-convex link), so the
    // corners were moved outwards onto a circle (closed) or a half-circle through the
    // fixed ends (open); every ear of a polygon on a circle is Delaunay-admissible.
    bool cocircular = false;
    std::vector<Vec2> q_polar;  // with `cocircular`: the corners where the polar map put them
    // Intermediate values, kept for their buffers: the angle at v of fan triangle i,
    // the polar angle and the radius (over radius_scale) of corner i.
    std::vector<double> theta, phi, radius;
};

// Lays out the polygon of `fan` around v. `radius_scale` divides the 3D distances (the
// mean link edge length, so that the layout does not depend on the model's units).
// Fails with `why` on a degenerate fan triangle, a scaled angle of pi or more, or when
// not even the circle makes the polygon convex; `map` is then unspecified.
bool polar_map(const std::vector<Vec3>& x, int32_t v, const Fan& fan, double radius_scale, PolarMap& map,
               std::string& why);

}  // namespace bpm::detail
