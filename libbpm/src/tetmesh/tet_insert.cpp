// Vertex insertion into locked slivers (tetmesh/tet_insert.h).
//
// Reference: B. M. Klingner and J. R. Shewchuk, "Aggressive tetrahedral mesh improvement",
// Proc. 16th International Meshing Roundtable (2007) 3-23, section 3.3 (they grow the
// cavity by dynamic programming and optimise p with their nonsmooth smoothing; a few fixed
// cavities and a compass search suffice for the slivers TetGen leaves at level 0).

#include "tetmesh/tet_insert.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <tuple>

#include "bpm/predicates.h"
#include "core/tetrahedron_quality.h"
#include "tetmesh/tetmesh_internal.h"

namespace bpm::detail {

namespace {

constexpr double kPi = 3.14159265358979323846;
// Compass search: at most this many moves or halvings; it stops once the step is below
// kMinStep times the longest edge of the tetrahedron.
constexpr int kSearchIterations = 60;
constexpr double kMinStep = 1e-4;

class Inserter {
public:
    Inserter(std::vector<Vec3>& x, std::vector<Tet>& tets, std::vector<int32_t>& regions,
             const std::vector<Tri>& protected_faces, const TetInsertOptions& o)
        : x_(x), tets_(tets), regions_(regions), rounds_(o.rounds), protected_(protected_faces) {
        target_ = pseudo_from_radians(o.target_degrees * kPi / 180);
        dead_.assign(tets_.size(), 0);
        in_cavity_.assign(tets_.size(), 0);
        build_neighbours();
    }

    TetInsertResult run() {
        TetInsertResult result;
        double before = std::numeric_limits<double>::infinity();
        for (size_t t = 0; t < tets_.size(); ++t) before = std::min(before, quality(static_cast<int32_t>(t)));
        for (int round = 0; round < rounds_; ++round) {
            std::vector<std::pair<double, int32_t>> bad;
            for (size_t t = 0; t < tets_.size(); ++t) {
                if (dead_[t]) continue;
                const double q = quality(static_cast<int32_t>(t));
                if (q < target_) bad.emplace_back(q, static_cast<int32_t>(t));
            }
            std::sort(bad.begin(), bad.end());
            if (round == 0) result.tried = static_cast<int64_t>(bad.size());
            int64_t inserted = 0;
            for (const auto& e : bad)
                if (!dead_[e.second] && try_insert(e.second)) ++inserted;
            result.inserted += inserted;
            ++result.rounds;
            if (inserted == 0) break;
        }
        double after = std::numeric_limits<double>::infinity();
        for (size_t t = 0; t < tets_.size(); ++t)
            if (!dead_[t]) after = std::min(after, quality(static_cast<int32_t>(t)));
        if (!tets_.empty()) {
            result.min_dihedral_before_degrees = radians_from_pseudo(before) * 180 / kPi;
            result.min_dihedral_after_degrees = radians_from_pseudo(after) * 180 / kPi;
        }
        return result;
    }

    // Drops the replaced tetrahedra, keeping the order of the rest.
    void compact() {
        size_t n = 0;
        for (size_t t = 0; t < tets_.size(); ++t) {
            if (dead_[t]) continue;
            tets_[n] = tets_[t];
            regions_[n] = regions_[t];
            ++n;
        }
        tets_.resize(n);
        regions_.resize(n);
    }

private:
    // A boundary face of a cavity, oriented out of it, and the tetrahedron on its other
    // side (-1 on the mesh's boundary) with that face's local index there.
    struct Face {
        std::array<int32_t, 3> v;
        int32_t outside;
        int outside_local;
    };
    struct Star {
        std::vector<int32_t> cavity;
        std::vector<Face> faces;
        Vec3 p{0, 0, 0};
        double quality = -std::numeric_limits<double>::infinity();
    };

    double quality(int32_t t) const { return quality_of(tets_[t]); }
    double quality_of(const Tet& T) const { return min_dihedral_pseudo(x_[T[0]], x_[T[1]], x_[T[2]], x_[T[3]]); }
    bool is_protected(const std::array<int32_t, 3>& f) const {
        return protected_.contains(f[0], f[1], f[2]);
    }

