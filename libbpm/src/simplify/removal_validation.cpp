#include "simplify/removal_validation.h"

#include <algorithm>

namespace bpm::detail {

bool assign_pieces(const Fan& fan, const FanTriangulation& tri, const StarGraph& graph, const RecutEdges& cuts,
                   TransferPieces& pieces, std::array<int32_t, 2>& along_diagonal, std::string& why) {
    const int32_t n = fan.corners();
    const int32_t ntris = static_cast<int32_t>(tri.triangles.size());
    const int32_t nnodes = static_cast<int32_t>(graph.nodes.size());
    // 3. Full: which new triangle every piece of a cut segment lies in, the graph of
    // every new triangle, validated exactly.
    pieces.diagonal_triangles.assign(tri.diagonals.size(), {-1, -1});
    pieces.side_triangle.assign(n, -1);
    for (int32_t t = 0; t < ntris; ++t) {
        const auto& c = tri.triangles[t];
        for (int k = 0; k < 3; ++k) {
            const int32_t a = c[k], b = c[(k + 1) % 3];
            if (b == mod(a + 1, n)) pieces.side_triangle[a] = t;
            for (int32_t d = 0; d < int32_t(tri.diagonals.size()); ++d)
                if ((tri.diagonals[d][0] == a && tri.diagonals[d][1] == b) || (tri.diagonals[d][0] == b && tri.diagonals[d][1] == a))
                    (pieces.diagonal_triangles[d][0] < 0 ? pieces.diagonal_triangles[d][0] : pieces.diagonal_triangles[d][1]) = t;
        }
    }
    // Items: star nodes (id) and new crossings (nnodes + index).
    auto candidates = [&](int32_t item, int32_t out[], int& count) {
        count = 0;
        if (item >= nnodes) {
            const auto& dt = pieces.diagonal_triangles[cuts.crossings[item - nnodes].diagonal];
            out[count++] = dt[0];
            out[count++] = dt[1];
            return;
        }
        const StarNode& s = graph.nodes[item];
        if (s.free) {
            if (s.new_triangle >= 0) {
                out[count++] = s.new_triangle;
            } else {
                out[count++] = pieces.diagonal_triangles[s.diagonal][0];
                out[count++] = pieces.diagonal_triangles[s.diagonal][1];
            }
        } else if (s.poly_edge >= 0) {
            out[count++] = pieces.side_triangle[s.poly_edge];
        } else {
            for (int32_t t = 0; t < ntris && count < 64; ++t)
                for (int k = 0; k < 3; ++k)
                    if (tri.triangles[t][k] == s.poly_corner) out[count++] = t;
        }
    };
    pieces.pieces.clear();
    for (PathEdit& e : pieces.path_edits) pieces.recycle(e.middle);
    pieces.path_edits.clear();
    // Whether items a and b (star nodes) both lie on one diagonal: free nodes put on it, or
    // a polygon corner at its end.
    auto along_one_diagonal = [&](int32_t a, int32_t b) {
        if (a >= nnodes || b >= nnodes) return false;
        const StarNode& sa = graph.nodes[a];
        const StarNode& sb = graph.nodes[b];
        auto on_diagonal = [](const StarNode& s) { return s.free && s.new_triangle < 0 ? s.diagonal : -1; };
        auto ends = [&](int32_t d, const StarNode& s) {
            return s.poly_corner >= 0 && (tri.diagonals[d][0] == s.poly_corner || tri.diagonals[d][1] == s.poly_corner);
        };
        const int32_t da = on_diagonal(sa), db = on_diagonal(sb);
        if (da >= 0 && db >= 0) return da == db;
        if (da >= 0) return ends(da, sb);
        if (db >= 0) return ends(db, sa);
        return false;
    };
    int32_t ca[64], cb[64];
    for (size_t si = 0; si < graph.segments.size(); ++si) {
        const StraightSegment& seg = graph.segments[si];
        const int32_t c0 = cuts.cut_begin[si], c1 = cuts.cut_begin[si + 1];
        int32_t previous = seg.a;
        for (int32_t i = c0; i <= c1; ++i) {
            const int32_t item = i < c1 ? nnodes + i : seg.b;
            int na, nb;
            candidates(previous, ca, na);
            candidates(item, cb, nb);
            int32_t common = -1, count = 0;
            for (int p = 0; p < na; ++p)
                for (int q = 0; q < nb; ++q)
                    if (ca[p] == cb[q] && ca[p] != common) {
                        common = ca[p];
                        ++count;
                    }
            if (count == 2 && along_one_diagonal(previous, item)) {
                // The run lies along a diagonal (both ends on it, snapped there within
                // rounding distance: on a regular lattice, e.g. a gmsh box face, every ear
                // of some stars has original edges along it). Like a run along a feature
                // edge it is no piece: the overlays of the two triangles have its ends on
                // their common side, and the path keeps them as points of that edge.
                previous = item;
                continue;
            }
            if (count != 1) {
                why = count == 0 ? "re-cut lost track of an original edge" : "original edge along a new edge";
                if (count > 1) {
                    // The two triangles the run lies in share the diagonal it runs along.
                    int32_t t1 = -1, t2 = -1;
                    for (int p = 0; p < na; ++p)
                        for (int q = 0; q < nb; ++q) {
                            if (ca[p] != cb[q]) continue;
                            if (t1 < 0) t1 = ca[p];
                            else if (ca[p] != t1 && t2 < 0) t2 = ca[p];
                        }
                    if (t1 >= 0 && t2 >= 0) {
                        int32_t shared[2], k = 0;
                        for (int32_t u : tri.triangles[t1])
                            for (int32_t w : tri.triangles[t2])
                                if (u == w && k < 2) shared[k++] = u;
                        if (k == 2) along_diagonal = {shared[0], shared[1]};
                    }
                }
                return false;
            }
            pieces.pieces.push_back({common, previous, item, seg.edge});
            previous = item;
        }
        // Path edit: the new crossings in order along the original edge (which runs
        // from its smaller vertex; the segment may run the other way).
        PathEdit edit{seg.edge, seg.first, seg.last, pieces.take()};
        const bool increasing = seg.sigma_b > seg.sigma_a;
        for (int32_t i = 0; i < c1 - c0; ++i) {
            const NewCrossing& c = cuts.crossings[increasing ? c0 + i : c1 - 1 - i];
            edit.middle.push_back({c.lo, c.hi, c.s, c.sigma});
        }
        pieces.path_edits.push_back(std::move(edit));
    }

    return true;
}

bool check_new_triangles(const FanTransfer& transfer, int32_t begin, int32_t end, TriangleCheck& check, double& min_cosine,
                         std::string& why) {
    const Fan& fan = transfer.fan;
    const FanTriangulation& tri = transfer.tri;
    const StarGraph& star = transfer.graph;
    const RecutEdges& cuts = transfer.cuts;
    const TransferPieces& pieces = transfer.pieces;
    const int32_t n = fan.corners();
    const int32_t nnodes = static_cast<int32_t>(star.nodes.size());
    TriangleGraph& graph = check.graph;
    auto& local_ = check.local;
    auto& touched_ = check.touched;
    local_.assign(nnodes + cuts.crossings.size(), -1);
    for (int32_t t = begin; t < end; ++t) {
        const auto& c = tri.triangles[t];
        graph.nodes.clear();
        graph.segments.clear();
        const Tri cv{fan.link[c[0]], fan.link[c[1]], fan.link[c[2]]};
        // Places a node stored as (lo, hi, s) on the side of this triangle it lies on.
        auto on_side = [&](int32_t lo, int32_t hi, double s, GraphNode& g) {
            const int k = local_edge(cv, lo, hi);
            if (k < 0) return false;
            g.bary = bary_on_side(cv, k, lo, s);
            g.on_edge = static_cast<int8_t>(k);
            return true;
        };
        touched_.clear();
        auto add = [&](int32_t item, const GraphNode& g) {
            local_[item] = static_cast<int32_t>(graph.nodes.size());
            touched_.push_back(item);
            graph.nodes.push_back(g);
        };
        for (int k = 0; k < 3; ++k) add(star.vertex_node.get(cv[k]), corner_node(k, cv[k]));
        for (int k = 0; k < 3; ++k) {
            const int32_t a = c[k], b = c[(k + 1) % 3];
            if (b != mod(a + 1, n)) continue;
            for (int32_t id : star.side_nodes[a]) {
                const StarNode& s = star.nodes[id];
                GraphNode g;
                if (!on_side(s.edge_lo, s.edge_hi, s.edge_s, g)) {
                    why = "fixed node without its edge";
                    return false;
                }
                if (s.vertex >= 0) {
                    g.kind = NodeKind::OriginalVertex;
                    g.vertex = s.vertex;
                } else {
                    g.kind = NodeKind::EdgeCrossing;
                    g.edge = s.edge;
                    g.sigma = s.sigma;
                }
                add(id, g);
            }
        }
        for (int32_t id = 0; id < nnodes; ++id) {
            const StarNode& s = star.nodes[id];
            if (!s.free) continue;
            GraphNode g;
            g.kind = NodeKind::OriginalVertex;
            g.vertex = s.vertex;
            if (s.new_triangle == t) {
                g.bary = s.bary;
                add(id, g);
            } else if (s.diagonal >= 0 && on_side(s.edge_lo, s.edge_hi, s.edge_s, g)) {
                add(id, g);
            }
        }
        for (size_t i = 0; i < cuts.crossings.size(); ++i) {
            const NewCrossing& nc = cuts.crossings[i];
            GraphNode g;
            if (!on_side(nc.lo, nc.hi, nc.s, g)) continue;
            g.kind = NodeKind::EdgeCrossing;
            g.edge = nc.edge;
            g.sigma = nc.sigma;
            add(nnodes + static_cast<int32_t>(i), g);
        }
        for (const Piece& p : pieces.pieces) {
            if (p.triangle != t) continue;
            const int32_t i0 = local_[p.item0], i1 = local_[p.item1];
            if (i0 < 0 || i1 < 0) {
                why = "segment end missing in its triangle";
                return false;
            }
            graph.segments.push_back({i0, i1, p.edge});
        }
        for (int32_t item : touched_) local_[item] = -1;
        // The faces' checks look up the original edges of the segments and crossings
        // (which triangles they bound, where they end), scattered: ask for them together.
        for (const GraphSegment& sg : graph.segments) {
            __builtin_prefetch(transfer.emb.edge_triangle_offsets.data() + sg.edge);
            __builtin_prefetch(transfer.emb.edges.data() + sg.edge);
        }
        std::string& reason = check.reason;
        size_t face_count = 0;
        if (!check_faces(graph, transfer.emb, transfer.sign, check.faces, face_count, &reason)) {
            why = "invalid transfer: " + reason;
            return false;
        }
        // Every original triangle with a piece on t has a face here: exact.
        for (size_t f = 0; f < face_count && !transfer.normals.empty(); ++f)
            min_cosine = std::min(min_cosine, dot(transfer.new_normals[t], transfer.normals[check.faces[f].original_triangle]));
    }
    return true;
}

}  // namespace bpm::detail
