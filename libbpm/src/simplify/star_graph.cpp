#include "simplify/star_graph.h"

#include <algorithm>
#include <cmath>

namespace bpm::detail {

namespace {

// The fan of v with its polygon and the graph being gathered: what the steps below share.
struct Gatherer {
    const CoarseMesh* mesh_;         // null for gather_segments (it reads only the graph)
    const Embedding& emb_;
    int32_t v_;
    const Fan* fan_;
    int32_t n_;                      // polygon corners
    const std::vector<Vec2>& q_;     // polygon corners in the plane
    bool validate_;                  // gather the fixed nodes on the link edges too
    const std::unordered_map<int32_t, double>* new_edge_params_;
    StarGraph& graph_;
    StarGraphScratch& scratch_;

    Vec2 corner_pos(int32_t vertex) const {
        if (vertex == v_) return {0.0, 0.0};
        for (int32_t i = 0; i < n_; ++i)
            if (fan_->link[i] == vertex) return q_[i];
        return {std::nan(""), std::nan("")};
    }
    // Does fixed node s lie on (the closure of) fan triangle i = (v, l_i, l_i+1)?
    bool in_fan_triangle(const StarNode& s, int32_t i) const {
        const int32_t next = mod(i + 1, n_);
        if (s.poly_corner >= 0) return s.poly_corner == i || s.poly_corner == next;
        if (!fan_->closed && s.poly_edge == n_ - 1) {
            // On the new edge: v (x = 0) is in every triangle, the rest on spoke 0 or n-1.
            if (s.pos[0] == 0.0) return true;
            return s.pos[0] > 0.0 ? i == 0 : i == n_ - 2;
        }
        return s.poly_edge == i;
    }
    int32_t add_node(const StarNode& node) {
        graph_.nodes.push_back(node);
        return static_cast<int32_t>(graph_.nodes.size()) - 1;
    }
    PointRole role(const SurfacePoint& p, bool endpoint, int32_t edge, int32_t index, int32_t& node) const;
    bool gather_nodes(std::string& why);
    bool gather_segments(std::string& why);
};

PointRole Gatherer::role(const SurfacePoint& p, bool endpoint, int32_t edge, int32_t index, int32_t& node) const {
    node = -1;
    auto lookup_vertex = [&](int32_t vertex) {
        return graph_.vertex_node.get(vertex);
    };
    switch (p.kind) {
        case SurfacePoint::Corner: {
            if (p.a == v_) {
                node = lookup_vertex(v_);
                return fan_->closed ? PointRole::Free : PointRole::Boundary;
            }
            if (fan_->corner_index(p.a) >= 0) {
                node = lookup_vertex(p.a);
                return PointRole::Boundary;
            }
            return PointRole::Outside;
        }
        case SurfacePoint::OnEdge: {
            const int32_t spoke = fan_->spoke_index(v_, p.a, p.b);
            if (spoke >= 0) {
                if (fan_->is_interior_spoke(spoke)) {
                    if (!endpoint) return PointRole::Dropped;
                    node = lookup_vertex(emb_.edges[edge][index == 0 ? 0 : 1]);
                    return PointRole::Free;
                }
                if (!endpoint) return PointRole::Dropped;  // a crossing on a feature edge: invalid, caught later
                node = lookup_vertex(emb_.edges[edge][index == 0 ? 0 : 1]);
                return PointRole::Boundary;
            }
            if (fan_->link_side(p.a, p.b) >= 0) {
                if (endpoint) {
                    node = lookup_vertex(emb_.edges[edge][index == 0 ? 0 : 1]);
                } else {
                    node = graph_.find_crossing_node((int64_t(edge) << 20) | (index - 1));
                }
                return PointRole::Boundary;
            }
            return PointRole::Outside;
        }
        case SurfacePoint::Inside:
            if (fan_->triangle_index(p.a) >= 0) {
                node = lookup_vertex(emb_.edges[edge][index == 0 ? 0 : 1]);
                return PointRole::Free;
            }
            return PointRole::Outside;
    }
    return PointRole::Outside;
}

bool Gatherer::gather_nodes(std::string& why) {
    const int32_t sides = n_;  // open fans: side n-1 is the new edge (end -> start)
    if (graph_.side_nodes.size() < size_t(sides)) graph_.side_nodes.resize(sides);
    for (auto& list : graph_.side_nodes) list.clear();
    // What lies on the spokes and (full plans) on the link edges, looked up all at once
    // before it is read: each lookup ends in a scattered entry, and asked for together
    // (prefetch) those misses overlap instead of following one another.
    auto& spoke = graph_.spoke_content;
    auto& side = scratch_.side_content;
    spoke.resize(size_t(n_));
    side.resize(size_t(n_));
    auto look_up = [&](int32_t a, int32_t b) {
        const EdgeContentMap::Entry* c = emb_.edge_content.find(edge_key(a, b));
        if (c) {
            __builtin_prefetch(c);
            __builtin_prefetch(reinterpret_cast<const char*>(c) + sizeof(*c) - 1);
        }
        return c;
    };
    for (int32_t i = 0; i < n_; ++i) spoke[size_t(i)] = look_up(v_, fan_->link[i]);
    for (int32_t i = 0; validate_ && i < (fan_->closed ? n_ : n_ - 1); ++i)
        side[size_t(i)] = look_up(fan_->link[i], fan_->link[mod(i + 1, n_)]);
    // Polygon corners.
    for (int32_t i = 0; i < n_; ++i) {
        StarNode c;
        c.pos = q_[i];
        c.vertex = fan_->link[i];
        c.poly_corner = i;
        const int32_t id = add_node(c);
        if (validate_) graph_.vertex_node.set(c.vertex, id);
    }
    // Fixed nodes on the link edges (only the full plan needs them: their place and
    // deviation do not change).
    for (int32_t i = 0; validate_ && i < (fan_->closed ? n_ : n_ - 1); ++i) {
        const int32_t a = fan_->link[i], b = fan_->link[mod(i + 1, n_)];
        if (!side[size_t(i)]) continue;
        const EdgeContentView content = emb_.edge_content.view(*side[size_t(i)]);
        auto t_of = [&](double s) { return a < b ? s : 1.0 - s; };  // from q_i to q_i+1
        auto& vs = scratch_.sorted;
        vs.assign(content.vertices.begin(), content.vertices.end());
        std::sort(vs.begin(), vs.end());
        for (int32_t u : vs) __builtin_prefetch(&emb_.location[size_t(u)]);
        for (int32_t u : vs) {
            StarNode s;
            s.vertex = u;
            s.poly_edge = i;
            s.poly_t = t_of(emb_.location[u].s);
            s.edge_lo = std::min(a, b);
            s.edge_hi = std::max(a, b);
            s.edge_s = emb_.location[u].s;
            s.pos = (1.0 - s.poly_t) * q_[i] + s.poly_t * q_[mod(i + 1, n_)];
            const int32_t id = add_node(s);
            graph_.vertex_node.set(u, id);
            graph_.side_nodes[i].push_back(id);
        }
        auto& es = scratch_.sorted;
        es.assign(content.crossing_edges.begin(), content.crossing_edges.end());
        std::sort(es.begin(), es.end());
        es.erase(std::unique(es.begin(), es.end()), es.end());
        for (int32_t e : es) emb_.path.prefetch_slot(size_t(e));
        const int64_t key = edge_key(a, b);
        for (size_t k = 0; k < es.size(); ++k) {
            const int32_t e = es[k];
            // The next path's crossings, while this one is scanned (its header is here).
            if (k + 1 < es.size()) emb_.path.prefetch_crossings(size_t(es[k + 1]));
            const ConstRange<Crossing> path = emb_.path[size_t(e)];
            for (int32_t j = 0; j < int32_t(path.size()); ++j) {
                if (edge_key(path[j].a, path[j].b) != uint64_t(key)) continue;
                StarNode s;
                s.edge = e;
                s.sigma = path[j].sigma;
                s.poly_edge = i;
                s.poly_t = t_of(path[j].s);
                s.edge_lo = std::min(a, b);
                s.edge_hi = std::max(a, b);
                s.edge_s = path[j].s;
                s.pos = (1.0 - s.poly_t) * q_[i] + s.poly_t * q_[mod(i + 1, n_)];
                const int32_t id = add_node(s);
                graph_.crossing_node.push_back({(int64_t(e) << 20) | j, id});
                graph_.side_nodes[i].push_back(id);
            }
        }
    }
    // v and the vertices on the two feature edges lie on the new edge of an open fan.
    if (!fan_->closed) {
        const int32_t side = n_ - 1;  // from corner n-1 (x < 0) to corner 0 (x > 0)
        const double x0 = q_[n_ - 1][0], x1 = q_[0][0];
        auto add_on_new_edge = [&](int32_t u, double x) {
            StarNode s;
            s.vertex = u;
            s.poly_edge = side;
            s.poly_t = (x - x0) / (x1 - x0);
            s.pos = {x, 0.0};
            auto it = new_edge_params_->find(u);
            if (it == new_edge_params_->end()) return false;
            s.edge_lo = std::min(fan_->link.front(), fan_->link.back());
            s.edge_hi = std::max(fan_->link.front(), fan_->link.back());
            s.edge_s = it->second;
            const int32_t id = add_node(s);
            if (validate_) graph_.vertex_node.set(u, id);
            graph_.side_nodes[side].push_back(id);
            return true;
        };
        if (!add_on_new_edge(v_, 0.0)) {
            why = "internal: vertex on the new feature edge without parameter";
            return false;
        }
        for (int32_t end : {0, n_ - 1}) {
            const int32_t w = fan_->link[end];
            if (!spoke[size_t(end)]) continue;
            const EdgeContentView content = emb_.edge_content.view(*spoke[size_t(end)]);
            if (!content.crossing_edges.empty()) {
                why = "an original edge crosses a feature line";
                return false;
            }
            auto& vs = scratch_.sorted;
            vs.assign(content.vertices.begin(), content.vertices.end());
            std::sort(vs.begin(), vs.end());
            for (int32_t u : vs) {
                const double from_v = v_ < w ? emb_.location[u].s : 1.0 - emb_.location[u].s;
                if (!add_on_new_edge(u, from_v * q_[end][0])) {
                    why = "internal: vertex on the new feature edge without parameter";
                    return false;
                }
            }
        }
    }
    // Free nodes: vertices inside the fan's triangles, on its interior spokes, and v of a disk.
    auto& free_vertices = graph_.free_vertices;
    free_vertices.clear();
    emb_.inside.append_all(fan_->triangles, free_vertices);
    for (int32_t i = 0; i < n_; ++i) {
        if (!fan_->is_interior_spoke(i) || !spoke[size_t(i)]) continue;
        const ConstRange<int32_t> vs = emb_.edge_content.view(*spoke[size_t(i)]).vertices;
        free_vertices.insert(free_vertices.end(), vs.begin(), vs.end());
    }
    if (fan_->closed) free_vertices.push_back(v_);
    // Their locations and positions (which the plan's deviation reads next) are
    // scattered: asked for together, before the sort.
    const Vec3* positions = mesh_->positions().data();
    for (int32_t u : free_vertices) {
        __builtin_prefetch(&emb_.location[size_t(u)]);
        __builtin_prefetch(positions + u);
    }
    std::sort(free_vertices.begin(), free_vertices.end());
    for (int32_t u : free_vertices) {
        StarNode s;
        s.free = true;
        s.vertex = u;
        const SurfacePoint& p = emb_.location[u];
        if (p.kind == SurfacePoint::Inside) {
            const Tri& c = mesh_->triangle(p.a);
            s.pos = p.bary[0] * corner_pos(c[0]) + p.bary[1] * corner_pos(c[1]) + p.bary[2] * corner_pos(c[2]);
        } else if (p.kind == SurfacePoint::OnEdge) {
            s.pos = (1.0 - p.s) * corner_pos(p.a) + p.s * corner_pos(p.b);
        } else {
            s.pos = corner_pos(p.a);
        }
        const int32_t id = add_node(s);
        if (validate_) graph_.vertex_node.set(u, id);
    }

    return true;
}

bool Gatherer::gather_segments(std::string& why) {
    // Original edges that may pass through the fan, and their straightened runs.
    auto& candidates = scratch_.candidates;
    candidates.clear();
    auto add_incident = [&](int32_t u) {
        for (int32_t i = emb_.vertex_edge_offsets[u]; i < emb_.vertex_edge_offsets[u + 1]; ++i)
            candidates.push_back(emb_.vertex_edges[i]);
    };
    for (int32_t u : graph_.free_vertices) add_incident(u);
    add_incident(v_);
    if (!fan_->closed)
        for (int32_t id : graph_.side_nodes[n_ - 1])
            if (graph_.nodes[id].vertex >= 0) add_incident(graph_.nodes[id].vertex);
    for (int32_t i = 0; i < n_; ++i) {
        if (!fan_->is_interior_spoke(i) || !graph_.spoke_content[size_t(i)]) continue;
        const ConstRange<int32_t> es = emb_.edge_content.view(*graph_.spoke_content[size_t(i)]).crossing_edges;
        candidates.insert(candidates.end(), es.begin(), es.end());
    }
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    // Their paths and ends are scattered: asked for together, then each edge's crossings
    // and end locations one edge ahead.
    for (int32_t e : candidates) {
        emb_.path.prefetch_slot(size_t(e));
        __builtin_prefetch(&emb_.edges[size_t(e)]);
    }

    auto& roles = scratch_.roles;
    auto& node_of = scratch_.node_of;
    for (size_t ci = 0; ci < candidates.size(); ++ci) {
        const int32_t e = candidates[ci];
        if (ci + 1 < candidates.size()) {
            const int32_t next = candidates[ci + 1];
            emb_.path.prefetch_crossings(size_t(next));
            __builtin_prefetch(&emb_.location[size_t(emb_.edges[size_t(next)][0])]);
            __builtin_prefetch(&emb_.location[size_t(emb_.edges[size_t(next)][1])]);
        }
        // The point sequence of Embedding::path_points, read in place: the two
        // locations with the crossings in between.
        const ConstRange<Crossing> path = emb_.path[size_t(e)];
        const int32_t last = static_cast<int32_t>(path.size()) + 1;
        auto sigma_at = [&](int32_t j) { return j == 0 ? 0.0 : (j == last ? 1.0 : path[j - 1].sigma); };
        roles.resize(last + 1);
        node_of.resize(last + 1);
        roles[0] = role(emb_.location[emb_.edges[e][0]], true, e, 0, node_of[0]);
        for (int32_t j = 1; j < last; ++j) {
            const Crossing& c = path[j - 1];
            roles[j] = role(SurfacePoint{SurfacePoint::OnEdge, c.a, c.b, c.s, {}}, false, e, j, node_of[j]);
        }
        roles[last] = role(emb_.location[emb_.edges[e][1]], true, e, last, node_of[last]);
        // Is segment (j, j+1) inside the fan?
        auto inside_fan = [&](int32_t j) {
            const PointRole r0 = roles[j], r1 = roles[j + 1];
            if (r0 == PointRole::Outside || r1 == PointRole::Outside) return false;
            if (r0 != PointRole::Boundary || r1 != PointRole::Boundary) return true;
            // Both on the polygon boundary: inside only if they are in one fan triangle
            // without sharing a side of the polygon.
            if (node_of[j] < 0 || node_of[j + 1] < 0) return true;  // reported below
            const StarNode& a = graph_.nodes[node_of[j]];
            const StarNode& b = graph_.nodes[node_of[j + 1]];
            auto on_side = [&](const StarNode& s, int32_t side) {
                return s.poly_edge == side ||
                       (s.poly_corner >= 0 && (s.poly_corner == side || mod(s.poly_corner - 1, n_) == side));
            };
            for (int32_t side = 0; side < n_; ++side)
                if (on_side(a, side) && on_side(b, side)) return false;
            const int32_t ntri = static_cast<int32_t>(fan_->triangles.size());
            for (int32_t i = 0; i < ntri; ++i)
                if (in_fan_triangle(a, i) && in_fan_triangle(b, i)) return true;
            return false;
        };
        int32_t j = 0;
        while (j < last) {
            if (!inside_fan(j)) {
                ++j;
                continue;
            }
            int32_t k = j + 1;
            while (k < last && roles[k] == PointRole::Dropped) ++k;
            if (roles[j] == PointRole::Dropped || roles[k] == PointRole::Dropped || node_of[j] < 0 || node_of[k] < 0) {
                why = "an original edge runs along a removed edge in an unexpected way";
                return false;
            }
            graph_.segments.push_back({node_of[j], node_of[k], e, j, k, sigma_at(j), sigma_at(k)});
            j = k;
        }
    }
    return true;
}

}  // namespace

bool gather_star_nodes(const CoarseMesh& mesh, const Embedding& emb, int32_t v, const Fan& fan,
                       const std::vector<Vec2>& q, bool fixed_nodes,
                       const std::unordered_map<int32_t, double>* new_edge_params, StarGraph& graph,
                       StarGraphScratch& scratch, std::string& why) {
    Gatherer g{&mesh, emb, v, &fan, fan.corners(), q, fixed_nodes, new_edge_params, graph, scratch};
    return g.gather_nodes(why);
}

bool gather_straight_segments(const Embedding& emb, int32_t v, const Fan& fan, StarGraph& graph,
                              StarGraphScratch& scratch, std::string& why) {
    // The segments join gathered nodes: neither the mesh nor the polygon is read again.
    static const std::vector<Vec2> kNoCorners;
    Gatherer g{nullptr, emb, v, &fan, fan.corners(), kNoCorners, true, nullptr, graph, scratch};
    return g.gather_segments(why);
}

}  // namespace bpm::detail
