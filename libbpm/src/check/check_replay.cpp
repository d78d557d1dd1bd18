// check_replay: bpm-check --replay. Re-applies the recorded point removals
// (/simplification_steps, bpm-simplify --record-steps) to the connectivity of S0 and
// checks every one of them combinatorially; the result must be the coarse surface.
//
// Per step (vertex v, recorded triangles N), on the current complex K:
//
//  1. The star of v. As in the simplifier (vertex_removal.cpp) and in the topology
//     check (surface_topology.h), an edge is a feature edge if it has 1 triangle
//     (boundary), 3 or more (non-manifold) or 2 of different patches (interface).
//     v must be regular: either no feature spoke and the star is one closed fan (a
//     disk; its link is a simple cycle), or exactly two feature spokes (v,a), (v,b)
//     and every fan of triangles connected through regular spokes runs from a to b
//     (k half-disks glued along the feature line, paper §2.4; k = 1 on a boundary,
//     k >= 3 where sheets meet). A crease or a patch border is combinatorially a disk
//     cut by the diagonal (a,b), so the simplifier's half-disk removals along creases
//     are accepted as disk removals. Any other vertex is a feature vertex: removing it
//     changes the non-manifold structure.
//  2. The link is the boundary of N: every polygon (the link cycle of a disk, or the
//     path a..b of a half-disk closed by the new feature edge (b,a)) must be filled by
//     its own triangles of N: each polygon side in exactly one of them, every other
//     edge in exactly two, n - 2 triangles for n corners, and around every corner one
//     fan from one side to the other, i.e. a triangulated disk. New triangles carry
//     the patch of the half-disk they replace.
//  3. The local condition of Conjecture 2.1: no new edge (an edge of N that is not an
//     edge of the link, including the new feature edge (a,b)) is already an edge of
//     K; and no triangle of N is already a triangle of K (for a vertex of degree 3 the
//     retriangulation adds no edge at all, and the condition must be on the triangle).
//
// Soundness of checking the global invariants only every K steps. For a step that
// passes 1-3 every invariant of check_topology is preserved, by a local argument:
// edge-connected components (N is edge-connected, meets the rest of K in exactly the
// link edges, as the star did, and its new edges are in no other triangle by 3);
// V - E + T (-1 vertex, -n spokes, +(n-3) diagonals, -n + (n-2) triangles per disk,
// likewise per half-disk); Z2 2-cycles (each disk / half-disk of the star and each
// triangulated disk of N is all-or-nothing in a 2-cycle, and both have the same Z2
// boundary up to the spokes / new feature edge, which are traversed an even number of
// times), hence all Betti numbers; orientability (a disk re-triangulated with the same
// boundary cycle carries the same orientation constraints); and the non-manifold
// structure (the feature line a-v-b becomes a-b with the same sheets and patches; at
// every link vertex the fan through v is replaced by a fan through new regular edges,
// so its regularity and wedges, hence boundary loops, are unchanged). The invariants
// are nevertheless recomputed from scratch (compute_topology) every K steps and after
// the last one, as an independent check of that argument and of this code; V - E + T
// is also updated exactly at every step. Should a recomputation ever disagree, the
// step is found by bisection over the steps since the last agreeing recomputation and
// reported as a counterexample. A step that satisfies 2 (as a plain boundary
// condition) and 3 but not 1 (a feature vertex) is applied and the invariants are
// recomputed at once: if they changed, the step is a counterexample to Conjecture 2.1
// as stated for 2-complexes (e.g. the apex of two cones touching at a point).
//
// The replay stops at the first step that fails (the state after it is meaningless).
#include <algorithm>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

#include "bpm/check.h"
#include "bpm/surface_topology.h"
#include "check/check_internal.h"
#include "core/edge_key.h"

namespace bpm {

namespace {

using Ids = std::vector<std::pair<std::string, int64_t>>;

using detail::edge_key;
using detail::edge_key_first;
using detail::edge_key_second;

inline bool contains(const Tri& t, int32_t v) { return t[0] == v || t[1] == v || t[2] == v; }

std::string tri_text(const Tri& t) {
    return "(" + std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " + std::to_string(t[2]) + ")";
}
std::string edge_text(uint64_t k) { return "(" + std::to_string(edge_key_first(k)) + ", " + std::to_string(edge_key_second(k)) + ")"; }

// The connectivity being replayed: triangles over original vertex ids with their patch
// and the original component they descend from, and the alive triangles of every vertex.
class ReplayMesh {
public:
    ReplayMesh(const Surface& s, const std::vector<int32_t>& component)
        : tris_(s.triangles), patch_(s.patches), comp_(component), alive_(s.triangles.size(), 1),
          around_(s.vertices.size()) {
        if (patch_.size() != tris_.size()) patch_.assign(tris_.size(), 0);
        for (int32_t t = 0; t < static_cast<int32_t>(tris_.size()); ++t) attach(t);
        alive_count_ = static_cast<int64_t>(tris_.size());
    }
    const std::vector<int32_t>& around(int32_t v) const { return around_[v]; }
    const Tri& tri(int32_t t) const { return tris_[t]; }
    int32_t patch(int32_t t) const { return patch_[t]; }
    int32_t component(int32_t t) const { return comp_[t]; }
    int64_t referenced_vertices() const { return referenced_; }
    int64_t alive_triangles() const { return alive_count_; }

