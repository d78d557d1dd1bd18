// 2-3 and 3-2 flips that raise the smallest dihedral angle (tetmesh/tet_flips.h).
//
// References: B. Joe, "Construction of three-dimensional improved-quality triangulations
// using local transformations", SIAM J. Sci. Comput. 16 (1995) 1292-1307; B. M. Klingner
// and J. R. Shewchuk, "Aggressive tetrahedral mesh improvement", Proc. 16th International
// Meshing Roundtable (2007) 3-23.

#include "tetmesh/tet_flips.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "bpm/predicates.h"
#include "core/tetrahedron_quality.h"
#include "tetmesh/tetmesh_internal.h"
#include "tetmesh/tet_split.h"

namespace bpm::detail {

namespace {

constexpr double kPi = 3.14159265358979323846;

// (a, b, c, d) with (c, d) chosen so that it is an even permutation of t (a, b in t).
std::array<int32_t, 2> rest_even(const Tet& t, int32_t a, int32_t b) {
    int i = -1, j = -1;
    for (int k = 0; k < 4; ++k) {
        if (t[k] == a) i = k;
        if (t[k] == b) j = k;
    }
    int rest[2], n = 0;
    for (int k = 0; k < 4; ++k)
        if (k != i && k != j) rest[n++] = k;
    // Parity of the permutation (i, j, rest0, rest1) of (0, 1, 2, 3): count inversions.
    const int p[4] = {i, j, rest[0], rest[1]};
    int inversions = 0;
    for (int u = 0; u < 4; ++u)
        for (int v = u + 1; v < 4; ++v) inversions += p[u] > p[v];
    return inversions % 2 == 0 ? std::array<int32_t, 2>{t[rest[0]], t[rest[1]]}
                               : std::array<int32_t, 2>{t[rest[1]], t[rest[0]]};
}

bool contains(const Tet& t, int32_t v) { return t[0] == v || t[1] == v || t[2] == v || t[3] == v; }

class Flipper {
public:
    Flipper(const std::vector<Vec3>& x, std::vector<Tet>& tets, std::vector<bool>* negative,
            std::vector<int32_t>& regions, std::vector<int32_t>* ancestor, const std::vector<Tri>& protected_faces,
            const TetFlipOptions& o)
        : x_(x), tets_(tets), negative_(negative), regions_(regions), ancestor_(ancestor), o_(o),
          protected_(protected_faces) {
        target_ = pseudo_from_radians(o.target_degrees * kPi / 180);
        dead_.assign(tets_.size(), 0);
        created_.assign(tets_.size(), 0);
        touched_.assign(x_.size(), 0);
        if (o.keep_surface_corners_out) surface_edges_ = surface_edges(protected_faces);
    }

