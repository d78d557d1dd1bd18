#include "simplify/edge_flip.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "bpm/predicates.h"
#include "core/tetrahedron_quality.h"
#include "simplify/clearance_guard.h"
#include "simplify/corner_wedge_guard.h"
#include "simplify/overlay.h"
#include "simplify/ridge_guard.h"
#include "simplify/sheet_guard.h"
#include "simplify/wedge_guard.h"

namespace bpm::detail {

namespace {

constexpr double kEndMargin = 1e-9;  // cuts this close to an end of a segment or of c -- d are refused

// The quad of a flip unfolded about a -- b: a at the origin, b on the x axis, c above
// (triangle (a,b,c) keeps its shape), d below ((b,a,d) likewise).
struct Unfolded {
    int32_t v[4];  // a, b, c, d
    Vec2 p[4];
    int index(int32_t vertex) const {
        for (int i = 0; i < 4; ++i)
            if (v[i] == vertex) return i;
        return -1;
    }
};

Unfolded unfold(const std::vector<Vec3>& x, int32_t a, int32_t b, int32_t c, int32_t d) {
    Unfolded u{{a, b, c, d}, {}};
    const Vec3 axis = x[b] - x[a];
    const double length = norm(axis);
    const Vec3 e = (1.0 / length) * axis;
    auto place = [&](int32_t w, double side) -> Vec2 {
        const Vec3 r = x[w] - x[a];
        const double along = dot(r, e);
        return {along, side * norm(r - along * e)};
    };
    u.p[0] = {0.0, 0.0};
    u.p[1] = {length, 0.0};
    u.p[2] = place(c, 1.0);
    u.p[3] = place(d, -1.0);
    return u;
}

// Local sides of triangle `corners` (id t) that p lies on as a bit mask (side k: corner k
// -> corner k+1), 0 strictly inside, -1 not in the triangle.
int sides_of(const Tri& corners, int32_t t, const SurfacePoint& p) {
    switch (p.kind) {
        case SurfacePoint::Corner:
            for (int k = 0; k < 3; ++k)
                if (corners[k] == p.a) return (1 << k) | (1 << ((k + 2) % 3));
            return -1;
        case SurfacePoint::OnEdge: {
            const int k = local_edge(corners, p.a, p.b);
            return k < 0 ? -1 : 1 << k;
        }
        case SurfacePoint::Inside:
            return p.a == t ? 0 : -1;
    }
    return -1;
}

}  // namespace

bool plan_edge_flip(const CoarseMesh& mesh, const Embedding& embedding, int32_t x, int32_t y, EdgeFlip& flip,
                    std::string& why) {
    flip = EdgeFlip();
    if (mesh.is_feature_edge(x, y)) {
        why = "a feature edge";
        return false;
    }
    std::vector<int32_t> tris;
    mesh.edge_triangles(x, y, tris);
    if (tris.size() != 2) {
        why = "not an edge of exactly two triangles";
        return false;
    }
    const Tri t0 = mesh.triangle(tris[0]), t1 = mesh.triangle(tris[1]);
    const int k0 = local_edge(t0, x, y), k1 = local_edge(t1, x, y);
    const int32_t a = t0[k0], b = t0[(k0 + 1) % 3], c = t0[(k0 + 2) % 3];
    if (!(t1[k1] == b && t1[(k1 + 1) % 3] == a)) {
        why = "its two triangles are not consistently oriented";
        return false;
    }
    const int32_t d = t1[(k1 + 2) % 3];
    if (c == d || mesh.has_edge(c, d)) {
        why = "the new edge exists already";
        return false;
    }
    if (mesh.patch(tris[0]) != mesh.patch(tris[1])) {
        why = "a patch border";
        return false;
    }
    const auto& X = mesh.positions();
    const Unfolded u = unfold(X, a, b, c, d);
    const Vec2 &pa = u.p[0], &pb = u.p[1], &pc = u.p[2], &pd = u.p[3];
    const int side_a = orient2d(pc, pd, pa), side_b = orient2d(pc, pd, pb);
    if (orient2d(pa, pb, pc) <= 0 || orient2d(pb, pa, pd) <= 0 || side_a == 0 || side_b != -side_a ||
        orient2d(pa, pd, pc) <= 0 || orient2d(pd, pb, pc) <= 0) {
        why = "the unfolded quad is not strictly convex";
        return false;
    }
    flip.a = a;
    flip.b = b;
    flip.c = c;
    flip.d = d;
    flip.removed = {tris[0], tris[1]};
    flip.added = {Tri{a, d, c}, Tri{d, b, c}};
    flip.patch = mesh.patch(tris[0]);
    const Tri old_corners[2] = {t0, t1};

    // Position of a point of the closed quad in the plane; false if it is not in the quad.
    auto position = [&](const SurfacePoint& p, Vec2& out) -> bool {
        switch (p.kind) {
            case SurfacePoint::Corner: {
                const int i = u.index(p.a);
                if (i < 0) return false;
                out = u.p[i];
                return true;
            }
            case SurfacePoint::OnEdge: {
                const int i = u.index(p.a), j = u.index(p.b);
                if (i < 0 || j < 0) return false;
                out = u.p[i] + p.s * (u.p[j] - u.p[i]);
                return true;
            }
            case SurfacePoint::Inside:
                for (int r = 0; r < 2; ++r) {
                    if (p.a != flip.removed[r]) continue;
                    out = {0.0, 0.0};
                    for (int k = 0; k < 3; ++k) out = out + p.bary[k] * u.p[u.index(old_corners[r][k])];
                    return true;
                }
                return false;
        }
        return false;
    };
    const int32_t ab_lo = std::min(a, b), ab_hi = std::max(a, b);
    const int ab_side[2] = {1 << local_edge(t0, a, b), 1 << local_edge(t1, a, b)};
    // Whether the segment between consecutive path points p, q runs through the quad
    // (inside one of its triangles, or along a -- b), not along one of its sides or outside.
    auto through_quad = [&](const SurfacePoint& p, const SurfacePoint& q) {
        for (int r = 0; r < 2; ++r) {
            const int mp = sides_of(old_corners[r], flip.removed[r], p);
            const int mq = sides_of(old_corners[r], flip.removed[r], q);
            if (mp < 0 || mq < 0) continue;
            const int common = mp & mq;
            if (common == 0 || common == ab_side[r]) return true;
        }
        return false;
    };

    // The original vertices inside the quad (inside a triangle, or on a -- b) keep their
    // place in the plane and are located in the new triangles.
    std::vector<int32_t> moved;
    for (int r = 0; r < 2; ++r) embedding.inside.append_to(flip.removed[r], moved);
    const auto* on_ab = embedding.edge_content.find(edge_key(a, b));
    if (on_ab) {
        const EdgeContentView content = embedding.edge_content.view(*on_ab);
        moved.insert(moved.end(), content.vertices.begin(), content.vertices.end());
    }
    std::sort(moved.begin(), moved.end());
    const Vec2 new_corners[2][3] = {{pa, pd, pc}, {pd, pb, pc}};
    for (int32_t v : moved) {
        Vec2 p;
        position(embedding.location[v], p);
        const int side = orient2d(pc, pd, p);
        if (side == 0) {
            why = "an original vertex lies on the new edge";
            return false;
        }
        const int r = side == side_a ? 0 : 1;
        const Vec2 *q = new_corners[r];
        const double area = cross(q[1] - q[0], q[2] - q[0]);
        Vec3 bary{cross(q[1] - p, q[2] - p) / area, cross(q[2] - p, q[0] - p) / area, 0.0};
        bary[2] = 1.0 - bary[0] - bary[1];
        if (!(bary[0] > 0 && bary[1] > 0 && bary[2] > 0)) {
            why = "an original vertex is too close to a side of a new triangle";
            return false;
        }
        flip.new_locations.push_back({v, SurfacePoint::inside(-1 - r, bary)});
    }

    // The original edges that may run through the quad: those crossing or ending on its
    // sides or a -- b, those at its corners and at the vertices inside.
    std::vector<int32_t> edges;
    auto add_vertex_edges = [&](int32_t v) {
        for (int32_t i = embedding.vertex_edge_offsets[v]; i < embedding.vertex_edge_offsets[v + 1]; ++i)
            edges.push_back(embedding.vertex_edges[i]);
    };
    for (int32_t v : u.v) add_vertex_edges(v);
    for (int32_t v : moved) add_vertex_edges(v);
    const int32_t sides[5][2] = {{a, b}, {b, c}, {c, a}, {a, d}, {d, b}};
    for (const auto& s : sides) {
        const auto* entry = embedding.edge_content.find(edge_key(s[0], s[1]));
        if (!entry) continue;
        const EdgeContentView content = embedding.edge_content.view(*entry);
        for (int32_t v : content.vertices) add_vertex_edges(v);
        edges.insert(edges.end(), content.crossing_edges.begin(), content.crossing_edges.end());
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());

    const int32_t cd_lo = std::min(c, d), cd_hi = std::max(c, d);
    std::vector<SurfacePoint> points;
    std::vector<double> sigmas;
    std::vector<uint8_t> inside;
    for (int32_t e : edges) {
        embedding.path_points(e, points, sigmas);
        const size_t n = points.size();
        inside.assign(n - 1, 0);
        bool any = false;
        for (size_t i = 0; i + 1 < n; ++i) any |= (inside[i] = through_quad(points[i], points[i + 1])) != 0;
        if (!any) continue;
        std::vector<Crossing> crossings;
        int64_t anchor = -1;  // the last point kept (not a crossing of a -- b)
        Vec2 anchor_pos{};
        for (size_t i = 0; i < n; ++i) {
            const SurfacePoint& p = points[i];
            const bool dropped = i > 0 && i + 1 < n && p.a == ab_lo && p.b == ab_hi;
            if (dropped) continue;
            Vec2 pos{};
            const bool in_quad = position(p, pos);
            if (anchor >= 0 && i > 0 && inside[i - 1]) {
                // The straightened run from the anchor to here, cut by c -- d.
                const int oa = orient2d(pc, pd, anchor_pos), ob = orient2d(pc, pd, pos);
                const bool anchor_end = points[anchor].kind == SurfacePoint::Corner &&
                                        (points[anchor].a == c || points[anchor].a == d);
                const bool here_end = p.kind == SurfacePoint::Corner && (p.a == c || p.a == d);
                if ((oa == 0 && !anchor_end) || (ob == 0 && !here_end)) {
                    why = "an original edge would run through the new edge's line at a fixed point";
                    return false;
                }
                if (oa * ob < 0) {
                    const Vec2 r = pos - anchor_pos, q = pd - pc, w = pc - anchor_pos;
                    const double denominator = cross(r, q);
                    const double lambda = cross(w, q) / denominator, mu = cross(w, r) / denominator;
                    if (!(lambda > kEndMargin && lambda < 1 - kEndMargin && mu > kEndMargin && mu < 1 - kEndMargin)) {
                        why = "an original edge would cross the new edge too close to an end";
                        return false;
                    }
                    const double sigma = sigmas[anchor] + lambda * (sigmas[i] - sigmas[anchor]);
                    crossings.push_back({cd_lo, cd_hi, cd_lo == c ? mu : 1.0 - mu, sigma});
                }
            }
            if (i > 0 && i + 1 < n) crossings.push_back({p.a, p.b, p.s, sigmas[i]});
            anchor = int64_t(i);
            if (in_quad) anchor_pos = pos;
        }
        flip.new_paths.push_back({e, std::move(crossings)});
    }
    return true;
}

std::array<int32_t, 2> commit_edge_flip(CoarseMesh& mesh, Embedding& embedding, const EdgeFlip& flip) {
    for (const auto& loc : flip.new_locations) embedding.clear_location(loc.first);
    for (int32_t t : flip.removed) mesh.remove_triangle(t);
    const std::array<int32_t, 2> ids = {mesh.add_triangle(flip.added[0], flip.patch),
                                        mesh.add_triangle(flip.added[1], flip.patch)};
    embedding.ensure_triangle_capacity(mesh.triangle_capacity());
    for (auto loc : flip.new_locations) {
        if (loc.second.kind == SurfacePoint::Inside) loc.second.a = ids[-1 - loc.second.a];
        embedding.location[loc.first] = SurfacePoint::corner(loc.first);  // cleared above
        embedding.set_location(loc.first, loc.second);
    }
    for (const auto& p : flip.new_paths) embedding.set_path(p.first, p.second);
    return ids;
}

bool validate_flipped(const CoarseMesh& mesh, const Embedding& embedding, const std::vector<int8_t>& orientation_sign,
                      const std::array<int32_t, 2>& ids, double& max_deviation, std::string& why) {
    TriangleGraph graph;
    std::vector<OverlayFace> faces;
    std::vector<Tri> pieces;
    std::vector<int32_t> piece_triangle;
    const auto& X = mesh.positions();
    max_deviation = 0.0;
    for (int32_t t : ids) {
        build_triangle_graph(mesh, embedding, t, graph);
        if (!compute_faces(graph, embedding, orientation_sign, faces, &why) ||
            !triangulate_faces(graph, embedding, orientation_sign, faces, pieces, piece_triangle, &why))
            return false;
        const Tri& c = mesh.triangle(t);
        for (const GraphNode& g : graph.nodes)
            max_deviation = std::max(max_deviation, distance(node_image(g, embedding),
                                                             barycentric_point(X[c[0]], X[c[1]], X[c[2]], g.bary)));
    }
    return true;
}

namespace {

double pair_aspect(const std::vector<Vec3>& X, const Tri& s, const Tri& t) {
    return std::max(aspect_ratio(X[s[0]], X[s[1]], X[s[2]]), aspect_ratio(X[t[0]], X[t[1]], X[t[2]]));
}

double normal_turn(const std::vector<Vec3>& X, const Tri& s, const Tri& t) {
    const Vec3 n = triangle_normal(X[s[0]], X[s[1]], X[s[2]]), m = triangle_normal(X[t[0]], X[t[1]], X[t[2]]);
    return std::atan2(norm(cross(n, m)), dot(n, m)) * 180.0 / M_PI;
}

// +1 if the triangles of `mesh` are oriented outwards, -1 inwards, 0 if that is not one
// closed single-patch sheet (then a thin tetrahedron at an edge may lie on either side).
int outward_orientation(const CoarseMesh& mesh) {
    const auto& X = mesh.positions();
    int32_t patch = -1;
    double volume = 0.0;
    std::vector<int32_t> tris;
    std::vector<uint8_t> seen(mesh.triangle_capacity(), 0);
    std::vector<int32_t> stack;
    int components = 0;
    for (int32_t t = 0; t < mesh.triangle_capacity(); ++t) {
        if (!mesh.alive(t)) continue;
        if (patch >= 0 && mesh.patch(t) != patch) return 0;
        patch = mesh.patch(t);
        const Tri& c = mesh.triangle(t);
        for (int k = 0; k < 3; ++k) {
            mesh.edge_triangles(c[k], c[(k + 1) % 3], tris);
            if (tris.size() != 2) return 0;
        }
        volume += dot(X[c[0]], cross(X[c[1]], X[c[2]]));
        if (seen[t]) continue;
        if (++components > 1) return 0;
        stack.assign(1, t);
        seen[t] = 1;
        while (!stack.empty()) {
            const int32_t s = stack.back();
            stack.pop_back();
            for (int32_t v : mesh.triangle(s))
                for (int32_t w : mesh.triangles_of(v))
                    if (!seen[w]) {
                        seen[w] = 1;
                        stack.push_back(w);
                    }
        }
    }
    return volume > 0 ? 1 : (volume < 0 ? -1 : 0);
}

// The alive coarse vertices sorted by x, to find those near a point.
struct VerticesByX {
    std::vector<std::pair<double, int32_t>> sorted;
    VerticesByX(const CoarseMesh& mesh, int32_t num_vertices) {
        for (int32_t v = 0; v < num_vertices; ++v)
            if (mesh.vertex_alive(v)) sorted.push_back({mesh.positions()[v][0], v});
        std::sort(sorted.begin(), sorted.end());
    }
    // Whether a vertex other than `skip` lies in the closed ball (center, radius), up to
    // a relative 1e-9.
    bool any_in_ball(const std::vector<Vec3>& X, const Vec3& center, double radius, const int32_t (&skip)[4]) const {
        auto it = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(center[0] - radius, int32_t(-1)));
        const double limit = radius * (1 + 1e-9);
        for (; it != sorted.end() && it->first <= center[0] + radius; ++it) {
            const int32_t v = it->second;
            if (v == skip[0] || v == skip[1] || v == skip[2] || v == skip[3]) continue;
            if (distance(X[v], center) <= limit) return true;
        }
        return false;
    }
};

// Center of the sphere through p0..p3, false if they are (nearly) coplanar.
bool circumcenter(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3, Vec3& center) {
    const Vec3 a = p1 - p0, b = p2 - p0, c = p3 - p0;
    const double det = dot(a, cross(b, c));
    if (!(std::abs(det) > 1e-300)) return false;
    const Vec3 r = (dot(a, a) * cross(b, c) + dot(b, b) * cross(c, a) + dot(c, c) * cross(a, b));
    center = p0 + (0.5 / det) * r;
    return std::isfinite(center[0]) && std::isfinite(center[1]) && std::isfinite(center[2]);
}

}  // namespace