    bool has_edge(int32_t a, int32_t b) const {
        const auto& la = around_[a];
        const auto& lb = around_[b];
        const bool a_shorter = la.size() <= lb.size();
        for (int32_t t : a_shorter ? la : lb)
            if (contains(tris_[t], a_shorter ? b : a)) return true;
        return false;
    }
    bool has_triangle(const Tri& c) const {
        for (int32_t t : around_[c[0]])
            if (contains(tris_[t], c[1]) && contains(tris_[t], c[2])) return true;
        return false;
    }
    void remove(int32_t t) {
        if (!alive_[t]) return;
        alive_[t] = 0;
        --alive_count_;
        for (int k = 0; k < 3; ++k) {
            const int32_t v = tris_[t][k];
            if (k > 0 && (v == tris_[t][0] || (k == 2 && v == tris_[t][1]))) continue;
            auto& list = around_[v];
            list.erase(std::find(list.begin(), list.end(), t));
            if (list.empty()) --referenced_;
        }
    }
    int32_t add(const Tri& c, int32_t patch, int32_t component) {
        const int32_t t = static_cast<int32_t>(tris_.size());
        tris_.push_back(c);
        patch_.push_back(patch);
        comp_.push_back(component);
        alive_.push_back(1);
        ++alive_count_;
        attach(t);
        return t;
    }
    // The alive triangles over all original vertices (unreferenced ones are ignored by
    // compute_topology), with the original component of each.
    Surface surface(const std::vector<Vec3>& vertices, std::vector<int32_t>& component) const {
        Surface s;
        s.vertices = vertices;
        component.clear();
        for (size_t t = 0; t < tris_.size(); ++t) {
            if (!alive_[t]) continue;
            s.triangles.push_back(tris_[t]);
            s.patches.push_back(patch_[t]);
            component.push_back(comp_[t]);
        }
        return s;
    }

private:
    void attach(int32_t t) {
        for (int k = 0; k < 3; ++k) {
            const int32_t v = tris_[t][k];
            if (k > 0 && (v == tris_[t][0] || (k == 2 && v == tris_[t][1]))) continue;
            if (around_[v].empty()) ++referenced_;
            around_[v].push_back(t);
        }
    }
    std::vector<Tri> tris_;
    std::vector<int32_t> patch_, comp_;
    std::vector<uint8_t> alive_;
    std::vector<std::vector<int32_t>> around_;
    int64_t referenced_ = 0, alive_count_ = 0;
};

// Differences between the topology of S0 and of the replayed surface; empty if none.
std::vector<std::string> topology_differences(const SurfaceTopology& original, const ReplayMesh& mesh,
                                              const Surface& s0, const std::vector<int32_t>& identity,
                                              size_t max_differences) {
    std::vector<int32_t> label;
    const Surface now = mesh.surface(s0.vertices, label);
    const SurfaceTopology t = compute_topology(now);
    TopologyCorrespondence corr;
    corr.vertex_map = identity;
    corr.component_map.assign(t.components.size(), -1);
    std::vector<std::string> out;
    for (size_t i = 0; i < label.size(); ++i) {
        int32_t& m = corr.component_map[t.triangle_component[i]];
        if (m < 0) m = label[i];
        else if (m != label[i] && out.empty())
            out.push_back("a component of the replayed surface joins triangles of original components " +
                          std::to_string(m) + " and " + std::to_string(label[i]));
    }
    if (!out.empty()) corr.component_map.clear();
    for (std::string d : compare_topology(original, t, corr, max_differences)) {
        // compare_topology speaks of "coarse"; here the second surface is the replayed one.
        for (size_t at = d.find("coarse"); at != std::string::npos; at = d.find("coarse", at + 8))
            d.replace(at, 6, "replayed");
        out.push_back(std::move(d));
    }
    return out;
}

// Everything about one step, recomputed for every step (buffers are reused).
struct StepCheck {
    enum class Kind { Disk, HalfDisks, FeatureVertex };
    Kind kind = Kind::FeatureVertex;
    std::string why_feature;                 // for FeatureVertex
    std::vector<int32_t> star;               // triangles of v
    std::vector<std::pair<int32_t, int32_t>> spoke;  // (neighbour x, star triangle with x), sorted
    std::vector<std::vector<int32_t>> polygons;      // corners in cyclic order
    std::vector<int32_t> polygon_patch;
    int32_t a = -1, b = -1;                  // feature spokes (half-disks)
    std::vector<std::string> boundary;       // rule 2 (the hole is not filled)
    std::vector<std::string> local;          // rule 3 (Conjecture 2.1's condition)
    std::vector<std::string> structure;      // rule 1 and the disk / patch parts of rule 2
    int64_t new_edges = 0;                   // distinct edges of N not in K
    int64_t spokes = 0;                      // distinct neighbours of v
};

class Replayer {
public:
    Replayer(const Surface& s0, const std::vector<int32_t>& component, const SimplificationSteps& steps)
        : steps_(steps),
          mesh_(s0, component),
          owner_(s0.vertices.size(), -1),
          stamp_(s0.vertices.size(), -1) {}