    TetFlipResult run() {
        TetFlipResult result;
        // The tetrahedra below the target; the rest is never visited and only changes by
        // being a flip partner (then its replacements are tracked as created).
        std::vector<int32_t> bad;
        double good_min = std::numeric_limits<double>::infinity();
        double all_min = std::numeric_limits<double>::infinity();
        for (size_t t = 0; t < tets_.size(); ++t) {
            const double q = quality(static_cast<int32_t>(t));
            all_min = std::min(all_min, q);
            if (q < target_) bad.push_back(static_cast<int32_t>(t));
            else good_min = std::min(good_min, q);
        }
        result.visited = static_cast<int64_t>(bad.size());
        result.min_dihedral_before_degrees = tets_.empty() ? 0 : radians_from_pseudo(all_min) * 180 / kPi;
        std::vector<int32_t> first_bad = bad;
        for (int sweep = 0; sweep < o_.sweeps && !bad.empty(); ++sweep) {
            ++result.sweeps;
            std::vector<std::pair<double, int32_t>> order;
            order.reserve(bad.size());
            for (int32_t t : bad)
                if (!dead_[t]) order.emplace_back(quality(t), t);
            std::sort(order.begin(), order.end());
            order.erase(std::unique(order.begin(), order.end()), order.end());
            build_incidence(order);
            next_.clear();
            std::vector<int32_t> failed;
            int64_t flips = 0;
            for (const auto& e : order) {
                const int32_t t = e.second;
                if (dead_[t]) continue;
                if (quality(t) >= target_) continue;
                bool in_w = true;
                for (int32_t v : tets_[t]) in_w = in_w && slot_[v] >= 0;
                if (!in_w) {
                    next_.push_back(t);  // no incidence lists for all its vertices: next sweep
                } else if (improve(t, result)) {
                    ++flips;
                } else {
                    failed.push_back(t);
                }
            }
            // A tetrahedron no flip could improve is retried only if a flip since touched one
            // of its vertices (its options are flips of tetrahedra sharing two of them).
            for (int32_t t : failed)
                if (!dead_[t] && (touched_[tets_[t][0]] || touched_[tets_[t][1]] || touched_[tets_[t][2]] ||
                                  touched_[tets_[t][3]]))
                    next_.push_back(t);
            for (int32_t v : touched_list_) touched_[v] = 0;
            touched_list_.clear();
            clear_incidence();
            if (flips == 0) break;
            bad.swap(next_);
        }
        // Smallest angle afterwards: over the tetrahedra ever below the target or made by a
        // flip, and the untouched rest (at least good_min >= target).
        double after = good_min;
        for (int32_t t : first_bad)
            if (!dead_[t]) after = std::min(after, quality(t));
        for (size_t t = 0; t < tets_.size(); ++t)
            if (created_[t] && !dead_[t]) after = std::min(after, quality(static_cast<int32_t>(t)));
        if (!(after < target_)) {  // everything is above the target: measure exactly
            after = std::numeric_limits<double>::infinity();
            for (size_t t = 0; t < tets_.size(); ++t)
                if (!dead_[t]) after = std::min(after, quality(static_cast<int32_t>(t)));
        }
        result.min_dihedral_after_degrees = tets_.empty() ? 0 : radians_from_pseudo(after) * 180 / kPi;
        return result;
    }

    // Drops removed tetrahedra (keeping the order of the rest) and fills `created`.
    void compact(std::vector<char>* created) {
        size_t n = 0;
        for (size_t t = 0; t < tets_.size(); ++t) {
            if (dead_[t]) continue;
            tets_[n] = tets_[t];
            regions_[n] = regions_[t];
            if (negative_) (*negative_)[n] = (*negative_)[t];
            if (ancestor_) (*ancestor_)[n] = (*ancestor_)[t];
            created_[n] = created_[t];
            ++n;
        }
        tets_.resize(n);
        regions_.resize(n);
        if (negative_) negative_->resize(n);
        if (ancestor_) ancestor_->resize(n);
        created_.resize(n);
        if (created) *created = created_;
    }

private:
    Tet oriented(int32_t t) const {
        Tet T = tets_[t];
        if (negative_ && (*negative_)[t]) std::swap(T[2], T[3]);
        return T;
    }
    double quality(int32_t t) const {
        const Tet T = oriented(t);
        return quality_of(T);
    }
    double quality_of(const Tet& T) const { return min_dihedral_pseudo(x_[T[0]], x_[T[1]], x_[T[2]], x_[T[3]]); }
    // Positively oriented (exact) and, with keep_surface_corners_out, no surface corner.
    bool allowed(const Tet& T) const {
        if (o_.keep_surface_corners_out && has_surface_corner(T, surface_edges_)) return false;
        return orient3d(x_[T[0]], x_[T[1]], x_[T[2]], x_[T[3]]) == 1;
    }
    bool is_protected(int32_t a, int32_t b, int32_t c) const {
        return protected_.contains(a, b, c);
    }
    bool compatible(int32_t s, int32_t t) const {
        return regions_[s] == regions_[t] && (!ancestor_ || (*ancestor_)[s] == (*ancestor_)[t]);
    }

