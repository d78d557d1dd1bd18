#pragma once
// Checks the tests of the tetrahedral mesh improvements share (tet_flips_test.cpp,
// tet_insert_test.cpp): a flip or an insertion must leave a conforming, positively oriented
// mesh with the same boundary and every face on S still a face.
#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <vector>

#include <catch2/catch.hpp>

#include "bpm/predicates.h"
#include "bpm/tetmesh.h"
#include "core/tetrahedron_quality.h"
#include "tetmesh/tetmesh_internal.h"

namespace bpm::test {

using detail::face_key;  // a face's vertices, sorted
using detail::FaceKey;

inline double min_angle(const std::vector<Vec3>& x, const std::vector<Tet>& tets) {
    double m = 180;
    for (const Tet& t : tets) m = std::min(m, detail::min_dihedral_degrees(x[t[0]], x[t[1]], x[t[2]], x[t[3]]));
    return m;
}

// How many tetrahedra have each face.
inline std::map<FaceKey, int> face_counts(const std::vector<Tet>& tets) {
    std::map<FaceKey, int> count;
    for (const Tet& t : tets)
        for (const auto& g : detail::kTetFaces) ++count[face_key(t[g[0]], t[g[1]], t[g[2]])];
    return count;
}

// The faces in exactly one tetrahedron: the mesh's boundary.
inline std::set<FaceKey> hull_of(const std::vector<Tet>& tets) {
    std::set<FaceKey> hull;
    for (const auto& [k, n] : face_counts(tets))
        if (n == 1) hull.insert(k);
    return hull;
}

// The hull's faces as triangles (what a boundary S around the tetrahedra would be).
inline std::vector<Tri> outer_faces(const std::vector<Tet>& tets) {
    std::vector<Tri> out;
    for (const FaceKey& k : hull_of(tets)) out.push_back({k[0], k[1], k[2]});
    return out;
}

// Conforming: every tetrahedron positive (exact), none twice, every face in one or two
// tetrahedra, the faces in one exactly `hull`, every protected face still a face, every
// vertex in some tetrahedron.
inline void check_valid(const std::vector<Vec3>& x, const std::vector<Tet>& tets, const std::set<FaceKey>& hull,
                        const std::vector<Tri>& protected_faces) {
    std::set<std::array<int32_t, 4>> seen;
    std::vector<char> used(x.size(), 0);
    for (const Tet& t : tets) {
        CHECK(orient3d(x[t[0]], x[t[1]], x[t[2]], x[t[3]]) == 1);
        std::array<int32_t, 4> s = t;
        std::sort(s.begin(), s.end());
        CHECK(seen.insert(s).second);
        for (int32_t v : t) used[v] = 1;
    }
    const auto counts = face_counts(tets);
    std::set<FaceKey> boundary;
    for (const auto& [k, n] : counts) {
        CHECK(n <= 2);
        if (n == 1) boundary.insert(k);
    }
    CHECK(boundary == hull);
    for (const Tri& f : protected_faces) CHECK(counts.count(face_key(f[0], f[1], f[2])) == 1);
    CHECK(std::count(used.begin(), used.end(), 0) == 0);
}

}  // namespace bpm::test
