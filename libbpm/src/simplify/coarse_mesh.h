#pragma once
// The coarse surface while it is being simplified: a non-manifold triangle mesh over
// the original vertex ids (point removal never creates vertices), with incident
// triangle lists per vertex and the set of feature edges that must survive as
// feature lines (paper §2.4). Internal to libbpm.

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "bpm/geometry.h"
#include "bpm/surface.h"
#include "core/crease_chains.h"
#include "core/edge_key.h"
#include "core/edge_uses.h"
#include "simplify/vertex_triangle_lists.h"

namespace bpm::detail {

class CoarseMesh {
public:
    // Starts as a copy of `original`. Triangles are re-oriented consistently within
    // each sheet (connected through edges with exactly two triangles) so that new
    // triangles can inherit a well-defined orientation; `flipped(t)` tells which
    // initial triangles were reversed relative to the original.
    explicit CoarseMesh(const Surface& original);
    // The same with the original's sides already grouped by edge (`uses` of `original`):
    // the orientation walk reads its neighbours off them.
    CoarseMesh(const Surface& original, const EdgeUses& uses);

    const std::vector<Vec3>& positions() const { return *positions_; }
    const Tri& triangle(int32_t t) const { return triangles_[slot(t)]; }
    int32_t patch(int32_t t) const { return patches_.empty() ? uniform_patch_ : patches_[slot(t)]; }
    // Whether every triangle has the same patch (new triangles inherit their patches:
    // decided by the input).
    bool one_patch() const { return patches_.empty(); }
    // Circumradius / inradius of triangle t (bpm::aspect_ratio of its corners in stored
    // order), computed once when the triangle is made: the planners ask for it every time
    // they plan a star, and used to cache it per planner (a double per triangle id each).
    // Not available after release_aspects().
    double aspect(int32_t t) const { return aspects_[slot(t)]; }
    void release_aspects() {
        decltype(aspects_)().swap(aspects_);
        keep_aspects_ = false;
    }
    bool alive(int32_t t) const { return compacted_ ? std::binary_search(kept_.begin(), kept_.end(), t) : alive_[t] != 0; }
    // The alive triangles' ids, increasing.
    void alive_triangles(std::vector<int32_t>& out) const;
    bool flipped_initially(int32_t t) const { return t < int32_t(initially_flipped_.size()) && initially_flipped_[t]; }
    int32_t triangle_capacity() const { return compacted_ ? capacity_ : static_cast<int32_t>(triangles_.size()); }
    int32_t num_alive_triangles() const { return num_alive_; }
    int32_t num_vertices_alive() const { return num_vertices_alive_; }
    bool vertex_alive(int32_t v) const { return !vertex_triangles_.empty(v); }

    // The alive triangles at v, sorted by id (has_edge() and find_triangle() rely on it).
    // Valid until the next add_triangle() or remove_triangle().
    VertexTriangleLists::View triangles_of(int32_t v) const { return vertex_triangles_.of(v); }

    // Alive triangles containing both a and b (all sheets of a non-manifold edge).
    void edge_triangles(int32_t a, int32_t b, std::vector<int32_t>& out) const;
    bool has_edge(int32_t a, int32_t b) const;
    // The alive triangle with exactly these three vertices, or -1.
    int32_t find_triangle(int32_t a, int32_t b, int32_t c) const;

    // Hard feature edges (boundary, non-manifold, patch border) must stay feature lines;
    // creases (sharp dihedral angle on one sheet) are soft: they are kept as lines while
    // their vertices are removed along them, but a crease may end or vanish when the
    // geometric error allows it (noisy scans have many short "creases").
    enum class Feature : uint8_t { None = 0, Hard = 1, Crease = 2 };
    Feature feature(int32_t a, int32_t b) const {
        if (feature_degree_[a] == 0 || feature_degree_[b] == 0) return Feature::None;  // the common case
        auto it = feature_edges_.find(edge_key(a, b));
        return it == feature_edges_.end() ? Feature::None : it->second;
    }
    bool is_feature_edge(int32_t a, int32_t b) const { return feature(a, b) != Feature::None; }
    // Whether any feature edge ends at v (else feature(v, x) is None for every x).
    bool on_feature_line(int32_t v) const { return feature_degree_[v] != 0; }

    // Cache hints, no effect on any result: ask for what triangles_of(v) and feature()
    // read at v, and for the corners of triangle t, ahead of a walk whose loads would
    // otherwise miss one after another (the ridge guard's walk over the triangles
    // around a star's link: about four misses per link vertex, in a chain). Not after
    // shrink_to_fit(). Unconditional: GCC drops a __builtin_prefetch under a branch.
    void prefetch_vertex(int32_t v) const {
        __builtin_prefetch(feature_degree_.data() + v);
        vertex_triangles_.prefetch(v);
    }
    void prefetch_triangle(int32_t t) const { __builtin_prefetch(triangles_.data() + t); }
    void prefetch_aspect(int32_t t) const { __builtin_prefetch(aspects_.data() + t); }
    void set_feature_edge(int32_t a, int32_t b, Feature kind);

