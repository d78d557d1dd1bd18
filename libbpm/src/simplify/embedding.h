#pragma once
// The original surface S0 embedded in the coarse surface S while simplifying: the
// internal form of phi. It is the graph G of the paper (§2.2.3): every original
// vertex has a location on S, and every original edge is a path on S that is a
// straight segment inside each coarse triangle it passes, described by the points
// where it crosses coarse edges. The per-triangle pieces of the file format are
// derived from it (overlay.h).
//
// Locations never refer to triangle ids for points on edges or corners, so that a
// vertex removal only touches what lies strictly inside the removed star.

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "bpm/geometry.h"
#include "bpm/surface.h"
#include "core/edge_uses.h"
#include "core/const_range.h"
#include "simplify/coarse_mesh.h"
#include "simplify/edge_content_map.h"
#include "simplify/path_store.h"

namespace bpm::detail {

// A point of the coarse surface.
struct SurfacePoint {
    enum Kind : uint8_t { Corner, OnEdge, Inside };
    Kind kind = Corner;
    int32_t a = -1;  // Corner: the coarse vertex; OnEdge: smaller endpoint; Inside: coarse triangle
    int32_t b = -1;  // OnEdge: larger endpoint
    double s = 0.0;  // OnEdge: parameter from a to b, strictly inside (0,1)
    Vec3 bary{};     // Inside: barycentric coordinates in triangle a (corner order of the triangle)

    static SurfacePoint corner(int32_t v) { return {Corner, v, -1, 0.0, {}}; }
    static SurfacePoint on_edge(int32_t x, int32_t y, double s_from_x) {
        return x < y ? SurfacePoint{OnEdge, x, y, s_from_x, {}} : SurfacePoint{OnEdge, y, x, 1.0 - s_from_x, {}};
    }
    static SurfacePoint inside(int32_t t, const Vec3& b) { return {Inside, t, -1, 0.0, b}; }
};

// The original vertices located Inside each coarse triangle, as intrusive doubly linked
// lists: a head per triangle id and a link pair per original vertex (a vertex lies inside
// at most one triangle). Triangle ids only grow (several per input vertex by the end of a
// run), and a std::vector per id cost 24 bytes of header per id ever created plus a heap
// block per list that kept its capacity after the triangle died; this costs 4 bytes per
// id and 8 per vertex. The order of a list is unspecified: every reader sorts.
class InsideLists {
public:
    void reset(int32_t num_vertices, int32_t triangle_capacity) {
        head_.assign(size_t(triangle_capacity), -1);
        compacted_ = false;
        listed_.clear();
        listed_head_.clear();
        next_.assign(size_t(num_vertices), -1);
        prev_.assign(size_t(num_vertices), kUnlisted);
    }
    void ensure_triangle_capacity(int32_t n) {
        if (int32_t(head_.size()) < n) head_.resize(size_t(n), -1);
    }
    bool empty(int32_t t) const { return head(t) < 0; }
    // A cache hint for the head of t's list (not after shrink_to_fit()).
    void prefetch(int32_t t) const { __builtin_prefetch(head_.data() + t); }
    size_t count(int32_t t) const {
        size_t n = 0;
        for (int32_t v = head(t); v >= 0; v = next_[v]) ++n;
        return n;
    }
    // Appends the vertices inside triangle t to `out`.
    void append_to(int32_t t, std::vector<int32_t>& out) const {
        for (int32_t v = head(t); v >= 0; v = next_[v]) out.push_back(v);
    }
    // Appends the vertices inside each of the triangles `ts` to `out`, the lists walked
    // side by side (up to 16 at a time), in an unspecified order: each step of a list is
    // a scattered load that waits for the one before, and the lists of a star's triangles
    // are independent of one another, so their loads overlap.
    void append_all(const std::vector<int32_t>& ts, std::vector<int32_t>& out) const {
        constexpr size_t kWalks = 16;
        for (size_t first = 0; first < ts.size(); first += kWalks) {
            int32_t at[kWalks];
            const size_t count = std::min(kWalks, ts.size() - first);
            size_t live = 0;
            for (size_t i = 0; i < count; ++i)
                if ((at[live] = head(ts[first + i])) >= 0) ++live;
            while (live > 0) {
                for (size_t i = 0; i < live;) {
                    out.push_back(at[i]);
                    if ((at[i] = next_[size_t(at[i])]) >= 0)
                        ++i;
                    else
                        at[i] = at[--live];  // this list is done
                }
            }
        }
    }
    void add(int32_t t, int32_t v) {
        ensure_triangle_capacity(t + 1);
        next_[v] = head_[t];
        prev_[v] = -1;
        if (head_[t] >= 0) prev_[head_[t]] = v;
        head_[t] = v;
    }
    // Takes v out of the list of t; nothing if v is in no list.
    void remove(int32_t t, int32_t v) {
        if (prev_[v] == kUnlisted) return;
        if (prev_[v] >= 0)
            next_[prev_[v]] = next_[v];
        else
            head_[t] = next_[v];
        if (next_[v] >= 0) prev_[next_[v]] = prev_[v];
        next_[v] = -1;
        prev_[v] = kUnlisted;
    }
    // Keeps the heads of the non-empty lists only (sorted by triangle id), instead of one
    // per id ever made: called once the lists no longer change (before phi is exported;
    // add() and remove() may not be called after it).
    void shrink_to_fit() {
        if (compacted_) return;
        for (int32_t t = 0; t < int32_t(head_.size()); ++t)
            if (head_[t] >= 0) {
                listed_.push_back(t);
                listed_head_.push_back(head_[t]);
            }
        decltype(head_)().swap(head_);
        compacted_ = true;
    }

private:
    static constexpr int32_t kUnlisted = -2;  // prev_ of a vertex in no list (-1: first of its list)
    std::vector<int32_t> head_;               // per triangle id: a vertex inside it, or -1
    bool compacted_ = false;                  // after shrink_to_fit(): heads in listed_, listed_head_
    std::vector<int32_t> listed_, listed_head_;
    int32_t head(int32_t t) const {
        if (!compacted_) return t < int32_t(head_.size()) ? head_[t] : -1;
        const auto it = std::lower_bound(listed_.begin(), listed_.end(), t);
        return it != listed_.end() && *it == t ? listed_head_[size_t(it - listed_.begin())] : -1;
    }
    std::vector<int32_t> next_, prev_;        // per original vertex: its neighbours in its list
};

struct Embedding {
    const Surface* original = nullptr;
    std::vector<std::array<int32_t, 2>> edges;  // original edges (u < w), sorted
    std::vector<int32_t> vertex_edge_offsets;   // CSR: edges incident to each original vertex
    std::vector<int32_t> vertex_edges;
    std::vector<int32_t> smaller_vertex_edges;  // edges[smaller_vertex_edges[u] .. [u+1]) are (u, w > u)
    std::vector<int32_t> edge_triangle_offsets; // CSR: original triangles incident to each edge
    std::vector<int32_t> edge_triangles;

