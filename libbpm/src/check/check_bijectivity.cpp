// check_bijectivity: phi: S -> S0 is a bijection.
//
// Argument. Inside one coarse triangle the pieces form a 2-chain. If every piece is
// positively oriented, every interior piece edge is used exactly twice with opposite
// directions and the piece edges on the triangle's boundary are exactly the segments
// between consecutive nodes along each coarse edge, traversed counter-clockwise, then
// the chain's boundary is the triangle's boundary and (degree argument) every point of
// the parameter triangle off the piece edges lies in exactly one piece: the pieces tile
// it. The same test in each original triangle's own barycentric chart shows that the
// images tile every original triangle. Together with nodes that agree along shared
// coarse edges, subdivisions of shared original edges that agree on all sides and
// every original vertex hit from exactly one point, phi is a continuous bijection.
// All orientation decisions use the exact orient2d on the stored coordinates; a piece
// whose three corners lie on one edge is degenerate by combinatorics alone.
#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include "bpm/check.h"
#include "bpm/phi_triangle.h"
#include "bpm/predicates.h"
#include "bpm/surface_topology.h"
#include "check/check_internal.h"

namespace bpm {

namespace {

using Ids = std::vector<std::pair<std::string, int64_t>>;

constexpr double kParameterTolerance = 1e-12;  // dimensionless: positions along edges, edge parameters
constexpr double kAreaTolerance = 1e-9;        // relative: area sums of pieces

inline Vec2 chart(const Vec3& b) { return {b[1], b[2]}; }
inline double area2(const Vec2& a, const Vec2& b, const Vec2& c) { return cross(b - a, c - a); }

struct DirectedEdge {
    int64_t lo, hi;   // endpoint keys, lo < hi
    bool forward;     // traversed lo -> hi
    int64_t piece;
    bool operator<(const DirectedEdge& o) const {
        return lo != o.lo ? lo < o.lo : (hi != o.hi ? hi < o.hi : piece < o.piece);
    }
};

// Position of a point of the coarse surface, shared by all coarse triangles that
// contain it: coarse vertex, k-th node along a coarse edge, or a node strictly inside.
struct PositionIds {
    int64_t edge_base = 0;      // + edge_offset[e] + index along the edge
    int64_t interior_base = 0;  // + global node index
    std::vector<int64_t> edge_offset;
};

// The problems found so far and the worst area-sum deviation, with where it occurs.
struct Findings {
    CheckResult& result;
    size_t max_problems;
    double worst = 0.0;  // the largest |area sum / area - 1| seen
    Ids worst_ids;

