#pragma once
// Helpers shared by tetmesh*.cpp and tet_refine.cpp (not public API).

#include <array>
#include <cstdint>
#include <vector>

#include "bpm/tetmesh.h"

namespace bpm::detail {

using FaceKey = std::array<int32_t, 3>;  // sorted vertex triple

// kTetFaces[k]: the face opposite vertex k, oriented outward for a positive tetrahedron.
extern const int kTetFaces[4][3];

FaceKey face_key(int32_t a, int32_t b, int32_t c);
// Is g a cyclic rotation of f (same vertices, same orientation)?
bool same_cyclic_orientation(const Tri& f, const std::array<int32_t, 3>& g);

struct TetFace {
    FaceKey key;
    int32_t tet;
    int local;  // 0..3, the face opposite this vertex
};
// All 4 faces of every tet, sorted by key (then tet): equal keys are adjacent.
std::vector<TetFace> enumerate_faces(const std::vector<Tet>& tets);
// Face k of tet t, oriented out of the tet (t positively oriented).
std::array<int32_t, 3> outward_face(const Tet& t, int k);

double signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace bpm::detail