    std::vector<SurfacePoint> location;          // per original vertex
    // path, path_version and edge_content are the changing form, until freeze(); read
    // through crossings() and content() where the frozen form may be current (overlay).
    PathStore path;                              // per original edge, ordered from u to w
    std::vector<uint32_t> path_version;          // per original edge, bumped by set_path
    InsideLists inside;                          // per coarse triangle id: vertices located Inside
    EdgeContentMap edge_content;

    // Identity embedding: every original vertex at its own corner, no crossings.
    void init_identity(const Surface& original_surface, int32_t triangle_capacity);
    // The same with the surface's sides already grouped by edge (`uses` of
    // original_surface): the edges and their triangles are read off it in order.
    void init_identity(const Surface& original_surface, int32_t triangle_capacity, const EdgeUses& uses);

    // Id of original edge (u,w), or -1.
    int32_t find_edge(int32_t u, int32_t w) const;
    // Original triangle containing edges e and f (which share a vertex), or -1.
    int32_t triangle_of_edges(int32_t e, int32_t f) const;

    // The crossings of edge e, ordered from its smaller vertex to its larger (path[e]).
    ConstRange<Crossing> crossings(int32_t e) const {
        if (!frozen_) return path[size_t(e)];
        const Crossing* base = frozen_crossings_.data();
        return {base + frozen_path_offsets_[size_t(e)], base + frozen_path_offsets_[size_t(e) + 1]};
    }
    // What lies on coarse edge (a, b); false if nothing (no entry in edge_content).
    bool content(int32_t a, int32_t b, EdgeContentView& out) const;

    // Full point sequence of edge e from its smaller vertex to its larger: the two
    // locations with the crossings in between. sigma of the endpoints is 0 and 1.
    void path_points(int32_t e, std::vector<SurfacePoint>& points, std::vector<double>& sigmas) const;

    // Bookkeeping helpers used when a star is replaced.
    void set_location(int32_t vertex, const SurfacePoint& p);   // maintains inside / edge_content lists
    void clear_location(int32_t vertex);                          // removes from lists (location kept)
    void set_path(int32_t e, const std::vector<Crossing>& crossings);  // maintains edge_content lists
    void ensure_triangle_capacity(int32_t n) { inside.ensure_triangle_capacity(n); }
    // Once the embedding no longer changes (before phi is exported): stores the paths and
    // the edge contents in a few flat arrays and frees the changing form (path,
    // path_version, edge_content; the inside lists keep only their non-empty heads). At
    // the end of a run the changing form was most of the embedding, alive beside phi
    // while it is exported (208k-triangle input to 10k vertices, when paths and contents
    // were vectors: 7.5 MB of path headers for 3.4 MB of crossings and 4.8 MB of hash
    // table and entries for 0.1 MB of ids; their block pools, path_store.h and
    // edge_content_map.h, hold less, but the flat form is still the smallest and frees
    // the pools' free blocks and the table's room). Read-only after it: only
    // crossings(), content(), path_points() and the inside lists read the moved parts.
    void freeze();
    bool frozen() const { return frozen_; }

private:
    bool frozen_ = false;
    std::vector<uint32_t> frozen_path_offsets_;  // per edge: its crossings are [e], [e + 1]
    std::vector<Crossing> frozen_crossings_;
    std::vector<uint64_t> frozen_keys_;          // edge keys with content, increasing
    std::vector<uint32_t> frozen_content_offsets_;  // per key i: vertices [2i, 2i + 1), crossing edges [2i + 1, 2i + 2)
    std::vector<int32_t> frozen_ids_;
    std::vector<uint8_t> kept_crossings_;  // of set_path: per new crossing, whether an old one matched it
};

}  // namespace bpm::detail