    ReplayMesh& mesh() { return mesh_; }

    // Checks step s against the current complex; fills `c`.
    void check(int64_t s, StepCheck& c);
    // Applies step s (no checks).
    void apply(int64_t s) {
        const int32_t v = steps_.vertex[s];
        const std::vector<int32_t> star = mesh_.around(v);
        const int32_t comp = star.empty() ? -1 : mesh_.component(star.front());
        for (int32_t t : star) mesh_.remove(t);
        for (int64_t j = steps_.triangle_offsets[s]; j < steps_.triangle_offsets[s + 1]; ++j)
            mesh_.add(steps_.triangles[j], steps_.triangle_patches[j], comp);
    }

private:
    void classify(int32_t v, StepCheck& c);
    bool check_retriangulation(int64_t s, int32_t v, StepCheck& c);
    void check_polygons(int64_t s, StepCheck& c);
    void check_polygon(int32_t i, const std::vector<int64_t>& members, StepCheck& c);
    const SimplificationSteps& steps_;
    ReplayMesh mesh_;
    std::vector<int32_t> owner_;  // polygon of a link vertex in this step (-2: a or b)
    std::vector<int64_t> stamp_;  // step that set owner_
};

// The other two corners of star triangle t of v.
inline std::pair<int32_t, int32_t> others(const Tri& t, int32_t v) {
    if (t[0] == v) return {t[1], t[2]};
    if (t[1] == v) return {t[2], t[0]};
    return {t[0], t[1]};
}

void Replayer::classify(int32_t v, StepCheck& c) {
    c.kind = StepCheck::Kind::FeatureVertex;
    c.polygons.clear();
    c.polygon_patch.clear();
    c.a = c.b = -1;
    c.spoke.clear();
    for (int32_t t : c.star) {
        const Tri& tri = mesh_.tri(t);
        const auto [x, y] = others(tri, v);
        if (x == y || x == v || y == v) {
            c.why_feature = "a triangle of its star has a repeated corner";
            return;
        }
        c.spoke.emplace_back(x, t);
        c.spoke.emplace_back(y, t);
    }
    std::sort(c.spoke.begin(), c.spoke.end());
    // Spoke (v, x): its triangles are c.spoke[lo .. hi).
    auto range = [&](int32_t x) {
        auto lo = std::lower_bound(c.spoke.begin(), c.spoke.end(), std::make_pair(x, INT32_MIN));
        auto hi = std::upper_bound(c.spoke.begin(), c.spoke.end(), std::make_pair(x, INT32_MAX));
        return std::make_pair(lo, hi);
    };
    std::vector<int32_t> features;
    c.spokes = 0;
    for (size_t i = 0; i < c.spoke.size();) {
        size_t j = i;
        while (j < c.spoke.size() && c.spoke[j].first == c.spoke[i].first) ++j;
        ++c.spokes;
        const bool regular = j - i == 2 && mesh_.patch(c.spoke[i].second) == mesh_.patch(c.spoke[i + 1].second);
        if (!regular) features.push_back(c.spoke[i].first);
        i = j;
    }
    // The other triangle of regular spoke (v, x), seen from t.
    auto across = [&](int32_t x, int32_t t) {
        const auto [lo, hi] = range(x);
        return lo->second == t ? (lo + 1)->second : lo->second;
    };
    if (features.empty()) {
        const int32_t t0 = c.star.front();
        const auto [x0, y0] = others(mesh_.tri(t0), v);
        std::vector<int32_t> link{x0};
        int32_t t = t0, last = y0;
        size_t visited = 1;
        while (true) {
            link.push_back(last);
            const int32_t n = across(last, t);
            if (n == t0) break;
            const auto [x, y] = others(mesh_.tri(n), v);
            last = x == last ? y : x;
            t = n;
            if (++visited > c.star.size()) break;  // cannot happen with 2 triangles per spoke; defensive
        }
        link.pop_back();  // the walk ends where it began
        if (visited != c.star.size()) {
            c.why_feature = "its star is not one disk (" + std::to_string(visited) + " of its " +
                            std::to_string(c.star.size()) + " triangles form a closed fan; non-manifold vertex)";
            return;
        }
        c.kind = StepCheck::Kind::Disk;
        c.polygons.push_back(std::move(link));
        c.polygon_patch.push_back(mesh_.patch(t0));
        return;
    }
    if (features.size() != 2) {
        c.why_feature = features.size() == 1 ? "it is the end of a feature line"
                                             : "it is a meeting point of " + std::to_string(features.size()) +
                                                   " feature edges";
        return;
    }
    c.a = features[0];
    c.b = features[1];
    size_t covered = 0;
    const auto [alo, ahi] = range(c.a);
    for (auto it = alo; it != ahi; ++it) {
        const int32_t t0 = it->second;
        const auto [x0, y0] = others(mesh_.tri(t0), v);
        std::vector<int32_t> path{c.a};
        int32_t t = t0, last = x0 == c.a ? y0 : x0;
        size_t count = 1;
        while (true) {
            path.push_back(last);
            if (last == c.a || last == c.b) break;
            const int32_t n = across(last, t);
            const auto [x, y] = others(mesh_.tri(n), v);
            last = x == last ? y : x;
            t = n;
            if (++count > c.star.size()) break;  // defensive
        }
        if (path.back() != c.b) {
            c.why_feature = "a fan of its star runs from feature edge (" + std::to_string(v) + ", " +
                            std::to_string(c.a) + ") back to it";
            return;
        }
        covered += count;
        c.polygons.push_back(std::move(path));
        c.polygon_patch.push_back(mesh_.patch(t0));
    }
    if (covered != c.star.size()) {
        c.why_feature = "its star is not made of half-disks between its two feature edges (" +
                        std::to_string(c.star.size() - covered) + " triangles are in no such fan)";
        return;
    }
    c.kind = StepCheck::Kind::HalfDisks;
}

void Replayer::check(int64_t s, StepCheck& c) {
    c.boundary.clear();
    c.local.clear();
    c.structure.clear();
    c.new_edges = 0;
    c.spokes = 0;
    const int32_t v = steps_.vertex[s];
    c.star = mesh_.around(v);
    if (c.star.empty()) {
        c.boundary.push_back("vertex " + std::to_string(v) + " has no triangles (removed before, or not on S0)");
        return;
    }
    std::sort(c.star.begin(), c.star.end());
    classify(v, c);
    const bool corners_ok = check_retriangulation(s, v, c);
    if (c.kind == StepCheck::Kind::FeatureVertex) {
        c.structure.push_back("vertex " + std::to_string(v) + " is a feature vertex (" + c.why_feature +
                              "); point removal must keep it");
        return;
    }
    if (!corners_ok) return;
    check_polygons(s, c);
}

// Rule 3 and the plain boundary condition, for every kind of vertex: link edges (the
// edges of the star opposite v) and the edges of N. Returns false where a recorded
// triangle has a bad corner (then the per-polygon rules are not checked).
bool Replayer::check_retriangulation(int64_t s, int32_t v, StepCheck& c) {
    const int64_t first = steps_.triangle_offsets[s], last = steps_.triangle_offsets[s + 1];
    auto new_tri = [&](int64_t j) { return steps_.triangles[j]; };
    std::vector<uint64_t> link_edges;
    for (int32_t t : c.star) {
        const auto [x, y] = others(mesh_.tri(t), v);
        link_edges.push_back(edge_key(x, y));
    }
    std::sort(link_edges.begin(), link_edges.end());
    std::vector<uint64_t> n_edges;
    bool corners_ok = true;
    for (int64_t j = first; j < last; ++j) {
        const Tri& t = new_tri(j);
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || contains(t, v)) {
            c.boundary.push_back("recorded triangle " + std::to_string(j) + " " + tri_text(t) +
                                 (contains(t, v) ? " contains the removed vertex" : " has a repeated corner"));
            corners_ok = false;
            continue;
        }
        for (int k = 0; k < 3; ++k) n_edges.push_back(edge_key(t[k], t[(k + 1) % 3]));
        if (mesh_.has_triangle(t))
            c.local.push_back("recorded triangle " + std::to_string(j) + " " + tri_text(t) +
                              " is already a triangle of the surface (local condition of Conjecture 2.1; the "
                              "degree-3 case, where the retriangulation adds no edge)");
    }
    if (last == first) c.boundary.push_back("the step records no triangles");
    std::sort(n_edges.begin(), n_edges.end());
    // Link vertices: every corner of N must be one.
    {
        std::vector<int32_t> link_vertices;
        for (uint64_t k : link_edges) {
            link_vertices.push_back(edge_key_first(k));
            link_vertices.push_back(edge_key_second(k));
        }
        std::sort(link_vertices.begin(), link_vertices.end());
        for (int64_t j = first; j < last && corners_ok; ++j)
            for (int32_t x : new_tri(j))
                if (!std::binary_search(link_vertices.begin(), link_vertices.end(), x)) {
                    c.boundary.push_back("recorded triangle " + std::to_string(j) + " " + tri_text(new_tri(j)) +
                                         " uses vertex " + std::to_string(x) + ", which is not on the link of " +
                                         std::to_string(v));
                    corners_ok = false;
                    break;
                }
    }
    // Distinct edges of N with their multiplicity; the new ones must not exist (rule 3).
    for (size_t i = 0; i < n_edges.size();) {
        size_t j = i;
        while (j < n_edges.size() && n_edges[j] == n_edges[i]) ++j;
        const uint64_t k = n_edges[i];
        const int64_t count = static_cast<int64_t>(j - i);
        const bool link_edge = std::binary_search(link_edges.begin(), link_edges.end(), k);
        if (!link_edge) {
            if (mesh_.has_edge(edge_key_first(k), edge_key_second(k)))
                c.local.push_back("new edge " + edge_text(k) + " is already an edge of the surface (local condition "
                                  "of Conjecture 2.1)");
            else
                ++c.new_edges;
        }
        // Plain boundary rule (a disk's; half-disks are checked per polygon below).
        if (c.kind != StepCheck::Kind::HalfDisks) {
            if (link_edge && count != 1)
                c.boundary.push_back("link edge " + edge_text(k) + " is in " + std::to_string(count) +
                                     " recorded triangles, expected 1");
            else if (!link_edge && count != 2)
                c.boundary.push_back("new edge " + edge_text(k) + " is in " + std::to_string(count) +
                                     " recorded triangles, expected 2 (the triangles do not close up)");
        }
        i = j;
    }
    if (c.kind != StepCheck::Kind::HalfDisks)
        for (uint64_t k : link_edges)
            if (!std::binary_search(n_edges.begin(), n_edges.end(), k))
                c.boundary.push_back("link edge " + edge_text(k) + " of " + std::to_string(v) +
                                     " is in no recorded triangle (the hole is not filled)");
    for (size_t i = 1; i < link_edges.size(); ++i)
        if (link_edges[i] == link_edges[i - 1])
            c.boundary.push_back("link edge " + edge_text(link_edges[i]) + " bounds two triangles of the star");
    return corners_ok;
}