    void build_neighbours() {
        nb_.assign(tets_.size(), {-1, -1, -1, -1});
        const std::vector<TetFace> faces = enumerate_faces(tets_);
        for (size_t i = 0; i + 1 < faces.size(); ++i)
            if (faces[i].key == faces[i + 1].key) {
                nb_[faces[i].tet][faces[i].local] = faces[i + 1].tet;
                nb_[faces[i + 1].tet][faces[i + 1].local] = faces[i].tet;
            }
    }

    // The smallest pseudo-angle of the star of p over `faces`, taken in the order `order`,
    // or some value <= floor as soon as it is known not to exceed floor; `worst`: the
    // position in `order` of the face that gave the smallest so far. The order changes only
    // which value <= floor comes back (the minimum over all faces is the same in any order),
    // and every caller treats those alike: not better.
    double star_quality(const std::vector<Face>& faces, const std::vector<int32_t>& order, const Vec3& p,
                        double floor, size_t& worst) const {
        double q = std::numeric_limits<double>::infinity();
        for (size_t i = 0; i < order.size(); ++i) {
            const Face& f = faces[size_t(order[i])];
            const double fq = min_dihedral_pseudo(x_[f.v[0]], x_[f.v[2]], x_[f.v[1]], p);
            if (fq < q) {
                q = fq;
                worst = i;
            }
            if (!(q > floor)) return q;
        }
        return q;
    }

    // The boundary of the cavity, or false if it is not a closed 2-manifold through every
    // corner of the cavity or a face inside it is on S.
    bool boundary_of(const std::vector<int32_t>& cavity, std::vector<Face>& faces) {
        faces.clear();
        for (int32_t c : cavity)
            if (regions_[c] != regions_[cavity[0]]) return false;
        for (int32_t c : cavity) in_cavity_[c] = 1;
        bool ok = true;
        for (int32_t c : cavity) {
            for (int k = 0; k < 4 && ok; ++k) {
                const int32_t n = nb_[c][k];
                const auto f = outward_face(tets_[c], k);
                if (n >= 0 && in_cavity_[n]) {
                    if (is_protected(f)) ok = false;
                    continue;
                }
                int local = -1;
                if (n >= 0)
                    for (int j = 0; j < 4; ++j)
                        if (nb_[n][j] == c) local = j;
                faces.push_back({f, n, local});
            }
        }
        for (int32_t c : cavity) in_cavity_[c] = 0;
        if (!ok) return false;
        // Each directed edge once and its reverse once: every edge in exactly two faces,
        // oriented consistently.
        std::vector<std::array<int32_t, 2>> edges;
        edges.reserve(3 * faces.size());
        for (const Face& f : faces)
            for (int i = 0; i < 3; ++i) edges.push_back({f.v[i], f.v[(i + 1) % 3]});
        std::sort(edges.begin(), edges.end());
        for (size_t i = 0; i < edges.size(); ++i) {
            if (i + 1 < edges.size() && edges[i] == edges[i + 1]) return false;
            if (!std::binary_search(edges.begin(), edges.end(), std::array<int32_t, 2>{edges[i][1], edges[i][0]}))
                return false;
        }
        // No corner of the cavity may be left inside it (it would lose all its tetrahedra).
        for (int32_t c : cavity)
            for (int32_t v : tets_[c]) {
                bool found = false;
                for (const Face& f : faces) found = found || f.v[0] == v || f.v[1] == v || f.v[2] == v;
                if (!found) return false;
            }
        return true;
    }

    // The tetrahedra around the edge pq of t (t first, then around the edge), or false when
    // the edge is on the mesh's boundary or has more than kMaxRing of them.
    bool edge_ring(int32_t t, int32_t p, int32_t q, std::vector<int32_t>& ring) const {
        constexpr size_t kMaxRing = 8;
        ring.assign(1, t);
        int32_t cur = t, cross = -1;  // cross: the corner of cur whose opposite face is crossed next
        for (int32_t v : tets_[t])
            if (v != p && v != q) cross = v;
        while (true) {
            int local = 0;
            while (tets_[cur][local] != cross) ++local;
            const int32_t next = nb_[cur][local];
            if (next < 0) return false;
            if (next == t) return true;
            if (ring.size() >= kMaxRing) return false;
            ring.push_back(next);
            int32_t w = -1;  // the corner shared with next besides p and q: cross next's face opposite it
            for (int32_t v : tets_[cur])
                if (v != p && v != q && v != cross) w = v;
            cross = w;
            cur = next;
        }
    }