    int32_t add_triangle(const Tri& corners, int32_t patch);
    // Room for triangle ids up to `ids` in the per-triangle arrays, allocated once:
    // ids only grow, and the arrays grew by doubling (208k-triangle input to 10k vertices:
    // ~600k ids in arrays for 832k). Beyond a reservation they grow by an eighth at a time.
    void reserve_triangles(size_t ids);
    // Keeps only the alive triangles (ids stay: triangle(t) finds t by binary search among
    // them) and stores the per-vertex triangle lists compactly: called once no triangle
    // will be added or removed any more, before phi is exported. The per-triangle arrays
    // had a slot per id ever made (208k-triangle input to 10k vertices: ~800k ids, 14 MB,
    // for 20k alive triangles); the removals are done. It also frees what only the
    // removals and the flips ask for: add_triangle(), remove_triangle(), has_edge(),
    // find_triangle(), feature(), corner() and flipped_initially() may not be called
    // after it (triangle(), triangles_of(), alive() and to_surface() may).
    void shrink_to_fit();
    void remove_triangle(int32_t t);
    // remove_triangle() of each, with the neighbour bits of their corners recounted once
    // at the end rather than after every triangle (a star: each corner is in two or more).
    void remove_triangles(const std::vector<int32_t>& ts);

    // Marks creases: a manifold edge that `rule` finds a crease (core/crease_chains.h:
    // normals more than the feature angle apart, or a long chain of shallower edges)
    // becomes a feature edge. Boundary edges, non-manifold edges and patch borders are
    // always feature edges.
    void mark_feature_edges(const CreaseRule& rule);
    // The feature angle alone, no chains (the internal tests' fans).
    void mark_feature_edges(double feature_angle_degrees) {
        CreaseRule rule;
        rule.feature_angle_degrees = feature_angle_degrees;
        mark_feature_edges(rule);
    }

    // Corners: vertices point removal never removes although they lie on creases
    // (Krause & Sander keep the vertices where feature lines of a non-manifold surface
    // meet or end, §2.4; this extends the rule to creases). A vertex is a corner where
    //   Junction   three or more feature edges meet, at least one of them a crease (the
    //              corners of a cube, where a crease meets a boundary or patch border);
    //   ConeEnd    a single crease ends at a sharp cone: the angle defect |2 pi - sum of
    //              the corner angles| of its star is at least 2 pi (1 - cos(feature
    //              angle / 2)), the defect of a circular cone whose opposite normals are
    //              the feature angle apart (the crease cannot fade out there smoothly).
    // A crease counts only if it runs as a line for at least `min_crease_length` (model
    // units) from the vertex: noise on scanned surfaces makes short creases that meet and
    // end everywhere (femur: 293 junctions of creases at most 1.8 % of the diagonal long;
    // fandisk's shortest real one is 3.2 %).
    // Ends and junctions of hard feature lines are kept by the classification of the
    // star anyway (never marked here). Call after mark_feature_edges(), before any removal. `keep` false marks
    // none but still counts them (corner_count()).
    enum class Corner : uint8_t { None = 0, Junction = 1, ConeEnd = 2 };
    void mark_corners(double feature_angle_degrees, double min_crease_length, bool keep);
    Corner corner(int32_t v) const { return corners_.empty() ? Corner::None : Corner(corners_[v]); }
    // From mark_corners(): vertices of each Corner kind (also when not kept), and the
    // ends and junctions of hard feature lines (one or three or more hard edges).
    int64_t corner_count(Corner kind) const { return corner_counts_[size_t(kind)]; }
    int64_t hard_feature_vertices() const { return hard_feature_vertices_; }

    // Alive triangles as a Surface (vertices compacted), with the original id of each
    // coarse vertex.
    Surface to_surface(std::vector<int32_t>& vertex_origin) const;

private:
    // Where triangle t is stored: t itself, or after shrink_to_fit() its rank among the
    // alive triangles (t must be alive then).
    size_t slot(int32_t t) const { return compacted_ ? compacted_slot(t) : size_t(t); }
    size_t compacted_slot(int32_t t) const {
        return size_t(std::lower_bound(kept_.begin(), kept_.end(), t) - kept_.begin());
    }
    bool compacted_ = false;
    std::vector<int32_t> kept_;  // after shrink_to_fit(): the alive ids, increasing
    int32_t capacity_ = 0;       // after shrink_to_fit(): the number of ids ever made
    const std::vector<Vec3>* positions_;
    std::vector<Tri> triangles_;
    std::vector<int32_t> patches_;  // per triangle; empty while every triangle has uniform_patch_
    int32_t uniform_patch_ = 0;
    void grow_triangle_arrays();  // before add_triangle() fills the capacity
    std::vector<uint8_t> alive_;
    std::vector<uint8_t> initially_flipped_;
    // Per original side (3 t + k, corners k and k + 1 as the input has them): the other
    // triangle of its edge where that edge has exactly two, else -1. Made for the
    // orientation walk and kept for mark_feature_edges, which frees it.
    std::vector<int32_t> across_;
    std::vector<double> aspects_;
    bool keep_aspects_ = true;
    VertexTriangleLists vertex_triangles_;
    // Per vertex, the bits (vertex_bit) of the corners of its alive triangles (itself too),
    // kept exact by add_triangle() and remove_triangle(): a missing bit proves that there
    // is no edge, from one load of a dense array, before has_edge() and find_triangle()
    // merge the scattered triangle lists (the planners ask for edges that mostly do not
    // exist, several times per plan).
    std::vector<uint64_t> neighbour_bits_;
    static uint64_t vertex_bit(int32_t v) { return uint64_t(1) << ((uint32_t(v) * 0x9E3779B9u) >> 26); }
    void set_neighbour_bits(int32_t v);
    std::unordered_map<uint64_t, Feature> feature_edges_;
    std::vector<int32_t> feature_degree_;  // feature edges at each vertex
    std::vector<uint8_t> corners_;         // Corner of each vertex (empty: none marked)
    int64_t corner_counts_[3] = {0, 0, 0};
    int64_t hard_feature_vertices_ = 0;
    void mark(int32_t a, int32_t b, Feature kind);
    int32_t num_alive_ = 0;
    int32_t num_vertices_alive_ = 0;
};

}  // namespace bpm::detail
