#include "simplify/overlay.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "bpm/predicates.h"

namespace bpm::detail {

namespace {

inline Vec2 param_point(const GraphNode& n) { return {n.bary[1], n.bary[2]}; }

// The local edges node n lies on (including their end corners), as bits 1 << k: corner
// c is on edges c and c - 1. Nodes share a local edge when their masks share a bit.
inline unsigned side_mask(const GraphNode& n) {
    unsigned mask = n.on_edge >= 0 ? 1u << n.on_edge : 0u;
    if (n.corner >= 0) mask |= (1u << n.corner) | (1u << ((n.corner + 2) % 3));
    return mask;
}

// Position of node n along local edge k, from corner k (0) to corner k+1 (1).
inline double along_edge(const GraphNode& n, int k) { return n.bary[(k + 1) % 3]; }

void set_reason(std::string* why, const char* text) {
    if (why) *why = text;
}

}  // namespace

Vec3 node_image(const GraphNode& n, const Embedding& embedding) {
    const auto& x = embedding.original->vertices;
    if (n.kind == NodeKind::EdgeCrossing) {
        const auto& e = embedding.edges[n.edge];
        return (1.0 - n.sigma) * x[e[0]] + n.sigma * x[e[1]];
    }
    return x[n.vertex];
}

bool image_barycentric(const GraphNode& n, const Embedding& embedding, int32_t original_triangle, Vec3& beta) {
    const Tri& t = embedding.original->triangles[original_triangle];
    beta = {0.0, 0.0, 0.0};
    if (n.kind == NodeKind::EdgeCrossing) {
        const auto& e = embedding.edges[n.edge];
        int iu = -1, iw = -1;
        for (int k = 0; k < 3; ++k) {
            if (t[k] == e[0]) iu = k;
            if (t[k] == e[1]) iw = k;
        }
        if (iu < 0 || iw < 0) return false;
        beta[iu] = 1.0 - n.sigma;
        beta[iw] = n.sigma;
        return true;
    }
    for (int k = 0; k < 3; ++k)
        if (t[k] == n.vertex) {
            beta[k] = 1.0;
            return true;
        }
    return false;
}

namespace {

// compute_faces() without shrinking `faces` at the end: the first `face_count` entries
// are the faces; the others keep their corner buffers for the next call.
bool faces_into(const TriangleGraph& graph, const Embedding& embedding, const std::vector<int8_t>& orientation_sign,
                std::vector<OverlayFace>& faces, size_t& face_count, std::string* why) {
    face_count = 0;
    const auto& nodes = graph.nodes;
    const int32_t n = static_cast<int32_t>(nodes.size());

    // Undirected edges: the triangle's sides split at the nodes on them, plus segments.
    struct Link {
        int32_t to;
        int32_t edge;   // original edge id along this link, or -1
        bool boundary_ccw;  // a side of the triangle traversed counter-clockwise
        bool boundary_cw;   // the same side traversed the other way (outer face)
        int8_t half = 0;    // sort key: half-plane of the direction, 0 for angles in [0, pi)
        Vec2 far{};         // sort key: parameter point of `to`
    };
    // Links of all nodes in CSR form (thread-local buffers: this runs for every candidate
    // removal, so it must not allocate). Per node, the links are in the order: sides 0,
    // 1, 2 split at their nodes, then the segments.
    static thread_local std::vector<Link> flat;
    static thread_local std::vector<int32_t> offset;
    static thread_local std::vector<uint8_t> used_flat;
    static thread_local std::vector<int32_t> chain[3];  // per side: its nodes from corner k to corner k+1
    // side_mask() of every node, computed once (the checks below ask it for every link
    // and every face corner).
    static thread_local std::vector<uint8_t> sides;
    sides.resize(n);
    for (int32_t i = 0; i < n; ++i) sides[i] = static_cast<uint8_t>(side_mask(nodes[i]));
    auto share_side = [&](int32_t a, int32_t b) { return (sides[a] & sides[b]) != 0; };
    auto three_on_one_side = [&](int32_t a, int32_t b, int32_t c) { return (sides[a] & sides[b] & sides[c]) != 0; };
    int32_t num_edges = 0;
    int32_t corner_node[3] = {-1, -1, -1};
    for (int32_t i = 0; i < n; ++i)
        if (nodes[i].corner >= 0) corner_node[nodes[i].corner] = i;
    for (int k = 0; k < 3; ++k)
        if (corner_node[k] < 0) {
            set_reason(why, "corner node missing");
            return false;
        }
    // The nodes on each side, in one pass over the nodes (in increasing index, the
    // order the sort below starts from).
    for (int k = 0; k < 3; ++k) {
        chain[k].clear();
        chain[k].push_back(corner_node[k]);
    }
    for (int32_t i = 0; i < n; ++i)
        if (nodes[i].on_edge >= 0) chain[nodes[i].on_edge].push_back(i);
    offset.assign(n + 1, 0);
    for (int k = 0; k < 3; ++k) {
        auto& side = chain[k];
        std::sort(side.begin() + 1, side.end(),
                  [&](int32_t a, int32_t b) { return along_edge(nodes[a], k) < along_edge(nodes[b], k); });
        for (size_t j = 1; j < side.size(); ++j) {
            const double x = along_edge(nodes[side[j]], k);
            if (!(x > 0.0 && x < 1.0) || (j > 1 && !(along_edge(nodes[side[j - 1]], k) < x))) {
                set_reason(why, "nodes on a coarse edge coincide or lie outside it");
                return false;
            }
        }
        side.push_back(corner_node[(k + 1) % 3]);
        for (size_t j = 0; j + 1 < side.size(); ++j) {
            ++offset[side[j] + 1];
            ++offset[side[j + 1] + 1];
            ++num_edges;
        }
    }
    for (const GraphSegment& s : graph.segments) {
        if (s.n0 == s.n1 || share_side(s.n0, s.n1)) {
            set_reason(why, "degenerate segment");
            return false;
        }
        ++offset[s.n0 + 1];
        ++offset[s.n1 + 1];
        ++num_edges;
    }
    for (int32_t i = 0; i < n; ++i) offset[i + 1] += offset[i];
    flat.resize(offset[n]);
    {
        static thread_local std::vector<int32_t> fill;
        fill.assign(offset.begin(), offset.end() - 1);
        for (const auto& side : chain)
            for (size_t j = 0; j + 1 < side.size(); ++j) {
                const int32_t a = side[j], b = side[j + 1];
                flat[fill[a]++] = {b, -1, true, false};
                flat[fill[b]++] = {a, -1, false, true};
            }
        for (const GraphSegment& s : graph.segments) {
            flat[fill[s.n0]++] = {s.n1, s.edge, false, false};
            flat[fill[s.n1]++] = {s.n0, s.edge, false, false};
        }
    }
    // links of node i: flat[offset[i] .. offset[i+1])
    auto begin_of = [&](int32_t i) { return flat.begin() + offset[i]; };
    auto end_of = [&](int32_t i) { return flat.begin() + offset[i + 1]; };

    // Sort the links of every node counter-clockwise, exactly: first by half-plane
    // (angle in [0, pi) or [pi, 2 pi)), then by orientation. Collinear overlapping links
    // from one node mean two edges on top of each other.
    for (int32_t i = 0; i < n; ++i) {
        const Vec2 p = param_point(nodes[i]);
        // The sort keys of each link, computed once instead of in every comparison.
        for (auto l = begin_of(i); l != end_of(i); ++l) {
            l->far = param_point(nodes[l->to]);
            l->half = (l->far[1] > p[1] || (l->far[1] == p[1] && l->far[0] > p[0])) ? 0 : 1;
        }
        std::sort(begin_of(i), end_of(i), [&](const Link& a, const Link& b) {
            if (a.half != b.half) return a.half < b.half;
            return orient2d(p, a.far, b.far) > 0;
        });
        const Link* li = &flat[offset[i]];
        const size_t m = static_cast<size_t>(offset[i + 1] - offset[i]);
        for (size_t j = 0; m > 1 && j < m; ++j) {
            const Link& la = li[j];
            const Link& lb = li[j + 1 == m ? 0 : j + 1];
            const int32_t a = la.to, b = lb.to;
            if (a == b) {
                set_reason(why, "duplicate edge");
                return false;
            }
            const Vec2 &pa = la.far, &pb = lb.far;  // param_point of a and b
            // The cheap tests first: the two links along a side of the coarse triangle are
            // collinear, and on a slanted side only the exact predicate can tell.
            if (dot(pa - p, pb - p) > 0 && !three_on_one_side(i, a, b) && orient2d(p, pa, pb) == 0) {
                set_reason(why, "overlapping edges");
                return false;
            }
        }
    }

    // Face traversal, face on the left: after arriving at w from u, leave along the
    // link that precedes (w->u) in counter-clockwise order.
    used_flat.assign(flat.size(), 0);
    auto position_of = [&](int32_t w, int32_t u) -> int32_t {
        for (int32_t j = offset[w]; j < offset[w + 1]; ++j)
            if (flat[j].to == u) return j - offset[w];
        return -1;
    };
    int32_t num_faces = 0;
    static thread_local std::vector<int32_t> corners, face_edges, face_vertices;
    for (int32_t start = 0; start < n; ++start) {
        for (size_t js = 0; js < size_t(offset[start + 1] - offset[start]); ++js) {
            if (used_flat[offset[start] + js]) continue;
            corners.clear();
            face_edges.clear();
            bool outer = false;
            int32_t u = start;
            size_t j = js;
            size_t guard = 0;
            while (!used_flat[offset[u] + j]) {
                used_flat[offset[u] + j] = 1;
                const Link& l = flat[offset[u] + j];
                corners.push_back(u);
                if (l.boundary_cw) outer = true;
                if (l.edge >= 0) face_edges.push_back(l.edge);
                const int32_t w = l.to;
                const int32_t back = position_of(w, u);
                const int32_t m = offset[w + 1] - offset[w];
                j = static_cast<size_t>(back == 0 ? m - 1 : back - 1);
                u = w;
                if (++guard > 4 * size_t(num_edges) + 8) {
                    set_reason(why, "face traversal did not close");
                    return false;
                }
            }
            if (u != start || j != js) {
                set_reason(why, "face traversal did not close");
                return false;
            }
            ++num_faces;
            if (outer) continue;
            const size_t m = corners.size();
            if (m < 3) {
                set_reason(why, "degenerate face");
                return false;
            }
            // Strictly convex and counter-clockwise, except for runs of nodes along one
            // side of the coarse triangle; winding once around: a polygon that only turns
            // left winds k times if its edge direction enters the upper half-plane k times.
            int windings = 0;
            for (size_t c = 0; c < m; ++c) {
                const int32_t ia = corners[c == 0 ? m - 1 : c - 1], ib = corners[c];
                const int32_t id = corners[c + 1 == m ? 0 : c + 1];
                const Vec2 pa = param_point(nodes[ia]), pb = param_point(nodes[ib]), pd = param_point(nodes[id]);
                if (!three_on_one_side(ia, ib, id) && orient2d(pa, pb, pd) <= 0) {
                    set_reason(why, "face not convex or flipped");
                    return false;
                }
                const Vec2 e0 = pb - pa, e1 = pd - pb;
                auto upper = [](const Vec2& e) { return e[1] > 0.0 || (e[1] == 0.0 && e[0] > 0.0); };
                if (!upper(e0) && upper(e1)) ++windings;
            }
            if (windings > 1) {
                set_reason(why, "face winds more than once");
                return false;
            }
            // Which original triangle: from the original edges and vertices on its boundary.
            face_vertices.clear();
            for (int32_t c : corners) {
                const GraphNode& g = nodes[c];
                if (g.kind == NodeKind::EdgeCrossing)
                    face_edges.push_back(g.edge);
                else
                    face_vertices.push_back(g.vertex);
            }
            std::sort(face_edges.begin(), face_edges.end());
            face_edges.erase(std::unique(face_edges.begin(), face_edges.end()), face_edges.end());
            int32_t tri = -1;
            if (face_edges.size() >= 2) {
                tri = embedding.triangle_of_edges(face_edges[0], face_edges[1]);
            } else {
                // Fewer than two known edges: the vertices on the boundary decide.
                static thread_local std::vector<int32_t> vs;
                vs.assign(face_vertices.begin(), face_vertices.end());
                if (face_edges.size() == 1) {
                    vs.push_back(embedding.edges[face_edges[0]][0]);
                    vs.push_back(embedding.edges[face_edges[0]][1]);
                }
                std::sort(vs.begin(), vs.end());
                vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
                if (vs.size() == 3) {
                    const int32_t e0 = embedding.find_edge(vs[0], vs[1]);
                    const int32_t e1 = embedding.find_edge(vs[0], vs[2]);
                    if (e0 >= 0 && e1 >= 0) tri = embedding.triangle_of_edges(e0, e1);
                }
            }
            if (tri < 0) {
                set_reason(why, "face does not identify one original triangle");
                return false;
            }
            // Every corner must lie on that triangle, and the image must have the
            // orientation the coarse surface has relative to it.
            // (The area terms are summed in the order c = 0 .. m-1 of
            // cross(image[c], image[c+1 mod m]).)
            Vec3 beta;
            double image_area2 = 0.0;
            Vec2 first_image{}, previous_image{};
            for (size_t c = 0; c < m; ++c) {
                if (!image_barycentric(nodes[corners[c]], embedding, tri, beta)) {
                    set_reason(why, "face corner not on its original triangle");
                    return false;
                }
                const Vec2 image{beta[1], beta[2]};
                if (c == 0)
                    first_image = image;
                else
                    image_area2 += cross(previous_image, image);
                previous_image = image;
            }
            image_area2 += cross(previous_image, first_image);
            if (!(image_area2 * orientation_sign[tri] > 0.0)) {
                set_reason(why, "face image flipped or degenerate");
                return false;
            }
            // Reuse the face objects of earlier calls (their corner lists keep capacity).
            if (face_count == faces.size()) faces.emplace_back();
            faces[face_count].corners.assign(corners.begin(), corners.end());
            faces[face_count].original_triangle = tri;
            ++face_count;
        }
    }
    // A connected plane graph has V - E + F = 2; otherwise something floats in a face.
    if (n - num_edges + num_faces != 2) {
        set_reason(why, "overlay is not a connected plane graph");
        return false;
    }
    return true;
}

}  // namespace

bool compute_faces(const TriangleGraph& graph, const Embedding& embedding, const std::vector<int8_t>& orientation_sign,
                   std::vector<OverlayFace>& faces, std::string* why) {
    size_t face_count = 0;
    const bool ok = faces_into(graph, embedding, orientation_sign, faces, face_count, why);
    faces.resize(face_count);
    return ok;
}

bool check_faces(const TriangleGraph& graph, const Embedding& embedding, const std::vector<int8_t>& orientation_sign,
                 std::vector<OverlayFace>& scratch, std::string* why) {
    size_t face_count = 0;
    return faces_into(graph, embedding, orientation_sign, scratch, face_count, why);
}

bool check_faces(const TriangleGraph& graph, const Embedding& embedding, const std::vector<int8_t>& orientation_sign,
                 std::vector<OverlayFace>& scratch, size_t& face_count, std::string* why) {
    return faces_into(graph, embedding, orientation_sign, scratch, face_count, why);
}

bool triangulate_faces(const TriangleGraph& graph, const Embedding& embedding,
                       const std::vector<int8_t>& orientation_sign, const std::vector<OverlayFace>& faces,
                       std::vector<Tri>& pieces, std::vector<int32_t>& piece_triangle, std::string* why) {
    pieces.clear();
    piece_triangle.clear();
    std::vector<int32_t> poly;
    std::vector<Vec2> image_of;
    for (const OverlayFace& f : faces) {
        poly = f.corners;
        const int8_t sign = orientation_sign[f.original_triangle];
        auto image_point = [&](int32_t node) {
            Vec3 beta;
            image_barycentric(graph.nodes[node], embedding, f.original_triangle, beta);
            return Vec2{beta[1], beta[2]};
        };
        // Ear clipping: an ear must be strictly positive in the parameter triangle
        // and strictly correctly oriented in the original triangle.
        while (poly.size() > 3) {
            const size_t m = poly.size();
            size_t ear = m;
            for (size_t c = 0; c < m && ear == m; ++c) {
                const int32_t a = poly[(c + m - 1) % m], b = poly[c], d = poly[(c + 1) % m];
                if (orient2d(param_point(graph.nodes[a]), param_point(graph.nodes[b]), param_point(graph.nodes[d])) <= 0)
                    continue;
                if (orient2d(image_point(a), image_point(b), image_point(d)) * sign <= 0) continue;
                ear = c;
            }
            if (ear == m) {
                set_reason(why, "face cannot be split into valid pieces");
                return false;
            }
            pieces.push_back({poly[(ear + m - 1) % m], poly[ear], poly[(ear + 1) % m]});
            piece_triangle.push_back(f.original_triangle);
            poly.erase(poly.begin() + static_cast<long>(ear));
        }
        if (orient2d(param_point(graph.nodes[poly[0]]), param_point(graph.nodes[poly[1]]),
                     param_point(graph.nodes[poly[2]])) <= 0 ||
            orient2d(image_point(poly[0]), image_point(poly[1]), image_point(poly[2])) * sign <= 0) {
            set_reason(why, "face cannot be split into valid pieces");
            return false;
        }
        pieces.push_back({poly[0], poly[1], poly[2]});
        piece_triangle.push_back(f.original_triangle);
    }
    return true;
}

void build_triangle_graph(const CoarseMesh& mesh, const Embedding& embedding, int32_t t, TriangleGraph& graph) {
    graph.nodes.clear();
    graph.segments.clear();
    const Tri& c = mesh.triangle(t);
    // Node of an original vertex and of a crossing (edge, index along its path): pairs
    // sorted once all nodes are made, then searched (a hash map and a tree allocated a
    // node per entry, for every triangle of the export). Were a key made twice, the later
    // node would count, as it did when the maps were assigned in turn.
    auto& buffers = graph.buffers;
    auto& vertex_node = buffers.vertex_node;
    auto& crossing_node = buffers.crossing_node;
    vertex_node.clear();
    crossing_node.clear();
    auto crossing_key = [](int32_t e, int32_t j) { return (uint64_t(uint32_t(e)) << 32) | uint32_t(j); };

    for (int k = 0; k < 3; ++k) {
        vertex_node.push_back({c[k], static_cast<int32_t>(graph.nodes.size())});
        graph.nodes.push_back(corner_node(k, c[k]));
    }
    auto& candidates = buffers.candidates;
    auto& list = buffers.list;
    candidates.clear();
    for (int k = 0; k < 3; ++k) {
        const int32_t a = c[k], b = c[(k + 1) % 3];
        EdgeContentView content;
        if (!embedding.content(a, b, content)) continue;
        const int32_t lo = std::min(a, b);
        auto bary_on_edge = [&](double s) { return bary_on_side(c, k, lo, s); };
        list.assign(content.vertices.begin(), content.vertices.end());
        std::sort(list.begin(), list.end());
        for (int32_t v : list) {
            GraphNode g;
            g.on_edge = static_cast<int8_t>(k);
            g.kind = NodeKind::OriginalVertex;
            g.vertex = v;
            g.bary = bary_on_edge(embedding.location[v].s);
            vertex_node.push_back({v, static_cast<int32_t>(graph.nodes.size())});
            graph.nodes.push_back(g);
            for (int32_t i = embedding.vertex_edge_offsets[v]; i < embedding.vertex_edge_offsets[v + 1]; ++i)
                candidates.push_back(embedding.vertex_edges[i]);
        }
        list.assign(content.crossing_edges.begin(), content.crossing_edges.end());
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
        const int32_t hi = std::max(a, b);
        for (int32_t e : list) {
            const auto p = embedding.crossings(e);
            for (int32_t j = 0; j < int32_t(p.size()); ++j) {
                if (p[j].a != lo || p[j].b != hi) continue;
                GraphNode g;
                g.on_edge = static_cast<int8_t>(k);
                g.kind = NodeKind::EdgeCrossing;
                g.edge = e;
                g.sigma = p[j].sigma;
                g.bary = bary_on_edge(p[j].s);
                crossing_node.push_back({crossing_key(e, j), static_cast<int32_t>(graph.nodes.size())});
                graph.nodes.push_back(g);
            }
            candidates.push_back(e);
        }
    }
    if (!embedding.inside.empty(t)) {
        list.clear();
        embedding.inside.append_to(t, list);
        std::sort(list.begin(), list.end());
        for (int32_t v : list) {
            GraphNode g;
            g.kind = NodeKind::OriginalVertex;
            g.vertex = v;
            g.bary = embedding.location[v].bary;
            vertex_node.push_back({v, static_cast<int32_t>(graph.nodes.size())});
            graph.nodes.push_back(g);
            for (int32_t i = embedding.vertex_edge_offsets[v]; i < embedding.vertex_edge_offsets[v + 1]; ++i)
                candidates.push_back(embedding.vertex_edges[i]);
        }
    }
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    // Nodes grow with the order of making: among equal keys the later node sorts last.
    std::sort(vertex_node.begin(), vertex_node.end());
    std::sort(crossing_node.begin(), crossing_node.end());
    auto node_with = [](const auto& pairs, auto key) -> int32_t {
        auto it = std::upper_bound(pairs.begin(), pairs.end(), key,
                                   [](const auto& k, const auto& pair) { return k < pair.first; });
        return it == pairs.begin() || std::prev(it)->first != key ? -1 : std::prev(it)->second;
    };

    // Local edges a point lies on (bit k for local edge k), or -1 if not in the triangle.
    auto edges_of = [&](const SurfacePoint& p) -> int {
        switch (p.kind) {
            case SurfacePoint::Corner:
                for (int k = 0; k < 3; ++k)
                    if (c[k] == p.a) return (1 << k) | (1 << ((k + 2) % 3));
                return -1;
            case SurfacePoint::OnEdge:
                for (int k = 0; k < 3; ++k)
                    if (edge_key(c[k], c[(k + 1) % 3]) == edge_key(p.a, p.b)) return 1 << k;
                return -1;
            case SurfacePoint::Inside:
                return p.a == t ? 0 : -1;
        }
        return -1;
    };
    auto& points = graph.buffers.points;
    auto& sigmas = graph.buffers.sigmas;
    for (int32_t e : candidates) {
        embedding.path_points(e, points, sigmas);
        const int32_t last = static_cast<int32_t>(points.size()) - 1;
        auto node_of = [&](int32_t j) -> int32_t {
            if (j == 0 || j == last) return node_with(vertex_node, embedding.edges[e][j == 0 ? 0 : 1]);
            return node_with(crossing_node, crossing_key(e, j - 1));
        };
        for (int32_t j = 0; j < last; ++j) {
            const int m0 = edges_of(points[j]), m1 = edges_of(points[j + 1]);
            if (m0 < 0 || m1 < 0 || (m0 & m1) != 0) continue;
            const int32_t n0 = node_of(j), n1 = node_of(j + 1);
            if (n0 < 0 || n1 < 0) continue;  // cannot happen for a consistent embedding
            graph.segments.push_back({n0, n1, e});
        }
    }
}

}  // namespace bpm::detail