    // Compass search for the p that maximises the star's smallest angle, from `start`.
    // The faces are tried worst first (the face that gave the smallest angle at the last
    // point kept): a neighbouring point that is no better is then usually refused after one
    // tetrahedron, not after half the star (noisy 32^3: most of bpm-mesh's time was here).
    // The point found is the same as in face order (star_quality).
    void optimise(Star& s, const Vec3& start, double length) {
        std::vector<int32_t>& order = face_order_;
        order.resize(s.faces.size());
        for (size_t i = 0; i < order.size(); ++i) order[i] = int32_t(i);
        size_t worst = 0;
        Vec3 p = start;
        double q = star_quality(s.faces, order, p, -std::numeric_limits<double>::infinity(), worst);
        if (order.empty()) return;  // no star (boundary_of gives a closed one: not reached)
        std::swap(order[0], order[worst]);
        double h = 0.25 * length;
        for (int it = 0; it < kSearchIterations && h > kMinStep * length; ++it) {
            Vec3 best_p = p;
            double best_q = q;
            size_t best_worst = 0;
            for (int axis = 0; axis < 3; ++axis)
                for (const double sign : {1.0, -1.0}) {
                    Vec3 c = p;
                    c[axis] += sign * h;
                    size_t cw = 0;
                    const double cq = star_quality(s.faces, order, c, best_q, cw);
                    if (cq > best_q) best_q = cq, best_p = c, best_worst = cw;
                }
            if (best_q > q) {
                p = best_p, q = best_q;
                std::swap(order[0], order[best_worst]);
            } else {
                h *= 0.5;
            }
        }
        if (q > s.quality) s.p = p, s.quality = q;
    }

    bool try_insert(int32_t t) {
        const Tet T = tets_[t];  // a copy: replace() appends to tets_
        // Neighbours that may join the cavity.
        std::vector<int32_t> candidates;
        for (int k = 0; k < 4; ++k) {
            const int32_t n = nb_[t][k];
            if (n >= 0 && regions_[n] == regions_[t] && !is_protected(outward_face(T, k))) candidates.push_back(n);
        }
        Vec3 centroid{0, 0, 0};
        double length = 0;
        for (int i = 0; i < 4; ++i) {
            centroid = centroid + 0.25 * x_[T[i]];
            for (int j = i + 1; j < 4; ++j) length = std::max(length, distance(x_[T[i]], x_[T[j]]));
        }
        // The cavities: t with each subset of its face neighbours (not t alone: its star
        // splits every dihedral angle of t), and t with all tetrahedra around one or both of
        // its two largest-angle edges when they are obtuse, with and without the face
        // neighbours. A flat sliver needs the latter: its two long edges cross, and with the
        // face neighbours alone they stay reflex edges of the cavity, one above and one below
        // any new vertex.
        std::vector<std::vector<int32_t>> cavities;
        const unsigned subsets = 1u << candidates.size();
        for (unsigned mask = 1; mask < subsets; ++mask) {
            cavities.emplace_back(1, t);
            for (size_t i = 0; i < candidates.size(); ++i)
                if (mask & (1u << i)) cavities.back().push_back(candidates[i]);
        }
        {
            static constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
            double angle[6];
            dihedral_angles(x_[T[0]], x_[T[1]], x_[T[2]], x_[T[3]], angle);
            int order[6] = {0, 1, 2, 3, 4, 5};
            std::stable_sort(order, order + 6, [&](int i, int j) { return angle[i] > angle[j]; });
            std::vector<std::vector<int32_t>> rings;
            std::vector<int32_t> ring;
            for (int i = 0; i < 2; ++i)
                if (angle[order[i]] > kPi / 2 && edge_ring(t, T[kEdges[order[i]][0]], T[kEdges[order[i]][1]], ring))
                    rings.push_back(ring);
            if (rings.size() == 2) {
                rings.push_back(rings[0]);
                rings.back().insert(rings.back().end(), rings[1].begin(), rings[1].end());
            }
            for (const auto& r : rings) {
                cavities.push_back(r);
                cavities.push_back(r);
                cavities.back().insert(cavities.back().end(), candidates.begin(), candidates.end());
            }
            for (auto& c : cavities) {  // t first, then each once in index order

                std::sort(c.begin() + 1, c.end());
                c.erase(std::unique(c.begin() + 1, c.end()), c.end());
                c.erase(std::remove(c.begin() + 1, c.end(), t), c.end());
            }
        }
        Star best, s;
        for (size_t i = 0; i < cavities.size(); ++i) {
            if (std::find(cavities.begin(), cavities.begin() + static_cast<std::ptrdiff_t>(i), cavities[i]) !=
                cavities.begin() + static_cast<std::ptrdiff_t>(i))
                continue;  // tried already
            s.cavity = cavities[i];
            if (!boundary_of(s.cavity, s.faces)) continue;
            double old_min = std::numeric_limits<double>::infinity();
            for (int32_t c : s.cavity) old_min = std::min(old_min, quality(c));
            s.quality = -std::numeric_limits<double>::infinity();
            optimise(s, centroid, length);
            if (!(s.quality > old_min) || !(s.quality > best.quality)) continue;
            bool positive = true;  // exact: the star must be a valid mesh of the cavity
            for (const Face& f : s.faces)
                positive = positive && orient3d(x_[f.v[0]], x_[f.v[2]], x_[f.v[1]], s.p) == 1;
            if (positive) best = s;
        }
        if (best.cavity.empty()) return false;
        replace(best);
        return true;
    }