FlipStats flip_edges(CoarseMesh& mesh, Embedding& embedding, const std::vector<int8_t>& orientation_sign,
                     IntersectionTest& intersections, const FlipLimits& limits, const IslandGuard* islands,
                     const std::vector<float>* vertex_ridges) {
    FlipStats stats;
    const auto& X = mesh.positions();
    const int outward = limits.sliver_dihedral_degrees > 0 ? outward_orientation(mesh) : 0;
    const VerticesByX near(mesh, int32_t(X.size()));
    std::set<uint64_t> refused;  // edges (by their vertices) whose flip was refused: not tried again
    std::vector<TriangleGrid::Entry> scratch;
    std::vector<int32_t> sheet_scratch;
    IslandGuard::Scratch island_scratch;
    WedgeScratch wedge_scratch;
    RidgeScratch ridge_scratch;
    const bool ridges = vertex_ridges && !vertex_ridges->empty() && limits.min_ridge_angle_degrees > 0;
    const bool clearance = limits.prevent_intersections && limits.clearance_floor > 0;
    // The clearance guard's bound on the longest edge of the alive triangles (its grid
    // query reaches that far), kept up to date: a flip's new edge may be longer than any
    // before it.
    double longest = 0.0;
    if (clearance)
        for (int32_t t = 0; t < mesh.triangle_capacity(); ++t)
            if (mesh.alive(t)) longest = std::max(longest, longest_edge(X, mesh.triangle(t)));
    EdgeFlip flip, undo;
    std::string why;
    enum class Kind { Needle, Sliver };

    auto try_flip = [&](int32_t x, int32_t y, Kind kind) -> bool {
        const uint64_t key = edge_key(x, y);
        if (refused.count(key)) return false;
        auto refuse = [&] {
            refused.insert(key);
            ++stats.refused;
            return false;
        };
        if (!plan_edge_flip(mesh, embedding, x, y, flip, why)) return refuse();
        const Tri old0 = mesh.triangle(flip.removed[0]), old1 = mesh.triangle(flip.removed[1]);
        const double before = pair_aspect(X, old0, old1), after = pair_aspect(X, flip.added[0], flip.added[1]);
        // A needle's flip must at least halve the worst R/r (flips that barely help a needle
        // with a short edge only move its sliver: femur --vertices 1000, 92.8 -> 91.5 gave
        // 0.33 degrees instead of 0.55).
        if (kind == Kind::Needle ? !(after <= 0.5 * before) : !(after <= std::max(before, limits.needle_aspect)))
            return refuse();
        if (normal_turn(X, flip.added[0], flip.added[1]) > std::max(limits.max_normal_turn, normal_turn(X, old0, old1)))
            return refuse();
        // The ridge guard, as for a removal: the new edge is the removal's diagonal, the
        // quad's four sides the sides of its hole (their triangles outside stay, the one
        // inside changes), and the original vertices it covers are its corners and those
        // that move (inside the two triangles and on a -- b).
        if (ridges) {
            double sharpest_original = 180.0;
            for (int32_t v : {flip.a, flip.b, flip.c, flip.d})
                sharpest_original = std::min(sharpest_original, double((*vertex_ridges)[size_t(v)]));
            for (const auto& loc : flip.new_locations)
                sharpest_original = std::min(sharpest_original, double((*vertex_ridges)[size_t(loc.first)]));
            const double sharpest_new = sharpest_changed_ridge(mesh, {flip.removed[0], flip.removed[1]},
                                                               {flip.added[0], flip.added[1]}, -1, -1, ridge_scratch);
            if (ridge_too_sharp(sharpest_new, sharpest_original, limits.min_ridge_angle_degrees)) return refuse();
        }
        if (limits.prevent_intersections &&
            intersections.intersects_rest({flip.added[0], flip.added[1]}, {flip.removed[0], flip.removed[1]}, scratch))
            return refuse();
        // The quad's sides may be junction edges: the new apexes must stay between the same sheets.
        if (!keeps_sheet_order(mesh, {flip.removed[0], flip.removed[1]}, {flip.added[0], flip.added[1]}, sheet_scratch))
            return refuse();
        // ... and not fold onto their neighbours (the wedges there bound bpm-mesh's angles).
        if (!keeps_feature_wedges(mesh, {flip.removed[0], flip.removed[1]}, {flip.added[0], flip.added[1]}, -1, -1, -1,
                                  wedge_scratch, limits.junction_wedge_floor, limits.crease_wedge_floor))
            return refuse();
        // ... nor onto a triangle they share one corner with (as for removals).
        if (!keeps_corner_wedges(mesh, {flip.removed[0], flip.removed[1]}, {flip.added[0], flip.added[1]},
                                 limits.corner_wedge_floor))
            return refuse();
        // ... nor within the clearance floor of another part of the surface (the grid is
        // up to date: each flip is committed into it before the next is planned).
        if (clearance && !keeps_clearance(mesh, intersections.grid(), {flip.removed[0], flip.removed[1]},
                                          {flip.added[0], flip.added[1]}, {}, longest, scratch, limits.clearance_floor))
            return refuse();
        // The tetrahedron between the old and the new pair must hold no other component.
        if (islands && islands->active() &&
            islands->sweeps_island(mesh, intersections.grid(), mesh.triangle_capacity(), flip.a, -1, -1,
                                   {flip.removed[0], flip.removed[1]}, {flip.added[0], flip.added[1]}, island_scratch))
            return refuse();
        // What undoes it: the old triangles, the old locations and paths.
        undo = EdgeFlip();
        undo.added = {old0, old1};
        undo.patch = flip.patch;
        for (const auto& loc : flip.new_locations) {
            SurfacePoint p = embedding.location[loc.first];
            if (p.kind == SurfacePoint::Inside) p.a = p.a == flip.removed[0] ? -1 : -2;
            undo.new_locations.push_back({loc.first, p});
        }
        for (const auto& path : flip.new_paths) {
            const ConstRange<Crossing> old = embedding.path[size_t(path.first)];
            undo.new_paths.push_back({path.first, std::vector<Crossing>(old.begin(), old.end())});
        }
        const std::array<int32_t, 2> ids = commit_edge_flip(mesh, embedding, flip);
        double deviation = 0.0;
        if (!validate_flipped(mesh, embedding, orientation_sign, ids, deviation, why) ||
            deviation > limits.max_deviation) {
            undo.removed = ids;
            const std::array<int32_t, 2> back = commit_edge_flip(mesh, embedding, undo);
            intersections.update({{flip.removed[0], old0}, {flip.removed[1], old1}}, back[0]);
            return refuse();
        }
        intersections.update({{flip.removed[0], old0}, {flip.removed[1], old1}}, ids[0]);
        if (clearance) longest = std::max({longest, longest_edge(X, flip.added[0]), longest_edge(X, flip.added[1])});
        ++(kind == Kind::Needle ? stats.needle_flips : stats.sliver_flips);
        return true;
    };

    std::vector<int32_t> across;
    for (int pass = 0; pass < 32; ++pass) {
        const int64_t flips_before = stats.needle_flips + stats.sliver_flips;
        const int32_t capacity = mesh.triangle_capacity();
        for (int32_t t = 0; t < capacity; ++t) {
            if (!mesh.alive(t)) continue;
            const Tri c = mesh.triangle(t);
            if (aspect_ratio(X[c[0]], X[c[1]], X[c[2]]) > limits.needle_aspect) {
                // Its edges, longest first (a cap's long edge is the one whose flip helps).
                int order[3] = {0, 1, 2};
                auto length = [&](int k) { return distance(X[c[k]], X[c[(k + 1) % 3]]); };
                std::sort(order, order + 3, [&](int i, int j) { return length(i) > length(j) || (length(i) == length(j) && i < j); });
                for (int k : order)
                    if (try_flip(c[k], c[(k + 1) % 3], Kind::Needle)) break;
                continue;
            }
            if (outward == 0) continue;
            for (int k = 0; k < 3; ++k) {
                const int32_t a = c[k], b = c[(k + 1) % 3], apex = c[(k + 2) % 3];
                mesh.edge_triangles(a, b, across);
                if (across.size() != 2) continue;
                const int32_t other = across[0] == t ? across[1] : across[0];
                if (other < t) continue;  // each edge once
                const Tri& o = mesh.triangle(other);
                int32_t d = -1;
                for (int32_t w : o)
                    if (w != a && w != b) d = w;
                // Convex edge: d is on the inner side of (a,b,apex) (orient3d is +1 on the
                // side its normal points to, -1 on the other), where tetrahedron
                // (a,b,apex,d) lies inside the volume and TetGen, which may not split the
                // surface, has to keep it.
                if (orient3d(X[a], X[b], X[apex], X[d]) != -outward) continue;
                // Its smallest dihedral angle, corners ordered to make it positive.
                const double thinnest = outward < 0 ? min_dihedral_degrees(X[a], X[b], X[apex], X[d])
                                                    : min_dihedral_degrees(X[b], X[a], X[apex], X[d]);
                if (thinnest >= limits.sliver_dihedral_degrees) continue;
                // Only where the tetrahedron is Delaunay among the coarse vertices (no
                // other inside its circumsphere): those are the ones TetGen's
                // constrained Delaunay mesh keeps (elephant 10 %: 8 of 99 thin ones, among
                // them both that are in its mesh).
                Vec3 center;
                const int32_t corners[4] = {a, b, apex, d};
                if (!circumcenter(X[a], X[b], X[apex], X[d], center) ||
                    near.any_in_ball(X, center, distance(center, X[a]), corners))
                    continue;
                if (try_flip(a, b, Kind::Sliver)) break;
            }
        }
        if (stats.needle_flips + stats.sliver_flips == flips_before) break;
    }
    return stats;
}

}  // namespace bpm::detail