// Rule 2 per polygon (the star's disk, or each half-disk): every recorded triangle lies
// in one polygon and has its patch.
void Replayer::check_polygons(int64_t s, StepCheck& c) {
    const int64_t first = steps_.triangle_offsets[s], last = steps_.triangle_offsets[s + 1];
    auto new_tri = [&](int64_t j) { return steps_.triangles[j]; };

    // Rule 2 per polygon: sides once, other edges twice, n - 2 triangles, one fan per corner.
    const int32_t np = static_cast<int32_t>(c.polygons.size());
    for (int32_t i = 0; i < np; ++i)
        for (int32_t x : c.polygons[i]) {
            stamp_[x] = s;
            owner_[x] = (x == c.a || x == c.b) ? -2 : i;
        }
    std::vector<std::vector<int64_t>> members(np);
    for (int64_t j = first; j < last; ++j) {
        int32_t poly = -1;
        bool mixed = false;
        for (int32_t x : new_tri(j)) {
            const int32_t o = stamp_[x] == s ? owner_[x] : -3;
            if (o == -2) continue;
            if (o < 0 || (poly >= 0 && o != poly)) mixed = true;
            poly = o;
        }
        if (mixed || poly < 0) {
            c.boundary.push_back("recorded triangle " + std::to_string(j) + " " + tri_text(new_tri(j)) +
                                 " joins two half-disks of the star");
            continue;
        }
        members[poly].push_back(j);
        if (steps_.triangle_patches[j] != c.polygon_patch[poly])
            c.structure.push_back("recorded triangle " + std::to_string(j) + " " + tri_text(new_tri(j)) +
                                  " has patch " + std::to_string(steps_.triangle_patches[j]) + ", but the " +
                                  (np == 1 && c.kind == StepCheck::Kind::Disk ? "star" : "half-disk") +
                                  " it replaces has patch " + std::to_string(c.polygon_patch[poly]));
    }
    if (!c.boundary.empty()) return;
    for (int32_t i = 0; i < np; ++i) check_polygon(i, members[i], c);
}

