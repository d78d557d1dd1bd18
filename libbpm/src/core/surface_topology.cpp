// Non-manifold connectivity and Z2 topology of a triangulated surface.
//
// Betti numbers: b0 from union-find, b2 = dim ker d2 over GF(2) by peeling (a triangle
// with an edge of which it is the only remaining triangle is in no 2-cycle) followed by
// merging triangles across edges of degree two into cells (a 2-cycle contains both or
// neither) and a sparse GF(2) elimination of the remaining constraints, one row per
// edge of degree >= 3. That matrix has one column per cell, so it is tiny for real
// surfaces; b1 then follows from the Euler characteristic: b1 = b0 + b2 - chi.
#include "bpm/surface_topology.h"

#include <algorithm>
#include <locale>
#include <map>
#include <numeric>
#include <sstream>
#include <tuple>

namespace bpm {

namespace {

struct UnionFind {
    std::vector<int32_t> parent;
    explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int32_t find(int32_t x) {
        while (parent[x] != x) {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        return x;
    }
    bool unite(int32_t a, int32_t b) {
        a = find(a);
        b = find(b);
        if (a == b) return false;
        if (a < b) std::swap(a, b);
        parent[a] = b;  // smaller index is the root: deterministic representatives
        return true;
    }
};

// Union-find that also tracks the parity between an element and its root, for
// orientation propagation.
struct ParityUnionFind {
    std::vector<int32_t> parent;
    std::vector<uint8_t> parity;  // parity to parent
    explicit ParityUnionFind(size_t n) : parent(n), parity(n, 0) { std::iota(parent.begin(), parent.end(), 0); }
    std::pair<int32_t, uint8_t> find(int32_t x) {
        uint8_t p = 0;
        int32_t r = x;
        while (parent[r] != r) {
            p ^= parity[r];
            r = parent[r];
        }
        // Path compression with parity fix-up.
        uint8_t q = p;
        while (parent[x] != x) {
            const int32_t next = parent[x];
            const uint8_t old = parity[x];
            parent[x] = r;
            parity[x] = q;
            q ^= old;
            x = next;
        }
        return {r, p};
    }
    // Requires parity(a) ^ parity(b) == rel; returns false on contradiction.
    bool unite(int32_t a, int32_t b, uint8_t rel) {
        auto [ra, pa] = find(a);
        auto [rb, pb] = find(b);
        if (ra == rb) return (pa ^ pb) == rel;
        parent[rb] = ra;
        parity[rb] = pa ^ pb ^ rel;
        return true;
    }
};

// Rank over GF(2) of the rows (sorted column lists). Rows are reduced by their
// smallest column against the pivot rows found so far.
int64_t gf2_rank(std::vector<std::vector<int32_t>> rows) {
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    std::map<int32_t, std::vector<int32_t>> pivots;
    int64_t rank = 0;
    std::vector<int32_t> scratch;
    for (auto& row : rows) {
        while (!row.empty()) {
            auto it = pivots.find(row.front());
            if (it == pivots.end()) break;
            scratch.clear();
            std::set_symmetric_difference(row.begin(), row.end(), it->second.begin(), it->second.end(),
                                          std::back_inserter(scratch));
            row.swap(scratch);
        }
        if (!row.empty()) {
            const int32_t lead = row.front();
            pivots.emplace(lead, std::move(row));
            ++rank;
        }
    }
    return rank;
}

}  // namespace

int32_t SurfaceConnectivity::find_edge(int32_t u, int32_t w) const {
    if (u > w) std::swap(u, w);
    const std::array<int32_t, 2> key{u, w};
    auto it = std::lower_bound(edges.begin(), edges.end(), key);
    if (it == edges.end() || *it != key) return -1;
    return static_cast<int32_t>(it - edges.begin());
}

SurfaceConnectivity build_connectivity(const Surface& surface) {
    SurfaceConnectivity c;
    const int32_t nt = surface.num_triangles();
    const int32_t nv = surface.num_vertices();
    // Half-edges bucketed by their smaller vertex (counting sort), then each small
    // bucket sorted by (larger vertex, triangle): edges come out in lexicographic order
    // in linear time, which matters for million-triangle surfaces.
    struct Incidence {
        int32_t other;
        int32_t triangle;
        int32_t local;
    };
    std::vector<int64_t> bucket(static_cast<size_t>(nv) + 1, 0);
    for (int32_t t = 0; t < nt; ++t) {
        const Tri& tri = surface.triangles[t];
        for (int k = 0; k < 3; ++k) {
            const int32_t a = tri[k], b = tri[(k + 1) % 3];
            if (a != b) ++bucket[std::min(a, b) + 1];
        }
    }
    for (int32_t v = 0; v < nv; ++v) bucket[v + 1] += bucket[v];
    std::vector<Incidence> inc(static_cast<size_t>(bucket[nv]));
    {
        std::vector<int64_t> fill(bucket.begin(), bucket.end() - 1);
        for (int32_t t = 0; t < nt; ++t) {
            const Tri& tri = surface.triangles[t];
            for (int k = 0; k < 3; ++k) {
                const int32_t a = tri[k], b = tri[(k + 1) % 3];
                if (a != b) inc[fill[std::min(a, b)]++] = {std::max(a, b), t, k};
            }
        }
    }
    c.triangle_edges.assign(nt, {-1, -1, -1});
    c.edge_triangle_offsets.push_back(0);
    c.edge_triangles.reserve(inc.size());
    c.edges.reserve(inc.size() / 2 + 1);
    for (int32_t u = 0; u < nv; ++u) {
        auto first = inc.begin() + bucket[u], last = inc.begin() + bucket[u + 1];
        std::sort(first, last, [](const Incidence& x, const Incidence& y) {
            return x.other != y.other ? x.other < y.other
                                      : (x.triangle != y.triangle ? x.triangle < y.triangle : x.local < y.local);
        });
        for (auto i = first; i != last;) {
            auto j = i;
            const int32_t e = static_cast<int32_t>(c.edges.size());
            c.edges.push_back({u, i->other});
            for (; j != last && j->other == i->other; ++j) {
                c.triangle_edges[j->triangle][j->local] = e;
                c.edge_triangles.push_back(j->triangle);
            }
            c.edge_triangle_offsets.push_back(static_cast<int64_t>(c.edge_triangles.size()));
            i = j;
        }
    }
    // Vertex -> triangles by counting sort (triangles come out ascending).
    c.vertex_triangle_offsets.assign(static_cast<size_t>(nv) + 1, 0);
    auto distinct_corners = [&](const Tri& tri, auto&& f) {
        f(tri[0]);
        if (tri[1] != tri[0]) f(tri[1]);
        if (tri[2] != tri[0] && tri[2] != tri[1]) f(tri[2]);
    };
    for (int32_t t = 0; t < nt; ++t)
        distinct_corners(surface.triangles[t], [&](int32_t v) { ++c.vertex_triangle_offsets[v + 1]; });
    for (int32_t v = 0; v < nv; ++v) c.vertex_triangle_offsets[v + 1] += c.vertex_triangle_offsets[v];
    c.vertex_triangles.resize(static_cast<size_t>(c.vertex_triangle_offsets[nv]));
    std::vector<int64_t> fill(c.vertex_triangle_offsets.begin(), c.vertex_triangle_offsets.end() - 1);
    for (int32_t t = 0; t < nt; ++t)
        distinct_corners(surface.triangles[t], [&](int32_t v) { c.vertex_triangles[fill[v]++] = t; });
    return c;
}

SurfaceTopology compute_topology(const Surface& surface) {
    SurfaceTopology topo;
    topo.connectivity = build_connectivity(surface);
    const SurfaceConnectivity& conn = topo.connectivity;
    const int32_t nt = surface.num_triangles();
    const int32_t nv = surface.num_vertices();
    const int32_t ne = conn.num_edges();
    auto patch_of = [&](int32_t t) { return t < static_cast<int32_t>(surface.patches.size()) ? surface.patches[t] : 0; };
    auto edge_tris = [&](int32_t e) {
        return std::make_pair(conn.edge_triangles.begin() + conn.edge_triangle_offsets[e],
                              conn.edge_triangles.begin() + conn.edge_triangle_offsets[e + 1]);
    };

    // --- edge classes ---
    topo.edge_class.resize(ne);
    for (int32_t e = 0; e < ne; ++e) {
        const int32_t d = conn.edge_degree(e);
        EdgeClass cls = EdgeClass::Regular;
        if (d == 1) {
            cls = EdgeClass::Boundary;
        } else if (d >= 3) {
            cls = EdgeClass::NonManifold;
        } else {
            const int32_t t0 = conn.edge_triangles[conn.edge_triangle_offsets[e]];
            const int32_t t1 = conn.edge_triangles[conn.edge_triangle_offsets[e] + 1];
            if (patch_of(t0) != patch_of(t1)) cls = EdgeClass::Interface;
        }
        topo.edge_class[e] = cls;
    }
    auto is_feature = [&](int32_t e) { return topo.edge_class[e] != EdgeClass::Regular; };

    // --- edge-connected components, numbered by their smallest triangle ---
    UnionFind comp_uf(nt);
    for (int32_t e = 0; e < ne; ++e) {
        auto [b, en] = edge_tris(e);
        for (auto it = b + 1; it < en; ++it) comp_uf.unite(*b, *it);
    }
    topo.triangle_component.assign(nt, -1);
    std::vector<int32_t> root_to_comp(nt, -1);
    int32_t ncomp = 0;
    for (int32_t t = 0; t < nt; ++t) {
        const int32_t r = comp_uf.find(t);
        if (root_to_comp[r] < 0) root_to_comp[r] = ncomp++;
        topo.triangle_component[t] = root_to_comp[r];
    }
    topo.components.resize(ncomp);
    std::vector<std::vector<int32_t>> comp_patches(ncomp);
    for (int32_t t = 0; t < nt; ++t) {
        ++topo.components[topo.triangle_component[t]].triangles;
        comp_patches[topo.triangle_component[t]].push_back(patch_of(t));
    }
    for (int32_t c = 0; c < ncomp; ++c) {
        auto& p = comp_patches[c];
        std::sort(p.begin(), p.end());
        p.erase(std::unique(p.begin(), p.end()), p.end());
        topo.components[c].patches = p;
    }
    auto edge_comp = [&](int32_t e) { return topo.triangle_component[conn.edge_triangles[conn.edge_triangle_offsets[e]]]; };
    for (int32_t e = 0; e < ne; ++e) ++topo.components[edge_comp(e)].edges;

    // Vertices per component, contact vertices, global b0 (components glued at contacts).
    UnionFind glue(ncomp);
    std::vector<int32_t> comps_here;
    for (int32_t v = 0; v < nv; ++v) {
        const int64_t b = conn.vertex_triangle_offsets[v], en = conn.vertex_triangle_offsets[v + 1];
        if (b == en) continue;
        ++topo.vertices;
        comps_here.clear();
        for (int64_t i = b; i < en; ++i) comps_here.push_back(topo.triangle_component[conn.vertex_triangles[i]]);
        std::sort(comps_here.begin(), comps_here.end());
        comps_here.erase(std::unique(comps_here.begin(), comps_here.end()), comps_here.end());
        for (int32_t c : comps_here) ++topo.components[c].vertices;
        if (comps_here.size() > 1) {
            topo.contact_vertices.push_back(v);
            for (size_t i = 1; i < comps_here.size(); ++i) glue.unite(comps_here[0], comps_here[i]);
        }
    }
    topo.edges = ne;
    topo.triangles = nt;
    topo.euler_characteristic = topo.vertices - topo.edges + topo.triangles;
    for (int32_t c = 0; c < ncomp; ++c)
        if (glue.find(c) == c) ++topo.betti0;

    // --- b2 per component: peel, merge cells, eliminate ---
    {
        std::vector<int32_t> degree(ne);
        for (int32_t e = 0; e < ne; ++e) degree[e] = conn.edge_degree(e);
        std::vector<uint8_t> alive(nt, 1);
        std::vector<int32_t> queue;
        for (int32_t e = 0; e < ne; ++e)
            if (degree[e] == 1) queue.push_back(e);
        while (!queue.empty()) {
            const int32_t e = queue.back();
            queue.pop_back();
            if (degree[e] != 1) continue;
            auto [b, en] = edge_tris(e);
            int32_t t = -1;
            for (auto it = b; it < en; ++it)
                if (alive[*it]) t = *it;
            alive[t] = 0;
            for (int k = 0; k < 3; ++k) {
                const int32_t f = conn.triangle_edges[t][k];
                if (f < 0) continue;
                if (--degree[f] == 1) queue.push_back(f);
            }
        }
        UnionFind cells(nt);
        for (int32_t e = 0; e < ne; ++e) {
            if (degree[e] != 2) continue;
            auto [b, en] = edge_tris(e);
            int32_t first = -1;
            for (auto it = b; it < en; ++it) {
                if (!alive[*it]) continue;
                if (first < 0) first = *it;
                else cells.unite(first, *it);
            }
        }
        std::vector<int64_t> cell_count(ncomp, 0);
        for (int32_t t = 0; t < nt; ++t)
            if (alive[t] && cells.find(t) == t) ++cell_count[topo.triangle_component[t]];
        std::vector<std::vector<std::vector<int32_t>>> rows(ncomp);
        std::vector<int32_t> row;
        for (int32_t e = 0; e < ne; ++e) {
            if (degree[e] < 3) continue;
            row.clear();
            auto [b, en] = edge_tris(e);
            for (auto it = b; it < en; ++it)
                if (alive[*it]) row.push_back(cells.find(*it));
            std::sort(row.begin(), row.end());
            std::vector<int32_t> odd;
            for (size_t i = 0; i < row.size();) {
                size_t j = i;
                while (j < row.size() && row[j] == row[i]) ++j;
                if ((j - i) % 2 == 1) odd.push_back(row[i]);
                i = j;
            }
            if (!odd.empty()) rows[edge_comp(e)].push_back(std::move(odd));
        }
        for (int32_t c = 0; c < ncomp; ++c) {
            topo.components[c].betti2 = cell_count[c] - gf2_rank(std::move(rows[c]));
            topo.betti2 += topo.components[c].betti2;
        }
    }

    // --- orientability across edges with exactly two triangles ---
    {
        ParityUnionFind orient(nt);
        std::vector<uint8_t> comp_orientable(ncomp, 1);
        for (int32_t e = 0; e < ne; ++e) {
            if (conn.edge_degree(e) != 2) continue;
            const int32_t t0 = conn.edge_triangles[conn.edge_triangle_offsets[e]];
            const int32_t t1 = conn.edge_triangles[conn.edge_triangle_offsets[e] + 1];
            auto direction = [&](int32_t t) {  // +1 if t runs u -> w along the edge
                for (int k = 0; k < 3; ++k)
                    if (conn.triangle_edges[t][k] == e) return surface.triangles[t][k] == conn.edges[e][0] ? 1 : -1;
                return 0;
            };
            // Consistent neighbours traverse the shared edge in opposite directions; if
            // they run the same way, one of the two must be flipped.
            const uint8_t rel = direction(t0) == direction(t1) ? 1 : 0;
            if (!orient.unite(t0, t1, rel)) comp_orientable[topo.triangle_component[t0]] = 0;
        }
        for (int32_t c = 0; c < ncomp; ++c) {
            topo.components[c].orientable = comp_orientable[c] != 0;
            topo.orientable = topo.orientable && comp_orientable[c];
        }
    }

    // --- sheets: components after cutting along feature edges ---
    {
        UnionFind sheets(nt);
        for (int32_t e = 0; e < ne; ++e) {
            if (is_feature(e)) continue;
            auto [b, en] = edge_tris(e);
            sheets.unite(*b, *(b + 1));
        }
        for (int32_t t = 0; t < nt; ++t)
            if (sheets.find(t) == t) ++topo.components[topo.triangle_component[t]].sheets;
    }

    // --- per vertex: wedges (for boundary loops, manifoldness) and fans (feature vertices) ---
    // Wedge ids are global positions in vertex_triangles (the root's position).
    std::vector<int64_t> wedge_of_position(conn.vertex_triangles.size());
    std::vector<uint8_t> is_feature_vertex(nv, 0);
    std::vector<uint8_t> comp_manifold(ncomp, 1);
    for (int32_t e = 0; e < ne; ++e)
        if (topo.edge_class[e] == EdgeClass::NonManifold) comp_manifold[edge_comp(e)] = 0;
    {
        std::vector<int32_t> fan_end_edge;  // per local fan root: up to two feature edges at its ends
        for (int32_t v = 0; v < nv; ++v) {
            const int64_t b = conn.vertex_triangle_offsets[v], en = conn.vertex_triangle_offsets[v + 1];
            const int32_t d = static_cast<int32_t>(en - b);
            if (d == 0) continue;
            auto local = [&](int32_t t) {
                auto it = std::lower_bound(conn.vertex_triangles.begin() + b, conn.vertex_triangles.begin() + en, t);
                return static_cast<int32_t>(it - (conn.vertex_triangles.begin() + b));
            };
            UnionFind wedges(d), fans(d);
            std::vector<int32_t> feature_edges_here;
            // edges at v: each incident triangle has two of them
            for (int32_t i = 0; i < d; ++i) {
                const int32_t t = conn.vertex_triangles[b + i];
                for (int k = 0; k < 3; ++k) {
                    const int32_t e = conn.triangle_edges[t][k];
                    if (e < 0 || (conn.edges[e][0] != v && conn.edges[e][1] != v)) continue;
                    auto [eb, ee] = edge_tris(e);
                    if (*eb != t) continue;  // handle each edge once, from its first triangle
                    for (auto it = eb + 1; it < ee; ++it) wedges.unite(i, local(*it));
                    if (is_feature(e)) feature_edges_here.push_back(e);
                    else fans.unite(i, local(*(eb + 1)));
                }
            }
            int32_t num_wedges = 0;
            for (int32_t i = 0; i < d; ++i) {
                wedge_of_position[b + i] = b + wedges.find(i);
                if (wedges.find(i) == i) ++num_wedges;
            }
            if (num_wedges > 1) {
                // Two wedges in one component pinch that component; wedges in different
                // components are a contact between components (see contact_vertices).
                std::vector<int32_t> seen;
                for (int32_t i = 0; i < d; ++i) {
                    if (wedges.find(i) != i) continue;
                    const int32_t c = topo.triangle_component[conn.vertex_triangles[b + i]];
                    if (std::find(seen.begin(), seen.end(), c) != seen.end()) comp_manifold[c] = 0;
                    seen.push_back(c);
                }
                topo.manifold = false;
            }
            // Fans: ends at feature edges.
            const size_t nf = feature_edges_here.size();
            bool regular = false;
            if (nf == 0) {
                int32_t num_fans = 0;
                for (int32_t i = 0; i < d; ++i)
                    if (fans.find(i) == i) ++num_fans;
                regular = num_fans == 1;
            } else if (nf == 2) {
                const int32_t e1 = feature_edges_here[0], e2 = feature_edges_here[1];
                // count ends per fan at e1 and at e2
                fan_end_edge.assign(static_cast<size_t>(d) * 2, 0);  // [root*2+0] ends at e1, [root*2+1] ends at e2
                for (int32_t i = 0; i < d; ++i) {
                    const int32_t t = conn.vertex_triangles[b + i];
                    const int32_t r = fans.find(i);
                    for (int k = 0; k < 3; ++k) {
                        const int32_t e = conn.triangle_edges[t][k];
                        if (e == e1) ++fan_end_edge[r * 2 + 0];
                        if (e == e2) ++fan_end_edge[r * 2 + 1];
                    }
                }
                regular = true;
                for (int32_t i = 0; i < d; ++i)
                    if (fans.find(i) == i && !(fan_end_edge[i * 2] == 1 && fan_end_edge[i * 2 + 1] == 1)) regular = false;
            }
            if (!regular) {
                is_feature_vertex[v] = 1;
                topo.feature_vertices.push_back(v);
            }
        }
    }
    for (int32_t e = 0; e < ne; ++e)
        if (topo.edge_class[e] == EdgeClass::NonManifold) topo.manifold = false;
    for (int32_t c = 0; c < ncomp; ++c) topo.components[c].manifold = comp_manifold[c] != 0;

    // --- boundary loops: boundary edges join the wedges of their end vertices ---
    {
        auto position = [&](int32_t v, int32_t t) {
            auto first = conn.vertex_triangles.begin() + conn.vertex_triangle_offsets[v];
            auto last = conn.vertex_triangles.begin() + conn.vertex_triangle_offsets[v + 1];
            return static_cast<int64_t>(std::lower_bound(first, last, t) - conn.vertex_triangles.begin());
        };
        std::vector<int32_t> boundary_edges;
        for (int32_t e = 0; e < ne; ++e)
            if (topo.edge_class[e] == EdgeClass::Boundary) boundary_edges.push_back(e);
        // Union-find over boundary edges: two boundary edges are in one loop when they
        // meet in the same wedge of a vertex.
        UnionFind loops(boundary_edges.size());
        std::vector<std::pair<int64_t, int32_t>> wedge_edge;  // (wedge id, boundary edge index)
        wedge_edge.reserve(boundary_edges.size() * 2);
        for (size_t i = 0; i < boundary_edges.size(); ++i) {
            const int32_t e = boundary_edges[i];
            const int32_t t = conn.edge_triangles[conn.edge_triangle_offsets[e]];
            for (int s = 0; s < 2; ++s)
                wedge_edge.push_back({wedge_of_position[position(conn.edges[e][s], t)], static_cast<int32_t>(i)});
        }
        std::sort(wedge_edge.begin(), wedge_edge.end());
        for (size_t i = 1; i < wedge_edge.size(); ++i)
            if (wedge_edge[i].first == wedge_edge[i - 1].first) loops.unite(wedge_edge[i].second, wedge_edge[i - 1].second);
        for (size_t i = 0; i < boundary_edges.size(); ++i) {
            if (loops.find(static_cast<int32_t>(i)) != static_cast<int32_t>(i)) continue;
            ++topo.boundary_loops;
            ++topo.components[edge_comp(boundary_edges[i])].boundary_loops;
        }
    }

    // --- Euler characteristic and b1 ---
    for (auto& c : topo.components) {
        c.euler_characteristic = c.vertices - c.edges + c.triangles;
        c.betti0 = 1;
        c.betti1 = c.betti0 + c.betti2 - c.euler_characteristic;
    }
    topo.betti1 = topo.betti0 + topo.betti2 - topo.euler_characteristic;

    // --- feature lines ---
    {
        std::vector<int64_t> fe_off(static_cast<size_t>(nv) + 1, 0);
        for (int32_t e = 0; e < ne; ++e)
            if (is_feature(e)) {
                ++fe_off[conn.edges[e][0] + 1];
                ++fe_off[conn.edges[e][1] + 1];
            }
        for (int32_t v = 0; v < nv; ++v) fe_off[v + 1] += fe_off[v];
        std::vector<int32_t> fe(static_cast<size_t>(fe_off[nv]));
        {
            std::vector<int64_t> fill(fe_off.begin(), fe_off.end() - 1);
            for (int32_t e = 0; e < ne; ++e)
                if (is_feature(e)) {
                    fe[fill[conn.edges[e][0]]++] = e;
                    fe[fill[conn.edges[e][1]]++] = e;
                }
        }
        std::vector<uint8_t> visited(ne, 0);
        auto other = [&](int32_t e, int32_t v) { return conn.edges[e][0] == v ? conn.edges[e][1] : conn.edges[e][0]; };
        auto make_line = [&](int32_t start_vertex, int32_t first_edge, bool closed) {
            FeatureLine line;
            line.closed = closed;
            line.vertices.push_back(start_vertex);
            int32_t v = start_vertex, e = first_edge;
            while (true) {
                visited[e] = 1;
                line.edges.push_back(e);
                v = other(e, v);
                if (closed ? v == start_vertex : is_feature_vertex[v] != 0) break;
                line.vertices.push_back(v);
                // a regular feature-line vertex has exactly two feature edges
                const int32_t a = fe[fe_off[v]], b = fe[fe_off[v] + 1];
                e = a == e ? b : a;
            }
            if (!closed) line.vertices.push_back(v);
            line.sheets = conn.edge_degree(first_edge);
            auto [tb, tend] = edge_tris(first_edge);
            for (auto it = tb; it < tend; ++it) line.patches.push_back(patch_of(*it));
            std::sort(line.patches.begin(), line.patches.end());
            line.component = topo.triangle_component[*tb];
            if (!closed) {
                if (line.vertices.front() > line.vertices.back()) {
                    std::reverse(line.vertices.begin(), line.vertices.end());
                    std::reverse(line.edges.begin(), line.edges.end());
                }
                line.first_vertex = line.vertices.front();
                line.last_vertex = line.vertices.back();
            } else {
                line.first_vertex = line.last_vertex = start_vertex;
            }
            return line;
        };
        std::vector<FeatureLine> open, loops;
        for (int32_t v : topo.feature_vertices)
            for (int64_t i = fe_off[v]; i < fe_off[v + 1]; ++i)
                if (!visited[fe[i]]) open.push_back(make_line(v, fe[i], false));
        // What is left lies on closed loops of regular vertices; start each at its
        // smallest vertex (edges are sorted, so the first unvisited edge has it).
        for (int32_t e = 0; e < ne; ++e)
            if (is_feature(e) && !visited[e]) loops.push_back(make_line(conn.edges[e][0], e, true));
        std::sort(open.begin(), open.end(), [](const FeatureLine& x, const FeatureLine& y) {
            return std::tie(x.first_vertex, x.last_vertex, x.sheets, x.edges) <
                   std::tie(y.first_vertex, y.last_vertex, y.sheets, y.edges);
        });
        topo.feature_lines = std::move(open);
        for (auto& l : loops) topo.feature_lines.push_back(std::move(l));
        topo.vertex_feature_line.assign(nv, -1);
        for (size_t i = 0; i < topo.feature_lines.size(); ++i) {
            const FeatureLine& l = topo.feature_lines[i];
            const size_t first = l.closed ? 0 : 1, last = l.closed ? l.vertices.size() : l.vertices.size() - 1;
            for (size_t j = first; j < last; ++j) topo.vertex_feature_line[l.vertices[j]] = static_cast<int32_t>(i);
            ++topo.components[l.component].feature_lines;
            if (l.closed) ++topo.components[l.component].feature_loops;
        }
    }
    for (int32_t v : topo.feature_vertices) {
        comps_here.clear();
        for (int64_t i = conn.vertex_triangle_offsets[v]; i < conn.vertex_triangle_offsets[v + 1]; ++i)
            comps_here.push_back(topo.triangle_component[conn.vertex_triangles[i]]);
        std::sort(comps_here.begin(), comps_here.end());
        comps_here.erase(std::unique(comps_here.begin(), comps_here.end()), comps_here.end());
        for (int32_t c : comps_here) ++topo.components[c].feature_vertices;
    }
    return topo;
}

namespace {

std::string join(const std::vector<int32_t>& v) {
    std::string s;
    for (size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + std::to_string(v[i]);
    return s;
}

std::string describe_component(const ComponentSummary& c) {
    std::ostringstream o;
    o.imbue(std::locale::classic());  // not a host's global locale: no "12.345", no "0,5"
    o << "chi " << c.euler_characteristic << ", b=(" << c.betti0 << "," << c.betti1 << "," << c.betti2 << "), "
      << (c.orientable ? "orientable" : "non-orientable") << ", " << (c.manifold ? "manifold" : "non-manifold") << ", "
      << c.boundary_loops << " boundary loops, " << c.sheets << " sheets, " << c.feature_vertices
      << " feature vertices, " << c.feature_lines << " feature lines, patches {" << join(c.patches) << "}";
    return o.str();
}

using ComponentKey = std::tuple<int64_t, bool, bool, int64_t, int64_t, int64_t, int64_t, int64_t, int64_t, int64_t,
                                std::vector<int32_t>>;
ComponentKey key_of(const ComponentSummary& c) {
    return {c.euler_characteristic, c.orientable, c.manifold, c.boundary_loops, c.betti0, c.betti1, c.betti2,
            c.sheets, c.feature_vertices, c.feature_lines, c.patches};
}

std::string line_name(const FeatureLine& l) {
    std::ostringstream o;
    o.imbue(std::locale::classic());  // not a host's global locale: no "12.345", no "0,5"
    if (l.closed) o << "closed feature line through vertex " << l.first_vertex;
    else o << "feature line " << l.first_vertex << "-" << l.last_vertex;
    o << " (" << l.sheets << " sheets, patches {" << join(l.patches) << "})";
    return o.str();
}

}  // namespace

std::vector<std::string> compare_topology(const SurfaceTopology& a, const SurfaceTopology& b,
                                          const TopologyCorrespondence& corr, size_t max_differences) {
    std::vector<std::string> out;
    auto add = [&](const std::string& s) {
        if (out.size() < max_differences) out.push_back(s);
    };
    auto cmp = [&](const char* what, int64_t va, int64_t vb) {
        if (va != vb) add(std::string(what) + ": original " + std::to_string(va) + ", coarse " + std::to_string(vb));
    };
    cmp("edge-connected components", static_cast<int64_t>(a.components.size()), static_cast<int64_t>(b.components.size()));
    cmp("Euler characteristic", a.euler_characteristic, b.euler_characteristic);
    cmp("Betti number b0 (Z2)", a.betti0, b.betti0);
    cmp("Betti number b1 (Z2)", a.betti1, b.betti1);
    cmp("Betti number b2 (Z2)", a.betti2, b.betti2);
    cmp("boundary loops", a.boundary_loops, b.boundary_loops);
    cmp("orientable", a.orientable, b.orientable);
    cmp("manifold", a.manifold, b.manifold);
    cmp("vertex-only contacts between components", static_cast<int64_t>(a.contact_vertices.size()),
        static_cast<int64_t>(b.contact_vertices.size()));
    cmp("feature vertices", static_cast<int64_t>(a.feature_vertices.size()), static_cast<int64_t>(b.feature_vertices.size()));
    cmp("feature lines", static_cast<int64_t>(a.feature_lines.size()), static_cast<int64_t>(b.feature_lines.size()));

    // Components.
    const bool have_component_map = corr.component_map.size() == b.components.size() && !b.components.empty();
    if (have_component_map && a.components.size() == b.components.size()) {
        std::vector<int32_t> hit(a.components.size(), -1);
        for (size_t j = 0; j < b.components.size(); ++j) {
            const int32_t i = corr.component_map[j];
            if (i < 0 || i >= static_cast<int32_t>(a.components.size())) {
                add("coarse component " + std::to_string(j) + " corresponds to no original component");
                continue;
            }
            if (hit[i] >= 0) {
                add("coarse components " + std::to_string(hit[i]) + " and " + std::to_string(j) +
                    " both correspond to original component " + std::to_string(i));
                continue;
            }
            hit[i] = static_cast<int32_t>(j);
            if (key_of(a.components[i]) != key_of(b.components[j]))
                add("coarse component " + std::to_string(j) + " differs from original component " + std::to_string(i) +
                    ": original " + describe_component(a.components[i]) + "; coarse " + describe_component(b.components[j]));
        }
    } else if (a.components.size() == b.components.size()) {
        std::vector<ComponentKey> ka, kb;
        for (auto& c : a.components) ka.push_back(key_of(c));
        for (auto& c : b.components) kb.push_back(key_of(c));
        std::sort(ka.begin(), ka.end());
        std::sort(kb.begin(), kb.end());
        if (ka != kb) add("the components' invariants differ (compared as sets; no correspondence given)");
    }

    // Feature vertices, exactly by id.
    const bool have_vertex_map = !corr.vertex_map.empty();
    auto map_vertex = [&](int32_t v) {
        return v >= 0 && v < static_cast<int32_t>(corr.vertex_map.size()) ? corr.vertex_map[v] : -1;
    };
    if (have_vertex_map) {
        std::vector<int32_t> mapped;
        for (int32_t v : b.feature_vertices) mapped.push_back(map_vertex(v));
        std::vector<int32_t> sorted = mapped;
        std::sort(sorted.begin(), sorted.end());
        for (int32_t v : a.feature_vertices)
            if (!std::binary_search(sorted.begin(), sorted.end(), v))
                add("original feature vertex " + std::to_string(v) + " is not a feature vertex of the coarse surface");
        for (size_t i = 0; i < mapped.size(); ++i)
            if (!std::binary_search(a.feature_vertices.begin(), a.feature_vertices.end(), mapped[i]))
                add("coarse vertex " + std::to_string(b.feature_vertices[i]) + " (original " + std::to_string(mapped[i]) +
                    ") is a feature vertex, but the original vertex is not");

        // Feature lines: lines with inner vertices are matched through them; single-edge
        // lines by their ends. Every original line must be matched exactly once.
        std::vector<int32_t> matched_by(a.feature_lines.size(), -1);
        // Open original lines by (ends, sheets, patches), for lines without inner vertices.
        using EndKey = std::tuple<int32_t, int32_t, int32_t, std::vector<int32_t>>;
        std::map<EndKey, std::vector<int32_t>> by_ends;
        for (size_t i = a.feature_lines.size(); i-- > 0;) {
            const FeatureLine& l = a.feature_lines[i];
            if (!l.closed) by_ends[EndKey{l.first_vertex, l.last_vertex, l.sheets, l.patches}].push_back(static_cast<int32_t>(i));
        }
        std::vector<size_t> order;
        for (size_t j = 0; j < b.feature_lines.size(); ++j)
            if (b.feature_lines[j].vertices.size() > (b.feature_lines[j].closed ? 0u : 2u)) order.push_back(j);
        for (size_t j = 0; j < b.feature_lines.size(); ++j)
            if (b.feature_lines[j].vertices.size() <= (b.feature_lines[j].closed ? 0u : 2u)) order.push_back(j);
        for (size_t j : order) {
            const FeatureLine& lb = b.feature_lines[j];
            int32_t fa = lb.closed ? -1 : map_vertex(lb.first_vertex), la = lb.closed ? -1 : map_vertex(lb.last_vertex);
            if (fa > la) std::swap(fa, la);
            auto fits = [&](const FeatureLine& l) {
                return l.closed == lb.closed && l.sheets == lb.sheets && l.patches == lb.patches &&
                       (lb.closed || (l.first_vertex == fa && l.last_vertex == la));
            };
            int32_t candidate = -1;
            const size_t first_inner = lb.closed ? 0 : 1;
            const size_t end_inner = lb.closed ? lb.vertices.size() : lb.vertices.size() - 1;
            if (end_inner > first_inner) {
                const int32_t va = map_vertex(lb.vertices[first_inner]);
                candidate = va >= 0 && va < static_cast<int32_t>(a.vertex_feature_line.size()) ? a.vertex_feature_line[va] : -1;
                for (size_t k = first_inner; k < end_inner && candidate >= 0; ++k) {
                    const int32_t vk = map_vertex(lb.vertices[k]);
                    if (vk < 0 || vk >= static_cast<int32_t>(a.vertex_feature_line.size()) ||
                        a.vertex_feature_line[vk] != candidate)
                        candidate = -1;
                }
                if (candidate >= 0 && !fits(a.feature_lines[candidate])) candidate = -1;
            } else if (!lb.closed) {
                auto it = by_ends.find(EndKey{fa, la, lb.sheets, lb.patches});
                if (it != by_ends.end()) {
                    auto& list = it->second;  // smallest index last
                    while (!list.empty() && matched_by[list.back()] >= 0) list.pop_back();
                    if (!list.empty()) candidate = list.back();
                }
            }
            if (candidate < 0) {
                add("coarse " + line_name(lb) + " matches no original feature line (ends mapped to original " +
                    std::to_string(fa) + "-" + std::to_string(la) + ")");
            } else if (matched_by[candidate] >= 0) {
                add("coarse " + line_name(lb) + " and another coarse line both follow original " +
                    line_name(a.feature_lines[candidate]));
            } else {
                matched_by[candidate] = static_cast<int32_t>(j);
            }
        }
        for (size_t i = 0; i < a.feature_lines.size(); ++i)
            if (matched_by[i] < 0) add("original " + line_name(a.feature_lines[i]) + " has no coarse counterpart");
    } else {
        using LineKey = std::tuple<bool, int32_t, std::vector<int32_t>>;
        std::vector<LineKey> la, lb;
        for (auto& l : a.feature_lines) la.push_back({l.closed, l.sheets, l.patches});
        for (auto& l : b.feature_lines) lb.push_back({l.closed, l.sheets, l.patches});
        std::sort(la.begin(), la.end());
        std::sort(lb.begin(), lb.end());
        if (la != lb) add("the feature lines' sheet counts or patches differ");
    }
    return out;
}

std::string describe_topology(const SurfaceTopology& t) {
    std::ostringstream o;
    o.imbue(std::locale::classic());  // not a host's global locale: no "12.345", no "0,5"
    o << t.components.size() << (t.components.size() == 1 ? " component" : " components") << ", chi "
      << t.euler_characteristic << ", b=(" << t.betti0 << "," << t.betti1 << "," << t.betti2 << "), "
      << (t.orientable ? "orientable" : "non-orientable") << ", " << (t.manifold ? "manifold" : "non-manifold") << ", "
      << t.boundary_loops << " boundary loops, " << t.feature_vertices.size() << " topological feature vertices, "
      << t.feature_lines.size() << " topological feature lines (of boundaries, patch borders, non-manifold edges; "
         "creases are geometry, not counted)";
    return o.str();
}

}  // namespace bpm
