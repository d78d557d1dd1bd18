#pragma once
// Surfaces and parametrizations built in code, shared by the unit tests.
//
// Every fixture states its topology, so tests can compare computed invariants with
// known ones. Patch ids are one per material interface: for a voxel complex, a face
// between cells labelled a < b gets patch a * 100 + b (label 0 = outside).

#include <string>
#include <vector>

#include "bpm/parametrization.h"
#include "bpm/surface.h"

namespace bpm::fixtures {

// Regular tetrahedron-like, outward oriented: V 4, T 4, chi 2, b=(1,0,1).
Surface tetrahedron();

// Closed surface of the union of labelled unit voxels: every face between two cells of
// different labels (0 = empty), each split into res x res quads of two triangles
// (diagonal from the quad's first to third corner; triangles (a,b,c), (a,c,d) are
// consecutive). Normals point from the higher label to the lower one.
// `labels` is nx*ny*nz, x fastest.
Surface voxel_surface(int nx, int ny, int nz, const std::vector<int>& labels, int res = 1);

// Unit cube, 8 vertices, 12 triangles, patch 1: chi 2, b=(1,0,1).
Surface cube(int res = 1);
// Torus of revolution from an n x m grid, patch 0: chi 0, b=(1,2,1), orientable.
Surface torus(int n = 12, int m = 8);
// Genus 2: boundary of a 3x2-hole block of voxels (5 x 3 x 1 with holes at (1,1), (3,1)).
// chi -2, b=(1,4,1).
Surface double_torus(int res = 1);
// Flat square n x n grid in z = 0: chi 1, b=(1,0,0), 1 boundary loop, one closed
// feature line (the boundary, 1 sheet), no feature vertices.
Surface disk(int n = 4);
// Cubes [0,1]^3 (label 1) and [1,2]x[0,1]^2 (label 2): the shared square is an
// interior sheet; its 4 edges have 3 sheets and form one closed feature line.
// chi 3, b=(1,0,2), no feature vertices.
Surface two_cubes(int res = 1);
// Cube [0,2]^3 split into 8 labelled octants: 6 internal feature lines with 4 sheets
// meet at the centre; chi 9, b=(1,0,8), 7 feature vertices (centre, face centres).
Surface octants(int res = 1);
// A 12-sided prism split into three wedges (materials 1..3) by walls from the axis:
// 4 feature lines with 3 sheets between the two axis end points; chi 4, b=(1,0,3).
Surface cylinder_wedges(int segments = 12, int levels = 2);
// Two closed cones (patches 1 and 2) touching at their apex: 2 components, 1 contact
// vertex (a feature vertex); chi 3, b=(1,0,2); each component chi 2.
Surface hourglass(int segments = 8);
// Moebius strip of n x 2 quads: chi 0, b=(1,1,0), 1 boundary loop, non-orientable.
Surface moebius(int n = 16);

// Two spherical caps meeting along the unit circle in z = 0 at a crease: the caps' normals
// there are `crease_degrees` apart (0: the unit sphere). Latitude-longitude grid of
// `segments` around and `rings` per cap (a pole vertex on each), patch 0, outward:
// chi 2, b=(1,0,1). The facets next to the circle are a few degrees steeper than the caps'
// tangents (+ 90 / rings degrees at the crease). `noise` > 0 moves every vertex radially by
// up to that fraction of its distance from the origin (a fixed pseudo-random sequence):
// a scan-like surface whose edges kink every way.
Surface ridged_lens(int segments, int rings, double crease_degrees, double noise = 0.0);

// Each triangle split into four at its edge midpoints (midpoints appended after the
// original vertices, one per edge), patches kept.
Surface subdivide(const Surface& surface);

// --- parametrizations (built here so the tests do not depend on the writer's) ---

// phi = identity: coarse = original, one piece per triangle.
Parametrization identity_parametrization(const Surface& surface);

// Coarse = `coarse`; original = each coarse triangle split 1-to-4 at edge midpoints,
// and the middle quarter split again into three at the interior point with coarse
// barycentric coordinates (3/8, 1/4, 3/8). Per coarse triangle: nodes 0..2 are the
// corners, 3..5 the midpoints of local edges 0, 1, 2 (OriginalVertex on coarse edges),
// 6 the interior point; pieces 0..2 the corner quarters, 3..5 the split middle quarter
// ((m0,m1,p), (m1,m2,p), (m2,m0,p)), mapping to original triangles 6t .. 6t+5.
Parametrization refined_parametrization(const Surface& coarse);

// `quads` must come from voxel_surface (consecutive triangle pairs (a,b,c), (a,c,d)
// over parallelograms). Original = quads; coarse = the same quads with the other
// diagonal (a,b,d), (b,c,d). phi has one EdgeCrossing node per quad (at its centre, on
// original edge (a,c) and coarse edge (b,d)) and two pieces per coarse triangle.
Parametrization flipped_diagonal_parametrization(const Surface& quads);

// Recomputes node_image from the node identities (what a writer does).
void recompute_images(Parametrization& p);

// Reads an ASCII OFF file (triangles only), for the real meshes in BPM_MESH_DIR, so the
// tests do not depend on bpm/surface_io.h.
Surface load_off(const std::string& path);

}  // namespace bpm::fixtures