    // Tetrahedra around W: the vertices of the tetrahedra to visit and their neighbours
    // (so that the ring of every edge of a visited tetrahedron has incidence lists). Two
    // scans of the mesh.
    void build_incidence(const std::vector<std::pair<double, int32_t>>& order) {
        slot_.assign(x_.size(), -1);
        lists_.clear();
        std::vector<char> core(x_.size(), 0);
        for (const auto& e : order)
            for (int32_t v : tets_[e.second]) core[v] = 1;
        for (size_t t = 0; t < tets_.size(); ++t) {
            if (dead_[t]) continue;
            const Tet& T = tets_[t];
            if (!(core[T[0]] || core[T[1]] || core[T[2]] || core[T[3]])) continue;
            for (int32_t v : T)
                if (slot_[v] < 0) {
                    slot_[v] = static_cast<int32_t>(lists_.size());
                    lists_.emplace_back();
                }
        }
        for (size_t t = 0; t < tets_.size(); ++t) {
            if (dead_[t]) continue;
            for (int32_t v : tets_[t])
                if (slot_[v] >= 0) lists_[slot_[v]].push_back(static_cast<int32_t>(t));
        }
    }
    void clear_incidence() {
        slot_.clear();
        lists_.clear();
    }
    void attach(int32_t t) {
        for (int32_t v : tets_[t])
            if (slot_[v] >= 0) lists_[slot_[v]].push_back(t);
    }
    void detach(int32_t t) {
        for (int32_t v : tets_[t]) {
            if (slot_[v] < 0) continue;
            auto& l = lists_[slot_[v]];
            const auto it = std::find(l.begin(), l.end(), t);
            if (it != l.end()) l.erase(it);  // keeps the order (determinism does not need it, clarity does)
        }
    }
    // Puts `fresh` (positively oriented) into the slots `reuse`, appending the rest; the
    // slots of `reuse` beyond fresh.size() are removed. Region/ancestor from `like`.
    void replace(const std::vector<int32_t>& reuse, const std::vector<Tet>& fresh) {
        const int32_t like = reuse[0];
        const int32_t region = regions_[like];
        const int32_t anc = ancestor_ ? (*ancestor_)[like] : 0;
        for (int32_t t : reuse) detach(t);
        for (size_t i = 0; i < fresh.size(); ++i) {
            int32_t t;
            if (i < reuse.size()) {
                t = reuse[i];
            } else {
                t = static_cast<int32_t>(tets_.size());
                tets_.emplace_back();
                regions_.push_back(region);
                if (negative_) negative_->push_back(false);
                if (ancestor_) ancestor_->push_back(anc);
                dead_.push_back(0);
                created_.push_back(0);
            }
            tets_[t] = fresh[i];
            for (int32_t v : fresh[i])
                if (!touched_[v]) touched_[v] = 1, touched_list_.push_back(v);
            regions_[t] = region;
            if (negative_) (*negative_)[t] = false;
            if (ancestor_) (*ancestor_)[t] = anc;
            created_[t] = 1;
            attach(t);
            if (quality_of(fresh[i]) < target_) next_.push_back(t);
        }
        for (size_t i = fresh.size(); i < reuse.size(); ++i) dead_[reuse[i]] = 1;
    }

    // The tetrahedron other than t with the face (a, b, c), or -1.
    int32_t across(int32_t t, int32_t a, int32_t b, int32_t c) const {
        for (int32_t s : lists_[slot_[a]])
            if (s != t && contains(tets_[s], b) && contains(tets_[s], c)) return s;
        return -1;
    }

    struct Candidate {
        double quality = -std::numeric_limits<double>::infinity();
        std::vector<int32_t> old;
        std::vector<Tet> fresh;
    };