// Rule 2 for polygon i filled by the recorded triangles `members`: sides once, other
// edges twice, n - 2 triangles, one fan around every corner.
void Replayer::check_polygon(int32_t i, const std::vector<int64_t>& members, StepCheck& c) {
    auto new_tri = [&](int64_t j) { return steps_.triangles[j]; };
    const auto& poly = c.polygons[i];
    const int32_t n = static_cast<int32_t>(poly.size());
    const std::string what = c.kind == StepCheck::Kind::Disk ? "the hole" : "half-disk " + std::to_string(i);
    if (n < 3) {
        c.local.push_back(what + " (" + std::to_string(c.a) + ", " + std::to_string(c.b) +
                          ") has a single triangle: its new feature edge is an edge of the surface already "
                          "(local condition of Conjecture 2.1)");
        return;
    }
    std::vector<uint64_t> sides, edges;
    for (int32_t k = 0; k < n; ++k) sides.push_back(edge_key(poly[k], poly[(k + 1) % n]));
    std::sort(sides.begin(), sides.end());
    for (int64_t j : members)
        for (int k = 0; k < 3; ++k) edges.push_back(edge_key(new_tri(j)[k], new_tri(j)[(k + 1) % 3]));
    std::sort(edges.begin(), edges.end());
    for (size_t e = 0; e < edges.size();) {
        size_t f = e;
        while (f < edges.size() && edges[f] == edges[e]) ++f;
        const bool side = std::binary_search(sides.begin(), sides.end(), edges[e]);
        if (side && f - e != 1)
            c.boundary.push_back(what + ": side " + edge_text(edges[e]) + " is in " + std::to_string(f - e) +
                                 " recorded triangles, expected 1");
        else if (!side && f - e != 2)
            c.boundary.push_back(what + ": edge " + edge_text(edges[e]) + " is in " + std::to_string(f - e) +
                                 " recorded triangles, expected 2 (the triangles do not close up)");
        e = f;
    }
    for (uint64_t k : sides)
        if (!std::binary_search(edges.begin(), edges.end(), k))
            c.boundary.push_back(what + ": side " + edge_text(k) + " is in no recorded triangle (the hole is not "
                                 "filled)");
    if (!c.boundary.empty()) return;
    if (static_cast<int32_t>(members.size()) != n - 2) {
        c.structure.push_back(what + " has " + std::to_string(n) + " corners but is filled with " +
                              std::to_string(members.size()) + " triangles, not " + std::to_string(n - 2) +
                              " (not a triangulated disk)");
        return;
    }
    // One fan around every corner, from the side to its successor to the side to its predecessor.
    for (int32_t k = 0; k < n; ++k) {
        const int32_t x = poly[k], succ = poly[(k + 1) % n], pred = poly[(k + n - 1) % n];
        std::vector<int64_t> at;
        for (int64_t j : members)
            if (contains(new_tri(j), x)) at.push_back(j);
        int64_t t = -1;
        for (int64_t j : at)
            if (contains(new_tri(j), succ)) t = j;
        int32_t from = succ;
        size_t visited = 0;
        while (t >= 0 && visited <= at.size()) {
            ++visited;
            const Tri& tri = new_tri(t);
            int32_t third = -1;
            for (int32_t y : tri)
                if (y != x && y != from) third = y;
            if (third == pred) break;
            int64_t next = -1;
            for (int64_t j : at)
                if (j != t && contains(new_tri(j), third)) next = j;
            t = next;
            from = third;
        }
        if (t < 0 || visited != at.size()) {
            c.structure.push_back(what + ": the recorded triangles around corner " + std::to_string(x) +
                                  " do not form one fan (not a triangulated disk)");
            break;
        }
    }
}

