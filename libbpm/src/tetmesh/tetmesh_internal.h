#pragma once
// Helpers shared by tetmesh*.cpp and tet_refine.cpp (not public API).

#include <array>
#include <cstdint>
#include <vector>

#include "bpm/context.h"
#include "bpm/tetmesh.h"
#include "bpm/tetmesh_smooth.h"

namespace bpm::detail {

using FaceKey = std::array<int32_t, 3>;  // sorted vertex triple

// kTetFaces[k]: the face opposite vertex k, oriented outward for a positive tetrahedron.
extern const int kTetFaces[4][3];

FaceKey face_key(int32_t a, int32_t b, int32_t c);
// Is g a cyclic rotation of f (same vertices, same orientation)?
bool same_cyclic_orientation(const Tri& f, const std::array<int32_t, 3>& g);

// The faces on S (boundary and interfaces) as sorted keys: the faces that flips and vertex
// insertion (tet_flips.h, tet_insert.h) must keep.
class ProtectedFaces {
public:
    explicit ProtectedFaces(const std::vector<Tri>& faces);
    bool contains(int32_t a, int32_t b, int32_t c) const;

private:
    std::vector<FaceKey> keys_;  // sorted
};

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

// \throw OptionError for options smooth_tetmesh refuses.
void check_smooth_options(const TetSmoothOptions& options);
// smooth_tetmesh with its progress in [progress_base, progress_base + progress_span] of
// the caller's (generate_tetmesh smooths as its last part), without its "smoothing done".
TetSmoothResult smooth_tetmesh_within(TetMesh& mesh, const TetSmoothOptions& options, const Context& context,
                                      double progress_base, double progress_span);
// smooth_tetmesh on raw arrays: moves the vertices v with movable[v] != 0. tets[t] is
// positively oriented, or negatively where negative[t] (negative may be empty: all
// positive). dirty (#V, or null = all): the vertices whose tetrahedra changed since they
// were last visited; only those are visited, and the call leaves it up to date, so a
// caller that moves vertices between calls marks their neighbours and passes it again.
// Progress goes to context in [progress_base, progress_base + progress_span].
TetSmoothResult smooth_interior(std::vector<Vec3>& x, const std::vector<Tet>& tets, const std::vector<bool>& negative,
                                const std::vector<char>& movable, std::vector<char>* dirty,
                                const TetSmoothOptions& options, const Context& context, double progress_base,
                                double progress_span);

}  // namespace bpm::detail