    void add(Ids ids, std::string message) { result.add_problem({std::move(ids), std::move(message)}, max_problems); }
    // `kind` names the element `id` (ids are built only for a new worst: this runs for
    // every triangle, and building them allocates).
    void note_area(double fraction, const char* kind, int64_t id) {
        const double dev = std::abs(fraction - 1.0);
        if (worst_ids.empty() || dev > worst) {
            worst = dev;
            worst_ids = {{kind, id}};
        }
    }
};

std::string n_str(int64_t n) { return std::to_string(n); }

// Scratch buffers of step A, reused across coarse triangles (no allocation per triangle).
struct TilingScratch {
    std::vector<DirectedEdge> edges;
    std::vector<std::pair<Vec2, int64_t>> sorted_nodes;
    std::vector<uint8_t> used;
    std::vector<std::array<int64_t, 2>> boundary_found[3];
    std::vector<std::pair<double, int64_t>> along;
};

// A: the pieces of coarse triangle `t` tile its parameter triangle: distinct parameter
// points, every node used, every piece counter-clockwise, areas summing to the
// triangle's, interior piece edges used twice in opposite directions, and the piece
// edges on each coarse edge exactly the segments between consecutive nodes along it.
void check_parameter_triangle(const Parametrization& p, int32_t t, TilingScratch& scratch, Findings& findings) {
    auto add = [&](Ids ids, std::string message) { findings.add(std::move(ids), std::move(message)); };
    auto& [edges, sorted_nodes, used, boundary_found, along] = scratch;

    const int64_t n0 = p.node_offsets[t], n1 = p.node_offsets[t + 1];
    const int64_t q0 = p.piece_offsets[t], q1 = p.piece_offsets[t + 1];
    auto bary = [&](int32_t local) -> const Vec3& { return p.node_barycentric[n0 + local]; };
    if (q0 == q1) {
        add({{"coarse_triangle", t}}, "has no pieces");
        return;
    }
    // Distinct parameter points.
    sorted_nodes.clear();
    for (int64_t n = n0; n < n1; ++n) sorted_nodes.push_back({chart(p.node_barycentric[n]), n});
    std::sort(sorted_nodes.begin(), sorted_nodes.end());
    for (size_t i = 1; i < sorted_nodes.size(); ++i)
        if (sorted_nodes[i].first == sorted_nodes[i - 1].first)
            add({{"coarse_triangle", t}, {"node", sorted_nodes[i].second}},
                "same parameter point as node " + n_str(sorted_nodes[i - 1].second));
    // Orientation and area of each piece; used nodes.
    used.assign(static_cast<size_t>(n1 - n0), 0);
    double area_sum = 0.0;
    edges.clear();
    for (int64_t q = q0; q < q1; ++q) {
        const Tri& pc = p.pieces[q];
        for (int k = 0; k < 3; ++k) used[pc[k]] = 1;
        const Vec2 a = chart(bary(pc[0])), b = chart(bary(pc[1])), c = chart(bary(pc[2]));
        bool degenerate = pc[0] == pc[1] || pc[1] == pc[2] || pc[0] == pc[2];
        for (int k = 0; k < 3 && !degenerate; ++k) {
            const int z = (k + 2) % 3;  // nodes on coarse edge k have b[z] == 0
            if (bary(pc[0])[z] == 0 && bary(pc[1])[z] == 0 && bary(pc[2])[z] == 0) degenerate = true;
        }
        const int o = degenerate ? 0 : orient2d(a, b, c);
        if (o <= 0)
            add({{"coarse_triangle", t}, {"piece", q}},
                o == 0 ? "degenerate piece (zero area in the parameter triangle)"
                       : "flipped piece (clockwise in the parameter triangle; nodes " + n_str(n0 + pc[0]) + ", " +
                             n_str(n0 + pc[1]) + ", " + n_str(n0 + pc[2]) + ")");
        area_sum += 0.5 * area2(a, b, c);
        for (int k = 0; k < 3; ++k) {
            const int64_t u = pc[k], w = pc[(k + 1) % 3];
            if (u == w) continue;
            edges.push_back({std::min(u, w), std::max(u, w), u < w, q});
        }
    }
    for (int64_t n = n0; n < n1; ++n)
        if (!used[n - n0]) add({{"coarse_triangle", t}, {"node", n}}, "node is a corner of no piece");
    const double fraction = area_sum / 0.5;
    findings.note_area(fraction, "coarse_triangle", t);
    if (!(std::abs(fraction - 1.0) <= kAreaTolerance))
        add({{"coarse_triangle", t}}, "pieces cover " + detail::format_number(fraction) +
                                          " times the area of the parameter triangle (gap or overlap)");
    // Edge matching.
    std::sort(edges.begin(), edges.end());
    for (auto& f : boundary_found) f.clear();
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
        const DirectedEdge& e = edges[i];
        const Vec3 &bl = bary(static_cast<int32_t>(e.lo)), &bh = bary(static_cast<int32_t>(e.hi));
        int side = -1;
        for (int k = 0; k < 3; ++k)
            if (bl[(k + 2) % 3] == 0 && bh[(k + 2) % 3] == 0) side = k;
        // Built only when a problem is reported: this runs for every piece edge.
        auto ids = [&]() { return Ids{{"coarse_triangle", t}, {"piece", e.piece}}; };
        auto name = [&]() { return "piece edge (node " + n_str(n0 + e.lo) + ", node " + n_str(n0 + e.hi) + ")"; };
        if (side >= 0) {
            // On coarse edge `side`: used once, counter-clockwise (b[side+1] increasing).
            const int s = (side + 1) % 3;
            const bool ccw = e.forward ? bh[s] > bl[s] : bl[s] > bh[s];
            if (j - i != 1)
                add(ids(), name() + " lies on coarse edge " + std::to_string(side) + " but is used by " +
                             std::to_string(j - i) + " pieces");
            else if (!ccw)
                add(ids(), name() + " on coarse edge " + std::to_string(side) +
                             " runs clockwise: the piece lies outside the parameter triangle");
            boundary_found[side].push_back({e.lo, e.hi});
        } else if (j - i == 1) {
            add(ids(), name() + " is used by only one piece: gap or overlap inside the coarse triangle");
        } else if (j - i == 2) {
            if (edges[i].forward == edges[i + 1].forward)
                add(ids(), name() + " is traversed in the same direction by pieces " + n_str(edges[i].piece) + " and " +
                             n_str(edges[i + 1].piece) + ": they overlap");
        } else {
            add(ids(), name() + " is used by " + std::to_string(j - i) + " pieces");
        }
        i = j;
    }
    // The piece edges on each coarse edge are exactly the segments between
    // consecutive nodes along it, from corner k to corner k+1.
    for (int k = 0; k < 3; ++k) {
        const int z = (k + 2) % 3, s = (k + 1) % 3;
        along.clear();
        for (int64_t n = n0; n < n1; ++n)
            if (p.node_barycentric[n][z] == 0) along.push_back({p.node_barycentric[n][s], n - n0});
        std::sort(along.begin(), along.end());
        if (along.size() < 2 || along.front().first != 0.0 || along.back().first != 1.0) {
            add({{"coarse_triangle", t}}, "coarse edge " + std::to_string(k) + " does not run from a node at corner " +
                                              std::to_string(k) + " to a node at corner " + std::to_string(s));
            continue;
        }
        auto& found = boundary_found[k];
        std::sort(found.begin(), found.end());
        for (size_t i = 1; i < along.size(); ++i) {
            const int64_t u = along[i - 1].second, w = along[i].second;
            const std::array<int64_t, 2> key{std::min(u, w), std::max(u, w)};
            if (!std::binary_search(found.begin(), found.end(), key)) {
                add({{"coarse_triangle", t}, {"node", n0 + w}},
                    "no piece has the segment from node " + n_str(n0 + u) + " to node " + n_str(n0 + w) +
                        " along coarse edge " + std::to_string(k));
                break;
            }
        }
        if (found.size() > along.size() - 1)
            add({{"coarse_triangle", t}}, "piece edges on coarse edge " + std::to_string(k) +
                                              " skip nodes or overlap (" + std::to_string(found.size()) +
                                              " segments for " + std::to_string(along.size()) + " nodes)");
    }
}

// B: the nodes on a coarse edge agree between the triangles that share it (same count,
// same positions, same original points and images). Returns each node's position id
// (PositionIds): nodes at the same point of the coarse surface get the same id.
std::vector<int64_t> node_positions(const Parametrization& p, Findings& findings) {
    auto add = [&](Ids ids, std::string message) { findings.add(std::move(ids), std::move(message)); };
    const int32_t nt = p.coarse.num_triangles();
    const int64_t nn = p.num_nodes();
    const double diagonal = bounding_box_diagonal(p.original);
    const SurfaceConnectivity coarse_conn = build_connectivity(p.coarse);
    PositionIds pos;
    pos.edge_base = p.coarse.num_vertices();
    pos.edge_offset.assign(static_cast<size_t>(coarse_conn.num_edges()) + 1, 0);
    std::vector<int64_t> node_position(nn, -1);
    // Nodes on coarse edges per (triangle, local edge), sorted by position from the
    // edge's smaller coarse vertex.
    auto edge_nodes = [&](int32_t t, int k, int32_t from) {
        std::vector<std::pair<double, int64_t>> list;
        const int z = (k + 2) % 3;
        const bool forward = p.coarse.triangles[t][k] == from;
        const int s = forward ? (k + 1) % 3 : k;
        for (int64_t n = p.node_offsets[t]; n < p.node_offsets[t + 1]; ++n) {
            const Vec3& b = p.node_barycentric[n];
            if (b[z] != 0) continue;
            if (b[k] == 1.0 || b[(k + 1) % 3] == 1.0) continue;  // corners are positions of coarse vertices
            list.push_back({b[s], n});
        }
        std::sort(list.begin(), list.end());
        return list;
    };
    auto same_identity = [&](int64_t a, int64_t b) {
        if (p.node_kind[a] != p.node_kind[b]) return false;
        if (p.node_kind[a] == NodeKind::EdgeCrossing)
            return p.node_original_edge[a] == p.node_original_edge[b] &&
                   std::abs(p.node_edge_parameter[a] - p.node_edge_parameter[b]) <= kParameterTolerance;
        return p.node_original_vertex[a] == p.node_original_vertex[b];
    };
    {
        int64_t offset = 0;
        for (int32_t e = 0; e < coarse_conn.num_edges(); ++e) {
            const int32_t u = coarse_conn.edges[e][0], w = coarse_conn.edges[e][1];
            std::vector<std::pair<double, int64_t>> first;
            int32_t first_t = -1;
            for (int64_t i = coarse_conn.edge_triangle_offsets[e]; i < coarse_conn.edge_triangle_offsets[e + 1]; ++i) {
                const int32_t t = coarse_conn.edge_triangles[i];
                int k = -1;
                for (int j = 0; j < 3; ++j)
                    if (coarse_conn.triangle_edges[t][j] == e) k = j;
                const auto list = edge_nodes(t, k, u);
                if (first_t < 0) {
                    first = list;
                    first_t = t;
                    for (size_t m = 0; m < list.size(); ++m) node_position[list[m].second] = pos.edge_base + offset + m;
                    continue;
                }
                if (list.size() != first.size()) {
                    add({{"coarse_triangle", t}}, "coarse edge (" + n_str(u) + ", " + n_str(w) + ") has " +
                                                      n_str(list.size()) + " nodes here but " + n_str(first.size()) +
                                                      " in coarse triangle " + n_str(first_t));
                }
                for (size_t m = 0; m < list.size(); ++m) {
                    const int64_t n = list[m].second;
                    if (m >= first.size()) {
                        node_position[n] = -1;  // gets an interior id below; already reported
                        continue;
                    }
                    node_position[n] = pos.edge_base + offset + m;
                    const int64_t f = first[m].second;
                    auto ids = [&]() { return Ids{{"coarse_triangle", t}, {"node", n}}; };
                    if (std::abs(list[m].first - first[m].first) > kParameterTolerance)
                        add(ids(), "at position " + detail::format_number(list[m].first) + " along coarse edge (" +
                                     n_str(u) + ", " + n_str(w) + "), but node " + n_str(f) + " of coarse triangle " +
                                     n_str(first_t) + " is at " + detail::format_number(first[m].first));
                    else if (!same_identity(n, f))
                        add(ids(), "is not the same original point as node " + n_str(f) + " of coarse triangle " +
                                     n_str(first_t) + " at the same place on coarse edge (" + n_str(u) + ", " + n_str(w) + ")");
                    else if (distance(p.node_image[n], p.node_image[f]) > 1e-9 * diagonal)
                        add(ids(), "image differs from that of node " + n_str(f) + " of coarse triangle " + n_str(first_t) +
                                     " at the same place on coarse edge (" + n_str(u) + ", " + n_str(w) + ")");
                }
            }
            offset += static_cast<int64_t>(first.size());
            pos.edge_offset[e + 1] = offset;
        }
        pos.interior_base = pos.edge_base + offset;
    }
    for (int32_t t = 0; t < nt; ++t)
        for (int64_t n = p.node_offsets[t]; n < p.node_offsets[t + 1]; ++n) {
            if (node_position[n] >= 0) continue;
            const Vec3& b = p.node_barycentric[n];
            int corner = -1;
            for (int k = 0; k < 3; ++k)
                if (b[k] == 1.0 && b[(k + 1) % 3] == 0.0 && b[(k + 2) % 3] == 0.0) corner = k;
            node_position[n] = corner >= 0 ? p.coarse.triangles[t][corner] : pos.interior_base + n;
        }

    return node_position;
}

// C: every original vertex is the image of exactly one point of the coarse surface, and
// no two points cross an original edge at the same place.
void check_original_vertices(const Parametrization& p, const std::vector<int64_t>& node_position, Findings& findings) {
    auto add = [&](Ids ids, std::string message) { findings.add(std::move(ids), std::move(message)); };
    const int64_t nn = p.num_nodes();
    const int32_t nv0 = p.original.num_vertices();
    std::vector<int64_t> first_pos(nv0, -1), first_node(nv0, -1);
    std::vector<uint8_t> reported(nv0, 0);
    for (int64_t n = 0; n < nn; ++n) {
        if (p.node_kind[n] == NodeKind::EdgeCrossing) continue;
        const int32_t v = p.node_original_vertex[n];
        if (first_pos[v] < 0) {
            first_pos[v] = node_position[n];
            first_node[v] = n;
        } else if (first_pos[v] != node_position[n] && !reported[v]) {
            reported[v] = 1;
            add({{"original_vertex", v}}, "is the image of two different points of the coarse surface (nodes " +
                                              n_str(first_node[v]) + " and " + n_str(n) + ")");
        }
    }
    // Vertices no triangle uses are not part of S0.
    std::vector<uint8_t> referenced(nv0, 0);
    for (const Tri& tri : p.original.triangles)
        for (int k = 0; k < 3; ++k) referenced[tri[k]] = 1;
    for (int32_t v = 0; v < nv0; ++v)
        if (referenced[v] && first_pos[v] < 0) add({{"original_vertex", v}}, "is the image of no node");
    // Two different points mapped to the same point of an original edge.
    std::vector<std::tuple<int32_t, int32_t, double, int64_t, int64_t>> crossings;
    for (int64_t n = 0; n < nn; ++n)
        if (p.node_kind[n] == NodeKind::EdgeCrossing)
            crossings.emplace_back(p.node_original_edge[n][0], p.node_original_edge[n][1], p.node_edge_parameter[n],
                                   node_position[n], n);
    std::sort(crossings.begin(), crossings.end());
    for (size_t i = 1; i < crossings.size(); ++i) {
        const auto &a = crossings[i - 1], &b = crossings[i];
        if (std::get<0>(a) == std::get<0>(b) && std::get<1>(a) == std::get<1>(b) &&
            std::abs(std::get<2>(a) - std::get<2>(b)) <= kParameterTolerance && std::get<3>(a) != std::get<3>(b))
            add({{"node", std::get<4>(b)}}, "crosses original edge (" + n_str(std::get<0>(b)) + ", " +
                                                n_str(std::get<1>(b)) + ") at the same point as node " +
                                                n_str(std::get<4>(a)) + ", from a different point of the coarse surface");
    }
}

// Per original triangle: 1 where its connected component of the original surface is
// consistently oriented (every edge of two triangles traversed in opposite directions).
// Orientation of an image relative to its original triangle must be positive where the
// original surface is consistently oriented (orientation is preserved). On a component
// that is not (a Moebius strip, or an input with flipped triangles) no coarse surface can
// match it everywhere, so there a piece may be reversed as long as everything mapping
// into one original triangle agrees (checked in E; the pieces of one coarse triangle may
// differ: their original triangles may be oriented inconsistently with each other).
std::vector<uint8_t> consistently_oriented(const Surface& original, const SurfaceConnectivity& original_conn) {
    std::vector<uint8_t> original_consistent(original.num_triangles(), 1);
    std::vector<int32_t> parent(original.num_triangles());
    for (size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int32_t>(i);
    auto find = [&](int32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::vector<uint8_t> bad_edge(original_conn.num_edges(), 0);
    for (int32_t e = 0; e < original_conn.num_edges(); ++e) {
        const int64_t b = original_conn.edge_triangle_offsets[e], en = original_conn.edge_triangle_offsets[e + 1];
        for (int64_t i = b + 1; i < en; ++i) {
            const int32_t x = find(original_conn.edge_triangles[b]), y = find(original_conn.edge_triangles[i]);
            if (x != y) parent[std::max(x, y)] = std::min(x, y);
        }
        if (en - b != 2) continue;
        auto runs_forward = [&](int32_t t) {
            for (int k = 0; k < 3; ++k)
                if (original_conn.triangle_edges[t][k] == e) return original.triangles[t][k] == original_conn.edges[e][0];
            return false;
        };
        if (runs_forward(original_conn.edge_triangles[b]) == runs_forward(original_conn.edge_triangles[b + 1]))
            bad_edge[e] = 1;
    }
    std::vector<uint8_t> root_ok(original.num_triangles(), 1);
    for (int32_t e = 0; e < original_conn.num_edges(); ++e)
        if (bad_edge[e]) root_ok[find(original_conn.edge_triangles[original_conn.edge_triangle_offsets[e]])] = 0;
    for (int32_t o = 0; o < original.num_triangles(); ++o) original_consistent[o] = root_ok[find(o)];
    return original_consistent;
}

// Each piece in its original triangle's own barycentric chart.
struct PieceCharts {
    std::vector<int8_t> sign;                       // +1, or -1 where reversed (allowed, see above)
    std::vector<std::array<Vec2, 3>> chart;         // corners in the original triangle's chart
    std::vector<std::array<uint8_t, 3>> support;    // per corner: bit mask of the original corners with non-zero coefficient
    std::vector<uint8_t> ok;                        // 0: a problem was reported for this piece
    int64_t reversed = 0;
};

// D: every piece maps into its original triangle (its corners are points of that
// triangle), not degenerate, with positive orientation where the original is
// consistently oriented.
PieceCharts chart_pieces(const Parametrization& p, const std::vector<uint8_t>& original_consistent, Findings& findings) {
    auto add = [&](Ids ids, std::string message) { findings.add(std::move(ids), std::move(message)); };
    const int32_t nt = p.coarse.num_triangles();
    const int64_t np = p.num_pieces();
    PieceCharts charts;
    auto& piece_sign = charts.sign;
    auto& piece_chart = charts.chart;
    auto& piece_support = charts.support;
    auto& piece_ok = charts.ok;
    auto& reversed_pieces = charts.reversed;
    piece_sign.assign(np, 1);
    piece_chart.resize(np);
    piece_support.resize(np);
    piece_ok.assign(np, 1);
    for (int32_t t = 0; t < nt; ++t) {
        const int64_t n0 = p.node_offsets[t];
        for (int64_t q = p.piece_offsets[t]; q < p.piece_offsets[t + 1]; ++q) {
            const int32_t o = p.piece_original_triangle[q];
            const Tri& ot = p.original.triangles[o];
            for (int k = 0; k < 3; ++k) {
                const int64_t n = n0 + p.pieces[q][k];
                double beta[3] = {0, 0, 0};
                uint8_t support = 0;
                if (p.node_kind[n] == NodeKind::EdgeCrossing) {
                    const auto& e = p.node_original_edge[n];
                    const double s = p.node_edge_parameter[n];
                    int iu = -1, iw = -1;
                    for (int j = 0; j < 3; ++j) {
                        if (ot[j] == e[0]) iu = j;
                        if (ot[j] == e[1]) iw = j;
                    }
                    if (iu < 0 || iw < 0) {
                        add({{"coarse_triangle", t}, {"piece", q}},
                            "corner node " + n_str(n) + " crosses original edge (" + n_str(e[0]) + ", " + n_str(e[1]) +
                                "), which is not an edge of original triangle " + n_str(o));
                        piece_ok[q] = 0;
                        continue;
                    }
                    beta[iu] = 1.0 - s;
                    beta[iw] = s;
                    support = static_cast<uint8_t>((1u << iu) | (1u << iw));
                } else {
                    const int32_t v = p.node_original_vertex[n];
                    int iv = -1;
                    for (int j = 0; j < 3; ++j)
                        if (ot[j] == v) iv = j;
                    if (iv < 0) {
                        add({{"coarse_triangle", t}, {"piece", q}},
                            "corner node " + n_str(n) + " is original vertex " + n_str(v) +
                                ", which is not a corner of original triangle " + n_str(o));
                        piece_ok[q] = 0;
                        continue;
                    }
                    beta[iv] = 1.0;
                    support = static_cast<uint8_t>(1u << iv);
                }
                piece_chart[q][k] = {beta[1], beta[2]};
                piece_support[q][k] = support;
            }
            if (!piece_ok[q]) continue;
            const auto& sp = piece_support[q];
            bool degenerate = false;
            for (uint8_t pair : {uint8_t(3), uint8_t(5), uint8_t(6)})
                if ((sp[0] & ~pair) == 0 && (sp[1] & ~pair) == 0 && (sp[2] & ~pair) == 0) degenerate = true;
            const int orientation = degenerate ? 0 : orient2d(piece_chart[q][0], piece_chart[q][1], piece_chart[q][2]);
            if (orientation == 0) {
                add({{"coarse_triangle", t}, {"piece", q}},
                    "image in original triangle " + n_str(o) + " is degenerate (zero area)");
                piece_ok[q] = 0;
                continue;
            }
            if (orientation < 0 && original_consistent[o]) {
                add({{"coarse_triangle", t}, {"piece", q}},
                    "maps into original triangle " + n_str(o) +
                        " with reversed orientation (the original surface is consistently oriented there)");
                piece_ok[q] = 0;
                continue;
            }
            piece_sign[q] = static_cast<int8_t>(orientation);
            reversed_pieces += orientation < 0;
        }
    }
    return charts;
}

// The pieces grouped by their original triangle (CSR), and each piece corner's position
// id, stored in piece order: a sequential pass, because step E visits pieces by original
// triangle, i.e. in random order, and would otherwise chase three dependent indices per
// corner.
struct PiecesByOriginal {
    std::vector<int64_t> offsets;   // #T0 + 1, into `pieces`
    std::vector<int64_t> pieces;
    std::vector<std::array<int64_t, 3>> corner_position;
};

PiecesByOriginal group_pieces_by_original(const Parametrization& p, const std::vector<int64_t>& node_position) {
    const int32_t nt = p.coarse.num_triangles();
    const int64_t np = p.num_pieces();
    const int32_t nt0 = p.original.num_triangles();
    PiecesByOriginal g;
    auto& off = g.offsets;
    off.assign(static_cast<size_t>(nt0) + 1, 0);
    for (int64_t q = 0; q < np; ++q) ++off[p.piece_original_triangle[q] + 1];
    for (int32_t o = 0; o < nt0; ++o) off[o + 1] += off[o];
    g.pieces.resize(np);
    {
        std::vector<int64_t> fill(off.begin(), off.end() - 1);
        for (int64_t q = 0; q < np; ++q) g.pieces[fill[p.piece_original_triangle[q]]++] = q;
    }
    g.corner_position.resize(np);
    for (int32_t t = 0; t < nt; ++t) {
        const PhiTriangle phi(p, t);
        for (int64_t j = 0; j < phi.num_pieces(); ++j)
            for (int k = 0; k < 3; ++k) g.corner_position[phi.first_piece() + j][k] = node_position[phi.piece_node(j, k)];
    }
    return g;
}

// Per original edge: the sequence of positions along it (from its smaller vertex) as
// seen from the first incident triangle, to compare the others with. One record per
// edge, so that a visit costs one cache miss.
struct EdgeSequence {
    int32_t first_triangle = -1;  // -1: no sequence yet
    int32_t length = 0;
    int64_t offset = 0;           // in OriginalEdgeSequences::positions
};
struct OriginalEdgeSequences {
    std::vector<EdgeSequence> edges;
    std::vector<int64_t> positions;
};

struct Along {
    double s;
    int64_t position;
    bool operator<(const Along& o) const { return s != o.s ? s < o.s : position < o.position; }
};

// Scratch buffers of step E, reused across original triangles.
struct CoverageScratch {
    std::vector<DirectedEdge> tedges;
    std::vector<Along> along[3];                            // points on edge j of the original triangle
    std::vector<std::array<int64_t, 2>> boundary_found[3];  // piece edges on edge j
    std::vector<int64_t> seq;
};

// E, last part: each edge of original triangle `o` is covered exactly once by piece
// edges, and its subdivision equals the one the other triangles at that edge see.
void check_original_triangle_edges(const Parametrization& p, int32_t o, const SurfaceConnectivity& original_conn,
                                   OriginalEdgeSequences& sequences_of, CoverageScratch& scratch, Findings& findings) {
    auto add = [&](Ids ids, std::string message) { findings.add(std::move(ids), std::move(message)); };
    auto& along = scratch.along;
    auto& boundary_found = scratch.boundary_found;
    auto& seq = scratch.seq;
    auto& edge_sequences = sequences_of.edges;
    auto& sequences = sequences_of.positions;

    const Tri& ot = p.original.triangles[o];
    for (int side = 0; side < 3; ++side) {
        auto& pts = along[side];
        std::sort(pts.begin(), pts.end());
        pts.erase(std::unique(pts.begin(), pts.end(),
                              [](const Along& x, const Along& y) { return x.position == y.position; }),
                  pts.end());
        auto& found = boundary_found[side];
        std::sort(found.begin(), found.end());
        bool chain_ok = pts.size() >= 2 && pts.front().s == 0.0 && pts.back().s == 1.0 &&
                        found.size() == pts.size() - 1;
        for (size_t i = 1; i < pts.size() && chain_ok; ++i) {
            const std::array<int64_t, 2> key{std::min(pts[i - 1].position, pts[i].position),
                                             std::max(pts[i - 1].position, pts[i].position)};
            chain_ok = std::binary_search(found.begin(), found.end(), key);
        }
        if (!chain_ok) {
            add({{"original_triangle", o}}, "its edge " + std::to_string(side) + " (vertices " + n_str(ot[side]) +
                                                ", " + n_str(ot[(side + 1) % 3]) +
                                                ") is not covered exactly once by piece edges");
            continue;
        }
        // Compare the subdivision of this original edge with the other triangles'.
        const int32_t u = ot[side], w = ot[(side + 1) % 3];
        const int32_t e = original_conn.triangle_edges[o][side];
        seq.clear();
        for (auto& a : pts) seq.push_back(a.position);
        if (u > w) std::reverse(seq.begin(), seq.end());
        EdgeSequence& first = edge_sequences[e];
        if (first.first_triangle < 0) {
            // (An edge of one triangle is stored too: a check of the degree would
            // cost another cache miss.)
            first.first_triangle = o;
            first.offset = static_cast<int64_t>(sequences.size());
            first.length = static_cast<int32_t>(seq.size());
            sequences.insert(sequences.end(), seq.begin(), seq.end());
        } else if (first.length != static_cast<int32_t>(seq.size()) ||
                   !std::equal(seq.begin(), seq.end(), sequences.begin() + first.offset)) {
            add({{"original_triangle", o}},
                "the points along its edge (" + n_str(std::min(u, w)) + ", " + n_str(std::max(u, w)) +
                    ") differ from those of original triangle " + n_str(first.first_triangle));
        }
    }
}

// E: the images of the pieces tile original triangle `o`: covered, all pieces with one
// orientation, areas summing to its area, interior piece edges used twice in opposite
// directions, and its edges covered exactly once and alike on all sides.
void check_original_triangle(const Parametrization& p, int32_t o, const SurfaceConnectivity& original_conn,
                             const PiecesByOriginal& groups, const PieceCharts& charts,
                             OriginalEdgeSequences& sequences, CoverageScratch& scratch, Findings& findings) {
    auto add = [&](Ids ids, std::string message) { findings.add(std::move(ids), std::move(message)); };
    const auto& off = groups.offsets;
    const auto& by_triangle = groups.pieces;
    auto corner_position = [&](int64_t q, int k) { return groups.corner_position[q][k]; };
    const auto& piece_ok = charts.ok;
    const auto& piece_sign = charts.sign;
    const auto& piece_chart = charts.chart;
    const auto& piece_support = charts.support;
    auto& tedges = scratch.tedges;
    auto& along_o = scratch.along;

    if (off[o] == off[o + 1]) {
        add({{"original_triangle", o}}, "is covered by no piece");
        return;
    }
    bool all_ok = true;
    for (int64_t i = off[o]; i < off[o + 1]; ++i) all_ok = all_ok && piece_ok[by_triangle[i]];
    if (!all_ok) return;  // already reported per piece
    const int8_t sign = piece_sign[by_triangle[off[o]]];
    bool same_sign = true;
    for (int64_t i = off[o]; i < off[o + 1]; ++i) same_sign = same_sign && piece_sign[by_triangle[i]] == sign;
    if (!same_sign) {
        add({{"original_triangle", o}}, "pieces map into it with both orientations (a fold)");
        return;
    }
    double area_sum = 0.0;
    tedges.clear();
    for (auto& a : along_o) a.clear();
    auto& along = along_o;
    for (int64_t i = off[o]; i < off[o + 1]; ++i) {
        const int64_t q = by_triangle[i];
        const auto& c = piece_chart[q];
        area_sum += 0.5 * sign * area2(c[0], c[1], c[2]);
        for (int k = 0; k < 3; ++k) {
            const int64_t a = corner_position(q, k), b = corner_position(q, (k + 1) % 3);
            tedges.push_back({std::min(a, b), std::max(a, b), a < b, q});
            // Points on edge j of the original triangle (corner j -> j+1).
            for (int j = 0; j < 3; ++j) {
                const uint8_t mask = static_cast<uint8_t>((1u << j) | (1u << ((j + 1) % 3)));
                if ((piece_support[q][k] & ~mask) == 0) {
                    const int s = (j + 1) % 3;
                    const double beta_s = s == 0 ? 1.0 - c[k][0] - c[k][1] : c[k][s - 1];
                    along[j].push_back({beta_s, a});
                }
            }
        }
    }
    const double fraction = area_sum / 0.5;
    findings.note_area(fraction, "original_triangle", o);
    if (!(std::abs(fraction - 1.0) <= kAreaTolerance))
        add({{"original_triangle", o}}, "pieces cover " + detail::format_number(fraction) +
                                            " times its area (gap or overlap on the original surface)");
    std::sort(tedges.begin(), tedges.end());
    auto& boundary_found = scratch.boundary_found;
    for (auto& f : boundary_found) f.clear();
    for (size_t i = 0; i < tedges.size();) {
        size_t j = i;
        while (j < tedges.size() && tedges[j].lo == tedges[i].lo && tedges[j].hi == tedges[i].hi) ++j;
        // Is this segment on an edge of the original triangle? Both ends have
        // support inside that edge's two corners.
        const DirectedEdge& e = tedges[i];
        const int64_t q = e.piece;
        int ka = -1, kb = -1;
        for (int k = 0; k < 3; ++k) {
            if (corner_position(q, k) == e.lo) ka = k;
            if (corner_position(q, k) == e.hi) kb = k;
        }
        int side = -1;
        for (int s = 0; s < 3 && ka >= 0 && kb >= 0; ++s) {
            const uint8_t mask = static_cast<uint8_t>((1u << s) | (1u << ((s + 1) % 3)));
            if ((piece_support[q][ka] & ~mask) == 0 && (piece_support[q][kb] & ~mask) == 0) side = s;
        }
        auto ids = [&]() { return Ids{{"original_triangle", o}, {"piece", q}}; };
        if (side >= 0) {
            if (j - i != 1)
                add(ids(), "a segment of its edge " + std::to_string(side) + " is covered by " +
                             std::to_string(j - i) + " pieces");
            boundary_found[side].push_back({e.lo, e.hi});
        } else if (j - i == 1) {
            add(ids(), "a piece edge inside it is used by only one piece: gap or overlap");
        } else if (j - i == 2) {
            if (tedges[i].forward == tedges[i + 1].forward)
                add(ids(), "pieces " + n_str(tedges[i].piece) + " and " + n_str(tedges[i + 1].piece) +
                             " overlap in it");
        } else {
            add(ids(), "a piece edge inside it is used by " + std::to_string(j - i) + " pieces");
        }
        i = j;
    }
    check_original_triangle_edges(p, o, original_conn, sequences, scratch, findings);
}

}  // namespace

CheckResult check_bijectivity(const Parametrization& p, const CheckOptions& options, const Context& context) {
    CheckResult r;
    r.name = "bijectivity";
    if (auto why = detail::parametrization_unsafe(p)) {
        detail::refuse(r, *why);
        return r;
    }
    Findings findings{r, options.max_problems, 0.0, {}};
    const int32_t nt = p.coarse.num_triangles();
    const int32_t nt0 = p.original.num_triangles();

    context.report(0.0, "checking the pieces of each coarse triangle");
    TilingScratch tiling;
    for (int32_t t = 0; t < nt; ++t) {
        if ((t & 0xfff) == 0) context.report(0.4 * t / std::max(nt, 1), "checking the pieces of each coarse triangle");
        check_parameter_triangle(p, t, tiling, findings);
    }

    context.report(0.4, "checking shared coarse edges");
    const std::vector<int64_t> node_position = node_positions(p, findings);

    context.report(0.5, "checking original vertices");
    check_original_vertices(p, node_position, findings);

    context.report(0.6, "checking pieces against original triangles");
    const SurfaceConnectivity original_conn = build_connectivity(p.original);
    const PieceCharts charts = chart_pieces(p, consistently_oriented(p.original, original_conn), findings);

    context.report(0.75, "checking coverage of the original triangles");
    {
        const PiecesByOriginal groups = group_pieces_by_original(p, node_position);
        OriginalEdgeSequences sequences;
        sequences.edges.resize(original_conn.num_edges());
        CoverageScratch coverage;
        for (int32_t o = 0; o < nt0; ++o) {
            if ((o & 0xfff) == 0) context.report(0.75 + 0.25 * o / std::max(nt0, 1), "checking coverage of the original triangles");
            check_original_triangle(p, o, original_conn, groups, charts, sequences, coverage, findings);
        }
    }

    r.add_count("coarse_triangles", nt);
    r.add_count("nodes", p.num_nodes());
    r.add_count("pieces", p.num_pieces());
    r.add_count("original_triangles", nt0);
    r.add_count("reversed_pieces", charts.reversed);
    r.worst = WorstValue{"area_sum_deviation", findings.worst, findings.worst_ids};
    r.summary = std::to_string(nt) + " coarse triangles, " + std::to_string(p.num_pieces()) + " pieces tile " +
                std::to_string(nt0) + " original triangles";
    context.report(1.0, "bijectivity");
    return r;
}

}  // namespace bpm