    // The star of a new vertex at best.p replaces best.cavity.
    void replace(const Star& best) {
        const int32_t p = static_cast<int32_t>(x_.size());
        x_.push_back(best.p);
        const int32_t region = regions_[best.cavity[0]];
        for (int32_t c : best.cavity) dead_[c] = 1;
        // The new tetrahedron on face (a, b, c) is (a, c, b, p): its face opposite p (local 3)
        // is (a, b, c), and its faces through p (kTetFaces) are opposite a (local 0: edge bc),
        // c (local 1: edge ab) and b (local 2: edge ca).
        struct EdgeSide {
            int32_t lo, hi, tet;
            int local;
        };
        std::vector<EdgeSide> sides;
        for (const Face& f : best.faces) {
            const int32_t t = static_cast<int32_t>(tets_.size());
            tets_.push_back(Tet{f.v[0], f.v[2], f.v[1], p});
            regions_.push_back(region);
            dead_.push_back(0);
            in_cavity_.push_back(0);
            nb_.push_back({-1, -1, -1, f.outside});
            if (f.outside >= 0) nb_[f.outside][f.outside_local] = t;
            const int32_t a = f.v[0], b = f.v[1], c = f.v[2];
            sides.push_back({std::min(a, b), std::max(a, b), t, 1});
            sides.push_back({std::min(b, c), std::max(b, c), t, 0});
            sides.push_back({std::min(c, a), std::max(c, a), t, 2});
        }
        std::sort(sides.begin(), sides.end(), [](const EdgeSide& u, const EdgeSide& v) {
            return std::tie(u.lo, u.hi, u.tet) < std::tie(v.lo, v.hi, v.tet);
        });
        for (size_t i = 0; i + 1 < sides.size(); i += 2) {  // each edge twice (boundary_of)
            nb_[sides[i].tet][sides[i].local] = sides[i + 1].tet;
            nb_[sides[i + 1].tet][sides[i + 1].local] = sides[i].tet;
        }
    }

    std::vector<Vec3>& x_;
    std::vector<Tet>& tets_;
    std::vector<int32_t>& regions_;
    int rounds_ = 1;
    double target_ = 0;
    ProtectedFaces protected_;
    std::vector<std::array<int32_t, 4>> nb_;  // tetrahedron across face k (kTetFaces), or -1
    std::vector<char> dead_, in_cavity_;
    std::vector<int32_t> face_order_;  // optimise()'s order of the star's faces
};

}  // namespace

TetInsertResult insert_vertices(std::vector<Vec3>& x, std::vector<Tet>& tets, std::vector<int32_t>& regions,
                                const std::vector<Tri>& protected_faces, const TetInsertOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    Inserter inserter(x, tets, regions, protected_faces, options);
    TetInsertResult result = inserter.run();
    inserter.compact();
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace bpm::detail