// The record is consistent in itself: offsets, sizes and vertex indices. The reader
// guarantees this; a BpmFile built in memory might not.
bool steps_record_well_formed(const SimplificationSteps& steps, int32_t nv0) {
    bool ok = static_cast<int64_t>(steps.triangle_offsets.size()) == steps.num_steps() + 1 &&
              steps.triangle_patches.size() == steps.triangles.size() && steps.triangle_offsets.front() == 0 &&
              steps.triangle_offsets.back() == steps.num_triangles();
    for (size_t i = 1; ok && i < steps.triangle_offsets.size(); ++i)
        ok = steps.triangle_offsets[i] >= steps.triangle_offsets[i - 1];
    for (int32_t v : steps.vertex) ok = ok && v >= 0 && v < nv0;
    for (const Tri& t : steps.triangles)
        for (int32_t v : t) ok = ok && v >= 0 && v < nv0;
    return ok;
}

// What the replay did.
struct ReplayTally {
    int64_t replayed = 0, disks = 0, half_disks = 0, full_checks = 0;
    bool failed = false;
};

// The topology agrees with S0 after `good` steps and differs after `bad` (its differences
// `at_bad`): bisects down to the step that changed it, leaving good + 1 == bad.
void bisect_topology_change(const Parametrization& p, const SimplificationSteps& steps,
                            const SurfaceTopology& original, const std::vector<int32_t>& identity,
                            const CheckOptions& options, int64_t& good, int64_t& bad,
                            std::vector<std::string>& at_bad, ReplayTally& tally) {
    while (bad - good > 1) {
        const int64_t mid = good + (bad - good) / 2;
        Replayer again(p.original, original.triangle_component, steps);
        for (int64_t i = 0; i < mid; ++i) again.apply(i);
        ++tally.full_checks;
        auto d = topology_differences(original, again.mesh(), p.original, identity, options.max_problems);
        if (d.empty()) {
            good = mid;
        } else {
            bad = mid;
            at_bad = std::move(d);
        }
    }
}