    // The best flip that removes t, made if it raises the local smallest angle.
    bool improve(int32_t t, TetFlipResult& result) {
        const Tet T = oriented(t);
        Candidate best;
        std::vector<Tet> fresh;
        // 2-3 across each face of T.
        for (int k = 0; k < 4; ++k) {
            const auto f = outward_face(T, k);
            const int32_t a = f[0], b = f[1], c = f[2], d = T[k];
            if (is_protected(a, b, c)) continue;
            const int32_t n = across(t, a, b, c);
            if (n < 0 || !compatible(t, n)) continue;
            int32_t e = -1;
            for (int32_t v : tets_[n])
                if (v != a && v != b && v != c) e = v;
            // The edge de must be new.
            bool exists = false;
            for (int32_t s : lists_[slot_[d]])
                if (contains(tets_[s], e)) exists = true;
            if (exists) continue;
            fresh = {Tet{a, b, d, e}, Tet{b, c, d, e}, Tet{c, a, d, e}};
            consider(best, {t, n}, fresh);
        }
        // Edge removal (3-2, 4-4, 5-6, ...) of each edge of T.
        static constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
        for (const auto& ed : kEdges) remove_edge(t, T, T[ed[0]], T[ed[1]], best);
        if (best.old.empty()) return false;
        if (best.old.size() == 2) ++result.flips_23;
        else ++result.edge_removals;
        // Keep the lowest indices for the new tetrahedra (deterministic, compact-friendly).
        std::vector<int32_t> reuse = best.old;
        std::sort(reuse.begin(), reuse.end());
        replace(reuse, best.fresh);
        return true;
    }

    // The tetrahedra around the edge pq form a ring (p, q, r_i, r_i+1), i = 0..m-1 (each an
    // even permutation of a positively oriented tetrahedron); replacing them by
    // (r_i, r_k, r_j, q) and (r_i, r_j, r_k, p) for the triangles (i, k, j) of a triangulation
    // of the ring polygon removes the edge. The triangulation with the largest smallest angle
    // comes from dynamic programming over the polygon's diagonals (Shewchuk, "Two discrete
    // optimization algorithms for the topological improvement of tetrahedral meshes", 2002).
    void remove_edge(int32_t t, const Tet& T, int32_t p, int32_t q, Candidate& best) const {
        constexpr int kMaxRing = 7;
        int32_t around = 0;
        for (int32_t s : lists_[slot_[p]])
            if (contains(tets_[s], q))
                if (++around > kMaxRing) return;
        std::vector<int32_t> r;  // ring vertices in order
        std::vector<int32_t> old;
        const auto cd = rest_even(T, p, q);
        r.push_back(cd[0]);
        r.push_back(cd[1]);
        old.push_back(t);
        while (true) {
            // The tetrahedron (p, q, r.back(), x).
            int32_t next = -1, x = -1;
            for (int32_t s : lists_[slot_[p]]) {
                if (!contains(tets_[s], q) || std::find(old.begin(), old.end(), s) != old.end()) continue;
                const auto pair = rest_even(oriented(s), p, q);
                if (pair[0] == r.back()) next = s, x = pair[1];
            }
            if (next < 0) return;  // the ring is open: pq is on the mesh's boundary
            if (!compatible(t, next) || is_protected(p, q, r.back())) return;
            old.push_back(next);
            if (x == r.front()) break;
            if (static_cast<int>(r.size()) >= kMaxRing) return;
            r.push_back(x);
        }
        const int m = static_cast<int>(r.size());
        if (m < 3 || static_cast<int32_t>(old.size()) != around || static_cast<int>(old.size()) != m) return;
        if (is_protected(p, q, r.front())) return;
        // New diagonals r_i r_j must not be edges already.
        auto edge_exists = [&](int32_t u, int32_t v) {
            if (slot_[u] >= 0) {
                for (int32_t s : lists_[slot_[u]])
                    if (contains(tets_[s], v)) return true;
                return false;
            }
            if (slot_[v] >= 0) {
                for (int32_t s : lists_[slot_[v]])
                    if (contains(tets_[s], u)) return true;
                return false;
            }
            return true;  // unknown: do not risk it
        };
        // With three around the edge the new face r0 r1 r2 must not be a face already (with
        // more, every triangle of the ring has a new diagonal).
        if (m == 3)
            for (int32_t s : lists_[slot_[r[0]]])
                if (contains(tets_[s], r[1]) && contains(tets_[s], r[2])) return;
        double old_min = std::numeric_limits<double>::infinity();
        for (int32_t s : old) old_min = std::min(old_min, quality(s));
        // DP: Q[i][j] = best smallest angle of the polygon r_i..r_j, K[i][j] the apex.
        const double kNone = -std::numeric_limits<double>::infinity();
        double Q[kMaxRing][kMaxRing];
        int K[kMaxRing][kMaxRing];
        for (int len = 1; len < m; ++len)
            for (int i = 0; i + len < m; ++i) {
                const int j = i + len;
                K[i][j] = -1;
                if (len == 1) {
                    Q[i][j] = std::numeric_limits<double>::infinity();
                    continue;
                }
                Q[i][j] = kNone;
                if (!(i == 0 && j == m - 1) && edge_exists(r[i], r[j])) continue;
                for (int k = i + 1; k < j; ++k) {
                    const double sub = std::min(Q[i][k], Q[k][j]);
                    if (!(sub > Q[i][j]) || !(sub > old_min)) continue;
                    const Tet up{r[i], r[k], r[j], q}, down{r[i], r[j], r[k], p};
                    const double here = std::min({sub, quality_of(up), quality_of(down)});
                    if (!(here > Q[i][j]) || !(here > old_min)) continue;
                    if (!allowed(up) || !allowed(down)) continue;
                    Q[i][j] = here;
                    K[i][j] = k;
                }
            }
        const double new_min = Q[0][m - 1];
        if (!(new_min > old_min) || !(new_min > best.quality)) return;
        std::vector<Tet> fresh;
        std::vector<std::array<int, 2>> stack{{0, m - 1}};
        while (!stack.empty()) {
            const auto [i, j] = stack.back();
            stack.pop_back();
            if (j - i < 2) continue;
            const int k = K[i][j];
            fresh.push_back(Tet{r[i], r[k], r[j], q});
            fresh.push_back(Tet{r[i], r[j], r[k], p});
            stack.push_back({i, k});
            stack.push_back({k, j});
        }
        best.quality = new_min;
        best.old = old;
        best.fresh = std::move(fresh);
    }

