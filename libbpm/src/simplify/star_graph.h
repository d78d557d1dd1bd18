#pragma once
// The original surface inside one fan, as a graph in the plane of the fan's polar map
// (Krause & Sander §2.2.3-2.2.4): the nodes are the polygon corners, the original
// vertices and edge crossings on the polygon sides (fixed: they keep their place), and
// the original vertices strictly inside the fan (free: they move with the new
// triangulation); the segments are the runs of original edges through the fan,
// straightened between two nodes. Gathering it is the first step of transferring phi
// onto the new triangles (phi_transfer.h).

#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "bpm/geometry.h"
#include "simplify/coarse_mesh.h"
#include "simplify/embedding.h"
#include "simplify/star_fans.h"

namespace bpm::detail {

struct StarNode {
    Vec2 pos{};
    bool free = false;
    int32_t vertex = -1;     // original vertex, or -1 for a crossing
    int32_t edge = -1;       // crossing: original edge
    double sigma = 0.0;      // crossing: position on the original edge
    int32_t poly_edge = -1;  // fixed node on polygon side i (corner i -> corner i+1): the side
    double poly_t = 0.0;     // ... and its parameter along that side
    int32_t poly_corner = -1;
    // On a coarse edge (fixed nodes on sides, free nodes on diagonals): the stored,
    // canonical form, edge (lo, hi) at parameter s from lo.
    int32_t edge_lo = -1, edge_hi = -1;
    double edge_s = 0.0;
    // Location in the new triangulation (free nodes; set by locate_free_nodes).
    int32_t new_triangle = -1;  // inside this new triangle, at `bary`
    Vec3 bary{};
    int32_t diagonal = -1;      // or on this diagonal
};

// A run of an original edge through the fan, straightened between two nodes.
struct StraightSegment {
    int32_t a, b;         // star nodes
    int32_t edge;         // original edge
    int32_t first, last;  // indices into the edge's point sequence replaced by this run
    double sigma_a, sigma_b;
};

// A map from original vertex to star node that is cleared in O(1). The value and its
// stamp side by side: one cache line per (random) vertex, not two.
class VertexSlots {
public:
    void resize(size_t n) {
        if (slots_.size() < n) slots_.resize(n, Slot{-1, 0});
    }
    void clear() { ++current_; }
    int32_t get(int32_t v) const { return slots_[v].stamp == current_ ? slots_[v].value : -1; }
    void set(int32_t v, int32_t id) { slots_[v] = Slot{id, current_}; }

private:
    struct Slot {
        int32_t value;
        uint32_t stamp;
    };
    std::vector<Slot> slots_;
    uint32_t current_ = 1;
};

struct StarGraph {
    std::vector<StarNode> nodes;
    VertexSlots vertex_node;                                 // original vertex -> node (with fixed nodes only)
    std::vector<std::pair<int64_t, int32_t>> crossing_node;  // ((edge << 20) | index in its path, node)
    std::vector<std::vector<int32_t>> side_nodes;            // per polygon side: its fixed nodes (not corners)
    std::vector<int32_t> free_vertices;                      // the free nodes' original vertices, sorted
    // Per polygon corner i: what lies on the spoke v -- link[i] (Embedding::edge_content),
    // or null; found by gather_star_nodes() for gather_straight_segments(). Valid while
    // the embedding does not change.
    std::vector<const EdgeContentMap::Entry*> spoke_content;
    std::vector<StraightSegment> segments;

    // Empty, for an embedding of `num_original_vertices` vertices; keeps the buffers.
    void clear(size_t num_original_vertices) {
        nodes.clear();
        segments.clear();
        crossing_node.clear();
        vertex_node.resize(num_original_vertices);
        vertex_node.clear();
    }
    int32_t find_crossing_node(int64_t key) const {
        for (const auto& p : crossing_node)
            if (p.first == key) return p.second;
        return -1;
    }
};

// What a point of an original edge's path is, relative to one fan: outside it, on its
// polygon boundary (a fixed node), inside it (a free node), or a crossing of an interior
// spoke, which the straightened run drops.
enum class PointRole : uint8_t { Outside, Boundary, Free, Dropped };

// Buffers of gather_star_nodes() and gather_straight_segments() (see RemovalScratch in
// vertex_removal.cpp).
struct StarGraphScratch {
    std::vector<int32_t> sorted;      // sorted copies of edge contents
    std::vector<int32_t> candidates;  // original edges that may pass through the fan
    std::vector<PointRole> roles;     // of each point of an edge's path
    std::vector<int32_t> node_of;     // its node, or -1
    std::vector<const EdgeContentMap::Entry*> side_content;  // per polygon side: what lies on it, or null
};

// Adds the nodes of the fan of v, laid out at polygon corners q (polar_map.h), to a
// cleared `graph`, in this order: the corners; with `fixed_nodes`, the vertices and
// crossings on the link edges (sorted by vertex, and by edge then path order); for an
// open fan, v and the vertices on its two feature edges on the new edge (side n-1), at
// the parameters `new_edge_params` gives them (every one must be there); then the free
// nodes (the vertices inside the fan's triangles, on its interior spokes, and v of a
// closed fan), sorted, placed by their locations through the polar map. Only with
// `fixed_nodes` (the full plan, whose segments and checks look nodes up by vertex) is
// graph.vertex_node filled: a cheap plan saves those scattered writes. Fails with `why`
// when an original edge crosses a feature edge of the fan.
bool gather_star_nodes(const CoarseMesh& mesh, const Embedding& emb, int32_t v, const Fan& fan,
                       const std::vector<Vec2>& q, bool fixed_nodes,
                       const std::unordered_map<int32_t, double>* new_edge_params, StarGraph& graph,
                       StarGraphScratch& scratch, std::string& why);

// Adds the straightened runs of every original edge through the fan to `graph` (after
// gather_star_nodes() with fixed nodes): each maximal run of the edge's path inside the
// fan becomes one segment between the nodes at its ends, the crossings of interior
// spokes in between dropped. Fails with `why` when a run does not start and end at nodes.
bool gather_straight_segments(const Embedding& emb, int32_t v, const Fan& fan, StarGraph& graph,
                              StarGraphScratch& scratch, std::string& why);

}  // namespace bpm::detail
