#pragma once
// The crease test: is the edge that two triangles share sharp? And how sharp it is
// (ridge_angle_degrees). The one implementation
// behind every crease bpm finds: the simplifier's feature edges
// (simplify/coarse_mesh.cpp, mark_feature_edges), the smoother's feature lines
// (smooth/smooth.cpp) and bpm-info's feature summary (io/bpm_info_features.cpp).
//
// Inputs: the corner positions and the two triangles (as stored, any orientation) that
// share the edge (u, w). Each caller has these over its own mesh structure (the
// simplifier's CoarseMesh, the smoother's original surface, bpm-info's coarse Surface),
// so the test takes no mesh type.
//
// Angle: the angle between the two unit normals (triangle_normal), 0 where the triangles
// lie flat, 180 degrees where they fold onto each other; i.e. 180 degrees minus the
// interior dihedral angle. The edge is a crease where that angle is MORE than the feature
// angle, compared as cosines: dot(n0, n1) < cos(feature angle). A feature angle of 180
// degrees or more finds no crease (the guard matters: the dot product of two opposite
// unit normals may round to just below -1).
//
// Orientation: the normals are compared as the triangles are oriented, the second turned
// over when the two run the edge in the same direction (a consistently oriented pair runs
// it in opposite directions). So flipping either triangle's stored orientation does not
// change the answer; on a non-orientable sheet every edge is still judged by its two
// triangles alone.
//
// Degenerate triangles: a triangle whose normal is zero (coincident or exactly collinear
// corners in floating point), or whose height is below 1e-10 of its longest edge (an
// input sliver, whose normal rounding decides), has no direction; its edges are not
// creases. (Inputs of the
// simplifier, and so the smoother's S0, pass validate_surface, which refuses zero-area
// triangles; bpm-info reads coarse surfaces as stored.)

#include <cstdint>
#include <vector>

#include "bpm/geometry.h"
#include "bpm/surface.h"

namespace bpm::detail {

class CreaseTest {
public:
    explicit CreaseTest(double feature_angle_degrees);

    // false when the feature angle is 180 degrees or more: then no edge is a crease.
    bool finds_creases() const { return finds_creases_; }

    // Is the edge (u, w) that t0 and t1 share a crease? Corners index `positions`.
    // \pre t0 and t1 both have u and w as corners.
    bool is_crease(const std::vector<Vec3>& positions, const Tri& t0, const Tri& t1, int32_t u,
                   int32_t w) const;
    // The same from the edge's oriented_normal_cosine() (which returned true), for a
    // caller that asks several tests about one edge (find_creases: the sharp test, the
    // shallow one and the angle), computing the normals once.
    bool is_crease(double cosine) const { return finds_creases_ && cosine < cos_limit_; }

private:
    double cos_limit_;
    bool finds_creases_;
};

// The ridge angle of the edge (u, w) that t0 and t1 share, in degrees: 180 minus the
// angle between their normals, the normals compared as is_crease() compares them. 180
// where the triangles lie flat, 0 where they fold onto each other: the interior dihedral
// angle of a convex edge, the exterior one of a concave edge (the angle of the thinner
// wedge the two triangles make, on whichever side it lies). Needs no consistent
// orientation of the whole surface. 180 when either triangle is degenerate or has no
// direction (see above).
// The simplifier's ridge guard (SimplifyOptions::min_ridge_angle_degrees) compares it.
// \pre t0 and t1 both have u and w as corners.
double ridge_angle_degrees(const std::vector<Vec3>& positions, const Tri& t0, const Tri& t1, int32_t u, int32_t w);
// The same from the edge's oriented_normal_cosine() (which returned true).
double ridge_angle_degrees(double cosine);

// The cosine of the angle between the normals of t0 and t1 (triangle_normal, corners in
// stored order), the second turned over when the two run the edge (u, w) in the same
// direction: what is_crease() and ridge_angle_degrees() compare. False for a degenerate
// triangle or one without a direction (see above): then the edge is no crease and its
// ridge angle 180.
bool oriented_normal_cosine(const std::vector<Vec3>& positions, const Tri& t0, const Tri& t1, int32_t u, int32_t w,
                            double& cosine);

}  // namespace bpm::detail