    void consider(Candidate& best, const std::vector<int32_t>& old, const std::vector<Tet>& fresh) const {
        double old_min = std::numeric_limits<double>::infinity();
        for (int32_t s : old) old_min = std::min(old_min, quality(s));
        double new_min = std::numeric_limits<double>::infinity();
        for (const Tet& n : fresh) new_min = std::min(new_min, quality_of(n));
        if (!(new_min > old_min) || !(new_min > best.quality)) return;
        for (const Tet& n : fresh)
            if (!allowed(n)) return;  // exact: the flip must give a valid mesh
        best.quality = new_min;
        best.old = old;
        best.fresh = fresh;
    }

    const std::vector<Vec3>& x_;
    std::vector<Tet>& tets_;
    std::vector<bool>* negative_;
    std::vector<int32_t>& regions_;
    std::vector<int32_t>* ancestor_;
    const TetFlipOptions& o_;
    double target_ = 0;
    ProtectedFaces protected_;
    std::vector<std::array<int32_t, 2>> surface_edges_;  // with keep_surface_corners_out
    std::vector<char> dead_, created_;
    std::vector<int32_t> slot_;
    std::vector<std::vector<int32_t>> lists_;
    std::vector<int32_t> next_;
    std::vector<char> touched_;  // vertices of tetrahedra made by flips this sweep
    std::vector<int32_t> touched_list_;
};

}  // namespace

TetFlipResult flip_tetrahedra(const std::vector<Vec3>& x, std::vector<Tet>& tets, std::vector<bool>* negative,
                              std::vector<int32_t>& regions, std::vector<int32_t>* ancestor,
                              const std::vector<Tri>& protected_faces, const TetFlipOptions& options,
                              std::vector<char>* created) {
    const auto start = std::chrono::steady_clock::now();
    Flipper flipper(x, tets, negative, regions, ancestor, protected_faces, options);
    TetFlipResult result = flipper.run();
    flipper.compact(created);
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace bpm::detail