// Replays the steps in order on `replay`, checking each against the rules and the Euler
// characteristic exactly, and the whole topology every `interval` steps. Stops at the
// first failure, which it reports into `r`.
ReplayTally replay_steps(const Parametrization& p, const SimplificationSteps& steps, const SurfaceTopology& original,
                         Replayer& replay, const CheckOptions& options, const Context& context, CheckResult& r) {
    const int64_t ns = steps.num_steps();
    const int32_t nv0 = p.original.num_vertices();
    std::vector<int32_t> identity(static_cast<size_t>(nv0));
    std::iota(identity.begin(), identity.end(), 0);
    const int64_t interval =
        options.replay_check_interval > 0 ? options.replay_check_interval : std::max<int64_t>(1, (ns + 3) / 4);
    const int64_t chi0 = original.euler_characteristic;
    int64_t chi = chi0;
    int64_t last_good = 0;
    ReplayTally tally;
    StepCheck c;
    auto step_ids = [&](int64_t s) { return Ids{{"step", s}, {"original_vertex", steps.vertex[s]}}; };
    auto report_all = [&](int64_t s, const std::vector<std::string>& messages, const std::string& prefix) {
        for (const std::string& m : messages) r.add_problem({step_ids(s), prefix + m}, options.max_problems);
    };
    for (int64_t s = 0; s < ns; ++s) {
        if ((s & 1023) == 0) context.report(0.05 + 0.85 * double(s) / double(ns), "replay");
        replay.check(s, c);
        const bool hypothesis = c.boundary.empty() && c.local.empty();  // what Conjecture 2.1 assumes
        if (!hypothesis || !c.structure.empty()) {
            tally.failed = true;
            report_all(s, c.boundary, "");
            report_all(s, c.local, "");
            report_all(s, c.structure, "");
            if (hypothesis) {
                // The local condition holds but the removal is not a regular one: does it
                // change the topology? Apply it and recompute.
                replay.apply(s);
                ++tally.full_checks;
                const auto diff =
                    topology_differences(original, replay.mesh(), p.original, identity, options.max_problems);
                if (!diff.empty())
                    report_all(s, diff, "counterexample to Conjecture 2.1 (the local condition holds, but the topology "
                                        "changes): ");
            }
            return tally;
        }
        // Exact local update of V - E + T.
        const int64_t v_before = replay.mesh().referenced_vertices();
        const int64_t t_before = replay.mesh().alive_triangles();
        replay.apply(s);
        const int64_t dv = replay.mesh().referenced_vertices() - v_before;
        const int64_t dt = replay.mesh().alive_triangles() - t_before;
        chi += dv - (c.new_edges - c.spokes) + dt;
        ++tally.replayed;
        (c.kind == StepCheck::Kind::Disk ? tally.disks : tally.half_disks) += 1;
        if (chi != chi0) {
            tally.failed = true;
            r.add_problem({step_ids(s), "counterexample: every local check passed, but the Euler characteristic "
                                        "changed from " + std::to_string(chi0) + " to " + std::to_string(chi)},
                          options.max_problems);
            return tally;
        }
        if ((s + 1) % interval == 0 || s + 1 == ns) {
            ++tally.full_checks;
            auto diff = topology_differences(original, replay.mesh(), p.original, identity, options.max_problems);
            if (diff.empty()) {
                last_good = s + 1;
                continue;
            }
            int64_t good = last_good, bad = s + 1;
            bisect_topology_change(p, steps, original, identity, options, good, bad, diff, tally);
            tally.failed = true;
            report_all(bad - 1, diff,
                       "counterexample: every local check passed, but the topology changed with this step: ");
            return tally;
        }
    }
    return tally;
}

