#pragma once
// Inside or outside a closed surface, decided exactly by the parity of the crossings of a
// ray (Jordan). The ray starts at p + (0, e, e^2) for an infinitesimal e > 0 and runs
// along +x: a symbolic perturbation in the manner of Edelsbrunner & Muecke's simulation
// of simplicity, so that the ray passes through no vertex and along no edge or plane of
// any triangle, and every decision is an exact orient2d / orient3d sign or a comparison of
// coordinates. Every crossing then counts once, and for a closed surface (a set of
// triangles in which every edge lies in an even number of them: a mod-2 cycle, which may
// touch or cross itself and have junction edges of four sheets) the parity of the
// crossings is 1 exactly when p lies in a region that the surface encloses an odd number of
// times. A point not on the surface lies in the same region as its perturbation.
// Triangles without area (and those seen edge-on from the ray) are never crossed: a
// generic ray misses them. Used by the simplifier's island guard and by bpm-check's
// junctions check (the material each component lies in). Internal to libbpm.

#include "bpm/geometry.h"

namespace bpm::detail {

enum class RayHit {
    Miss,     // the perturbed ray does not cross the triangle
    Cross,    // it crosses it once
    Touches,  // p itself lies on the (closed) triangle: inside/outside is not defined
};
// A point on a surface is reported as touching only by a triangle whose projection holds
// the perturbed point; elsewhere it gets the parity of its perturbation (which lies off the
// surface). Callers that must not decide for such a point test first that it is off the
// surface (the simplifier: the intersection test), or take Touches as a refusal.

// The ray from p + (0, e, e^2) along +x against triangle (a, b, c).
RayHit ray_crosses(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace bpm::detail