// The replayed connectivity must be the coarse surface (triangles as vertex sets, with
// patches). Reports every difference; returns how many triangles differ, and sets
// `triangles` to the replayed surface's count.
int64_t compare_with_coarse(const ReplayMesh& mesh, const Parametrization& p, const CheckOptions& options,
                            CheckResult& r, int64_t& triangles) {
    using Key = std::pair<std::array<int32_t, 3>, int32_t>;
    std::vector<std::pair<Key, int64_t>> replayed_tris, coarse_tris;
    {
        std::vector<int32_t> label;
        const Surface now = mesh.surface({}, label);
        for (size_t t = 0; t < now.triangles.size(); ++t) {
            Tri k = now.triangles[t];
            std::sort(k.begin(), k.end());
            replayed_tris.push_back({{k, now.patches[t]}, static_cast<int64_t>(t)});
        }
    }
    for (int32_t t = 0; t < p.coarse.num_triangles(); ++t) {
        Tri k;
        for (int j = 0; j < 3; ++j) k[j] = p.coarse_vertex_origin[p.coarse.triangles[t][j]];
        std::sort(k.begin(), k.end());
        coarse_tris.push_back({{k, p.coarse.patches[t]}, t});
    }
    std::sort(replayed_tris.begin(), replayed_tris.end());
    std::sort(coarse_tris.begin(), coarse_tris.end());
    int64_t mismatched = 0;
    size_t i = 0, j = 0;
    auto describe = [](const Key& k) { return tri_text(k.first) + " (patch " + std::to_string(k.second) + ")"; };
    while (i < replayed_tris.size() || j < coarse_tris.size()) {
        if (j == coarse_tris.size() || (i < replayed_tris.size() && replayed_tris[i].first < coarse_tris[j].first)) {
            ++mismatched;
            r.add_problem({{}, "the replayed surface has triangle " + describe(replayed_tris[i].first) +
                                   " (original vertex ids), which the coarse surface does not have"},
                          options.max_problems);
            ++i;
        } else if (i == replayed_tris.size() || coarse_tris[j].first < replayed_tris[i].first) {
            ++mismatched;
            r.add_problem({{{"coarse_triangle", coarse_tris[j].second}},
                           "coarse triangle " + describe(coarse_tris[j].first) +
                               " (original vertex ids) is not in the replayed surface"},
                          options.max_problems);
            ++j;
        } else {
            ++i;
            ++j;
        }
    }
    triangles = static_cast<int64_t>(replayed_tris.size());
    return mismatched;
}

}  // namespace

CheckResult check_replay(const BpmFile& file, const CheckOptions& options, const Context& context) {
    CheckResult r;
    r.name = "replay";
    const Parametrization& p = file.param;
    if (!file.simplification_steps) {
        // (What records them is the caller's to name: SimplifyOptions::record_steps, a
        // tool's flag.)
        detail::refuse(r, "the file has no recorded simplification steps");
        return r;
    }
    if (auto why = detail::parametrization_unsafe(p)) {
        detail::refuse(r, *why);
        return r;
    }
    const SimplificationSteps& steps = *file.simplification_steps;
    if (!steps_record_well_formed(steps, p.original.num_vertices())) {
        detail::refuse(r, "the record of simplification steps is malformed (sizes, offsets or vertex indices)");
        return r;
    }
    const int64_t ns = steps.num_steps();
    r.add_count("steps", ns);
    context.report(0.0, "replay: topology of S0");
    const SurfaceTopology original = compute_topology(p.original);
    Replayer replay(p.original, original.triangle_component, steps);
    const ReplayTally tally = replay_steps(p, steps, original, replay, options, context, r);
    r.add_count("replayed_steps", tally.replayed);
    r.add_count("disk_removals", tally.disks);
    r.add_count("feature_line_removals", tally.half_disks);
    r.add_count("full_topology_checks", tally.full_checks);
    if (tally.failed) {
        r.summary = "replay stopped at step " + std::to_string(tally.replayed) + " of " + std::to_string(ns);
        return r;
    }

    context.report(0.95, "replay: comparing with the coarse surface");
    int64_t triangles = 0;
    const int64_t mismatched = compare_with_coarse(replay.mesh(), p, options, r, triangles);
    r.add_count("mismatched_triangles", mismatched);
    r.add_count("triangles", triangles);
    r.summary = "replayed " + std::to_string(ns) + " removals (" + std::to_string(tally.disks) + " disks, " +
                std::to_string(tally.half_disks) + " on feature lines) with " + std::to_string(tally.full_checks) +
                " full topology checks" +
                (mismatched ? "; the result differs from the coarse surface in " + std::to_string(mismatched) +
                                  " triangles"
                            : "; the result is the coarse surface");
    context.report(1.0, "replay");
    return r;
}

}  // namespace bpm
