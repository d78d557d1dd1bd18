// repair_self_intersections (bpm/self_intersection_repair.h): bpm's exact check finds
// whether there is anything to repair and whether the repair helped; CGAL's
// experimental local repair does the surgery on a Surface_mesh copy, and the result is
// mapped back onto the Surface (order, patches, vertex data) only if it is better.
// The one translation unit of libbpm with CGAL's Polygon_mesh_processing repair code
// (it takes minutes to compile).
#include "bpm/self_intersection_repair.h"

#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/repair_self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <limits>
#include <map>
#include <set>
#include <vector>

#include "bpm/check.h"
#include "bpm/predicates.h"
#include "bpm/surface_topology.h"
#include "check/improper_pair.h"

namespace bpm {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using VertexIndex = Mesh::Vertex_index;
using FaceIndex = Mesh::Face_index;

Point to_point(const Vec3& v) { return Point(v[0], v[1], v[2]); }
Vec3 to_vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

// Reports CGAL's rounds as progress; bpm::Cancelled thrown from here leaves the CGAL
// copy half-repaired, never the caller's surface. (CGAL copies the visitor and uses the
// copy throughout.)
struct ProgressVisitor : CGAL::Polygon_mesh_processing::experimental::Remove_self_intersection_default_visitor<Mesh> {
    const Context* context = nullptr;
    int round = 0;
    // Once at the start of each round.
    void start_iteration() {
        ++round;
        report();
    }
    // At the start of each round and of each connected region within a round: the same
    // progress again, so that cancellation is noticed between regions.
    bool stop() const {
        if (round > 0) report();
        return false;
    }
    void report() const {
        context->report(0.1 + 0.1 * std::min(round, 7), "self-intersection repair: round " + std::to_string(round));
    }
};

// The vertices of face f, in the face's orientation.
std::array<VertexIndex, 3> corners(const Mesh& mesh, FaceIndex f);

// CGAL's filter of the intersecting pairs it finds: true for a pair that only touches
// where copies of one pinched vertex are (distinct vertices at one point to CGAL, one
// vertex to bpm), decided by check_intersections' own exact predicate.
struct PinchedPairs {
    const Mesh* mesh;
    const Mesh::Property_map<VertexIndex, int32_t>* vertex_input;
    bool operator()(const std::pair<FaceIndex, FaceIndex>& pair) const {
        // Corners as bpm sees them: copies of an input vertex at the same point are one.
        std::vector<Vec3> points;
        std::vector<std::pair<int64_t, Vec3>> keys;
        bool merged = false;
        auto local = [&](VertexIndex v) {
            const int32_t input = (*vertex_input)[v];
            const Vec3 p = to_vec(mesh->point(v));
            const int64_t key = input >= 0 ? int64_t(input) : -1 - int64_t(uint32_t(v));
            for (size_t i = 0; i < keys.size(); ++i)
                if (keys[i].first == key && keys[i].second == p) return int32_t(i);
            keys.push_back({key, p});
            points.push_back(p);
            return int32_t(points.size() - 1);
        };
        const auto a = corners(*mesh, pair.first), b = corners(*mesh, pair.second);
        Tri A, B;
        for (int k = 0; k < 3; ++k) A[size_t(k)] = local(a[size_t(k)]);
        for (int k = 0; k < 3; ++k) {
            B[size_t(k)] = local(b[size_t(k)]);
            for (int j = 0; j < 3; ++j) merged |= B[size_t(k)] == A[size_t(j)] && b[size_t(k)] != a[size_t(j)];
        }
        if (!merged) return false;  // no copies involved: CGAL's verdict stands
        for (const Tri& t : {A, B})
            if (collinear3d(points[size_t(t[0])], points[size_t(t[1])], points[size_t(t[2])])) return false;
        return !detail::surface_triangles_meet_improperly(points, A, B);
    }
};

// The vertices of face f, in the face's orientation.
std::array<VertexIndex, 3> corners(const Mesh& mesh, FaceIndex f) {
    const auto h = mesh.halfedge(f);
    return {mesh.target(h), mesh.target(mesh.next(h)), mesh.target(mesh.next(mesh.next(h)))};
}

// Whether `now` is `before` up to a rotation (the same oriented triangle).
bool same_triangle(const Tri& before, const Tri& now) {
    for (int r = 0; r < 3; ++r)
        if (now[0] == before[r] && now[1] == before[(r + 1) % 3] && now[2] == before[(r + 2) % 3]) return true;
    return false;
}

// Per corner (3 t + k) of the surface, its fan: the corners of one vertex whose triangles
// are joined through edges of exactly two consistently oriented triangles at that vertex
// share a fan id (the smallest corner of the fan). A vertex with more than one fan is
// pinched (or on an edge of 3+ triangles, or on a turned triangle).
std::vector<int32_t> fan_of_corners(const Surface& surface) {
    std::vector<int32_t> parent(surface.triangles.size() * 3);
    for (size_t i = 0; i < parent.size(); ++i) parent[i] = int32_t(i);
    auto find = [&](int32_t i) {
        while (parent[size_t(i)] != i) i = parent[size_t(i)] = parent[size_t(parent[size_t(i)])];
        return i;
    };
    auto join = [&](int32_t a, int32_t b) {
        a = find(a), b = find(b);
        if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
    };
    // Edges as (smaller vertex, larger vertex, corner of the edge's first end in its triangle).
    std::vector<std::array<int32_t, 3>> edges;
    edges.reserve(parent.size());
    for (int32_t t = 0; t < surface.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int32_t a = surface.triangles[size_t(t)][size_t(k)], b = surface.triangles[size_t(t)][size_t((k + 1) % 3)];
            edges.push_back({std::min(a, b), std::max(a, b), 3 * t + k});
        }
    std::sort(edges.begin(), edges.end());
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && edges[j][0] == edges[i][0] && edges[j][1] == edges[i][1]) ++j;
        // Two triangles that run the edge in opposite directions (a consistently oriented
        // neighbour): a triangle turned against its neighbours is a sheet of its own.
        const auto first_end = [&](int32_t corner) { return surface.triangles[size_t(corner / 3)][size_t(corner % 3)]; };
        if (j - i == 2 && first_end(edges[i][2]) != first_end(edges[i + 1][2])) {
            // Corner k of the edge's triangle is at vertex triangles[t][k], corner k+1 at the other end.
            for (const int32_t end : {edges[i][0], edges[i][1]}) {
                auto at = [&](int32_t corner) {
                    const int32_t t = corner / 3, k = corner % 3;
                    return surface.triangles[size_t(t)][size_t(k)] == end ? corner : 3 * t + (k + 1) % 3;
                };
                join(at(edges[i][2]), at(edges[i + 1][2]));
            }
        }
        i = j;
    }
    std::vector<int32_t> fan(parent.size());
    for (size_t i = 0; i < parent.size(); ++i) fan[i] = find(int32_t(i));
    return fan;
}

using Triangles = std::vector<Kernel::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

// The largest distance from `points` to the surface's triangles. With `near` (a box that
// holds every point, grown by a reach r on each side) only the triangles that meet `near`
// are searched: a distance up to r is then the same, a larger one may come out larger.
// (The repaired region is small; trees of the whole input and the whole repaired surface
// cost more than CGAL's local repair itself on 208k triangles.)
double farthest(const std::vector<Vec3>& points, const Surface& s, const CGAL::Bbox_3* near) {
    if (points.empty()) return 0.0;
    Triangles triangles;
    for (const Tri& t : s.triangles) {
        const Point a = to_point(s.vertices[size_t(t[0])]), b = to_point(s.vertices[size_t(t[1])]),
                    c = to_point(s.vertices[size_t(t[2])]);
        if (near && !CGAL::do_overlap(*near, a.bbox() + b.bbox() + c.bbox())) continue;
        triangles.emplace_back(a, b, c);
    }
    if (triangles.empty()) return std::numeric_limits<double>::infinity();
    Tree tree(triangles.begin(), triangles.end());
    tree.accelerate_distance_queries();
    double largest = 0.0;
    for (const Vec3& p : points) largest = std::max(largest, std::sqrt(CGAL::to_double(tree.squared_distance(to_point(p)))));
    return largest;
}

// The intersecting pairs check_intersections finds (smaller triangle first), at most 2^20.
std::set<std::pair<int32_t, int32_t>> intersecting_pairs(const Surface& s, int64_t& count, const Context& context) {
    CheckOptions options;
    options.max_problems = size_t(1) << 20;
    const CheckResult r = check_intersections(s, options, context);
    count = r.problem_count;
    std::set<std::pair<int32_t, int32_t>> pairs;
    for (const CheckProblem& p : r.problems) {
        const int64_t a = p.id("triangle"), b = p.id("other_triangle");
        if (a >= 0 && b >= 0) pairs.insert({int32_t(std::min(a, b)), int32_t(std::max(a, b))});
    }
    return pairs;
}

// CGAL's rounds look for intersecting pairs among the faces of their range only (and the
// faces they add); on the whole mesh each round searched every face (3 spikes through a
// 208k-triangle surface: 4.8 CPU s). The range: the faces of bpm's pairs and those within
// `rings` rings of shared vertices around them, wide enough for the regions CGAL grows
// (by `step` rings in round `step`, up to 6). A pair the range misses can only make the
// repair refuse: the result is checked on the whole surface.
constexpr int repair_rings = 12;

std::vector<FaceIndex> faces_near(const Mesh& mesh, const std::set<std::pair<int32_t, int32_t>>& pairs, int rings) {
    // The mesh was built with face i from input triangle i.
    std::vector<char> in_range(mesh.number_of_faces(), 0);
    std::vector<FaceIndex> range;
    auto add = [&](FaceIndex f) {
        if (f == Mesh::null_face() || in_range[size_t(f)]) return;
        in_range[size_t(f)] = 1;
        range.push_back(f);
    };
    for (const auto& [a, b] : pairs) add(FaceIndex(uint32_t(a))), add(FaceIndex(uint32_t(b)));
    std::vector<char> vertex_seen(mesh.number_of_vertices(), 0);
    size_t ring_begin = 0;  // range[ring_begin, size) is the last ring added
    for (int ring = 0; ring < rings && ring_begin < range.size(); ++ring) {
        const size_t ring_end = range.size();
        for (size_t i = ring_begin; i < ring_end; ++i)
            for (const VertexIndex v : corners(mesh, range[i])) {
                if (vertex_seen[size_t(v)]) continue;
                vertex_seen[size_t(v)] = 1;
                for (const FaceIndex g : CGAL::faces_around_target(mesh.halfedge(v), mesh)) add(g);
            }
        ring_begin = ring_end;
    }
    std::sort(range.begin(), range.end());
    return range;
}

std::string plural(int64_t n, const char* one, const char* many) { return std::to_string(n) + " " + (n == 1 ? one : many); }

}  // namespace

SelfIntersectionRepair repair_self_intersections(Surface& surface, const SelfIntersectionRepairOptions& options,
                                                 const Context& context) {
    SelfIntersectionRepair result;
    if (!(options.max_change >= 0))  // NaN would accept any change
        throw std::invalid_argument("repair_self_intersections: max_change must be a number >= 0, got " +
                                    std::to_string(options.max_change));
    // Bad input is the caller's error, not something to repair (the readers refuse it).
    if (surface.patches.size() != surface.triangles.size())
        throw std::invalid_argument("repair_self_intersections: " + std::to_string(surface.patches.size()) +
                                    " patch ids for " + std::to_string(surface.triangles.size()) + " triangles");
    if (const std::vector<std::string> bad = vertex_data_problems(surface); !bad.empty())
        throw std::invalid_argument("repair_self_intersections: " + bad[0]);
    // Every index and coordinate (validate_surface stops at its first problem, which may be
    // a harmless one ahead of an index Surface_mesh would read out of bounds).
    for (size_t v = 0; v < surface.vertices.size(); ++v)
        for (const double x : surface.vertices[v])
            if (!std::isfinite(x))
                throw std::invalid_argument("repair_self_intersections: vertex " + std::to_string(v) +
                                            " has a coordinate that is not finite");
    for (size_t t = 0; t < surface.triangles.size(); ++t)
        for (const int32_t v : surface.triangles[t])
            if (v < 0 || v >= surface.num_vertices())
                throw std::invalid_argument("repair_self_intersections: triangle " + std::to_string(t) + " has vertex " +
                                            std::to_string(v) + ", out of range [0, " +
                                            std::to_string(surface.num_vertices()) + ")");
    context.report(0.0, "self-intersection repair: finding intersections");
    const std::set<std::pair<int32_t, int32_t>> input_pairs =
        intersecting_pairs(surface, result.intersecting_pairs, Context{nullptr, context.progress});
    result.remaining_pairs = result.intersecting_pairs;
    if (result.intersecting_pairs == 0) return result;
    // Nothing changes unless the result is accepted: on a refusal only the counts before.
    const auto refuse = [&](std::string why) {
        const int64_t pairs = result.intersecting_pairs;
        result = SelfIntersectionRepair{};
        result.intersecting_pairs = result.remaining_pairs = pairs;
        result.refused = std::move(why);
        return result;
    };

    // The CGAL copy, with every element's index in `surface` (-1 for what the repair adds;
    // Surface_mesh resets the properties of a recycled slot). A vertex where several fans
    // of triangles meet only at their tip (a scan's pinched spot) is one mesh vertex per
    // fan: Surface_mesh holds only manifold vertices; the copies map back onto it below.
    Mesh mesh;
    auto vertex_input = mesh.add_property_map<VertexIndex, int32_t>("v:bpm_input", -1).first;
    auto face_input = mesh.add_property_map<FaceIndex, int32_t>("f:bpm_input", -1).first;
    for (int32_t v = 0; v < surface.num_vertices(); ++v) vertex_input[mesh.add_vertex(to_point(surface.vertices[size_t(v)]))] = v;
    const std::vector<int32_t> fan = fan_of_corners(surface);
    std::map<std::pair<int32_t, int32_t>, VertexIndex> fan_copy;  // (vertex, fan) -> its copy, beyond the first fan
    std::vector<int32_t> first_fan(surface.vertices.size(), -1);
    for (int32_t t = 0; t < surface.num_triangles(); ++t) {
        const Tri& tri = surface.triangles[size_t(t)];
        std::array<VertexIndex, 3> c;
        for (int k = 0; k < 3; ++k) {
            const int32_t v = tri[size_t(k)], f = fan[size_t(3 * t + k)];
            if (first_fan[size_t(v)] < 0) first_fan[size_t(v)] = f;
            if (f == first_fan[size_t(v)]) {
                c[size_t(k)] = VertexIndex(uint32_t(v));
            } else {
                auto [at, fresh] = fan_copy.try_emplace({v, f}, Mesh::null_vertex());
                if (fresh) {
                    at->second = mesh.add_vertex(to_point(surface.vertices[size_t(v)]));
                    vertex_input[at->second] = v;
                }
                c[size_t(k)] = at->second;
            }
        }
        const FaceIndex f = mesh.add_face(c[0], c[1], c[2]);
        if (f == Mesh::null_face())  // e.g. a repeated corner or a duplicate triangle
            return refuse("triangle " + std::to_string(t) + " (vertices " + std::to_string(tri[0]) + ", " +
                          std::to_string(tri[1]) + ", " + std::to_string(tri[2]) +
                          ") cannot be joined to its neighbours (a repeated corner, or the same triangle twice?)");
        face_input[f] = t;
    }

    ProgressVisitor visitor;
    visitor.context = &context;
    CGAL::Polygon_mesh_processing::experimental::remove_self_intersections(
        faces_near(mesh, input_pairs, repair_rings), mesh,
        CGAL::parameters::preserve_genus(true).visitor(visitor).filter(PinchedPairs{&mesh, &vertex_input}));
    context.report(0.85, "self-intersection repair: checking the result");
    // CGAL's hole filling gives the vertices inside a replaced region new points but keeps
    // their handles (and so their properties): a vertex away from its input position is
    // new, whatever its handle says. (So is a kept vertex the smoothing moved.)
    for (const VertexIndex v : mesh.vertices())
        if (vertex_input[v] >= 0 && to_vec(mesh.point(v)) != surface.vertices[size_t(vertex_input[v])]) vertex_input[v] = -1;

    // Kept triangles: the input's, still there with the same corners.
    const size_t input_triangles = surface.triangles.size();
    std::vector<char> kept(input_triangles, 0);
    std::vector<FaceIndex> face_of(input_triangles, Mesh::null_face());
    for (const FaceIndex f : mesh.faces()) {
        const int32_t t = face_input[f];
        if (t < 0) continue;
        const auto c = corners(mesh, f);
        if (same_triangle(surface.triangles[size_t(t)], {vertex_input[c[0]], vertex_input[c[1]], vertex_input[c[2]]})) {
            kept[size_t(t)] = 1;
            face_of[size_t(t)] = f;
        }
    }
    std::vector<FaceIndex> added;  // in the mesh's index order
    for (const FaceIndex f : mesh.faces())
        if (face_input[f] < 0 || !kept[size_t(face_input[f])]) added.push_back(f);

    // The repaired surface: kept vertices (in order) that some triangle still uses, then
    // the new ones in the mesh's index order, then the copies of a pinched vertex that the
    // repair moved apart from its first copy.
    Surface repaired;
    const size_t mesh_vertices = mesh.number_of_vertices() + mesh.number_of_removed_vertices();
    std::vector<int32_t> new_index(mesh_vertices, -1);
    std::vector<char> used(mesh_vertices, 0);
    std::vector<std::vector<VertexIndex>> copies(surface.vertices.size());  // in index order
    for (const VertexIndex v : mesh.vertices())
        if (vertex_input[v] >= 0) copies[size_t(vertex_input[v])].push_back(v);
    for (const FaceIndex f : mesh.faces())  // kept and added: every face left
        for (const VertexIndex v : corners(mesh, f)) used[size_t(v)] = 1;
    // Where new vertices take their data from: the nearest input vertex of the replaced
    // region (the corners of the removed triangles and the kept corners of the new ones).
    std::vector<int32_t> region;
    for (const FaceIndex f : added)
        for (const VertexIndex v : corners(mesh, f))
            if (vertex_input[v] >= 0) region.push_back(vertex_input[v]);
    for (size_t t = 0; t < input_triangles; ++t)
        if (!kept[t]) region.insert(region.end(), surface.triangles[t].begin(), surface.triangles[t].end());
    std::sort(region.begin(), region.end());
    region.erase(std::unique(region.begin(), region.end()), region.end());

    std::vector<int32_t> source_of;  // per repaired vertex: the input vertex its data comes from
    for (size_t v = 0; v < surface.vertices.size(); ++v) {
        bool any = false;
        for (const VertexIndex m : copies[v]) {
            if (!used[size_t(m)]) continue;
            if (!any) {  // every copy left is at the input position: one vertex
                new_index[size_t(m)] = repaired.num_vertices();
                repaired.vertices.push_back(surface.vertices[v]);
                source_of.push_back(int32_t(v));
                any = true;
            } else {
                new_index[size_t(m)] = repaired.num_vertices() - 1;
            }
        }
        if (!any) ++result.removed_vertices;
    }
    for (const VertexIndex v : mesh.vertices()) {
        if (vertex_input[v] >= 0 || !used[size_t(v)]) continue;
        const Vec3 p = to_vec(mesh.point(v));
        int32_t nearest = -1;
        double best = std::numeric_limits<double>::infinity();
        for (const int32_t u : region)
            if (const double d = distance(p, surface.vertices[size_t(u)]); d < best) best = d, nearest = u;
        new_index[size_t(v)] = repaired.num_vertices();
        repaired.vertices.push_back(p);
        source_of.push_back(nearest);
        ++result.added_vertices;
    }

    // Triangles: the kept ones in order, then the new ones; the new ones' patches from the
    // kept triangles around each connected group of them.
    const std::set<int32_t> all_patches(surface.patches.begin(), surface.patches.end());
    std::map<FaceIndex, int32_t> added_patch;
    for (const FaceIndex start : added) {
        if (added_patch.count(start)) continue;
        std::vector<FaceIndex> group{start};
        std::set<int32_t> around;
        added_patch[start] = -1;
        for (size_t i = 0; i < group.size(); ++i) {
            for (const auto h : CGAL::halfedges_around_face(mesh.halfedge(group[i]), mesh)) {
                const FaceIndex g = mesh.face(mesh.opposite(h));
                if (g == Mesh::null_face()) continue;
                const int32_t t = face_input[g];
                if (t >= 0 && kept[size_t(t)]) {
                    around.insert(surface.patches[size_t(t)]);
                } else if (!added_patch.count(g)) {
                    added_patch[g] = -1;
                    group.push_back(g);
                }
            }
        }
        if (around.empty()) {
            // Cut off at edges of 3+ triangles or pinched vertices: the kept triangles at
            // its input vertices.
            std::set<int32_t> corners_of_group;
            for (const FaceIndex g : group)
                for (const VertexIndex v : corners(mesh, g))
                    if (vertex_input[v] >= 0) corners_of_group.insert(vertex_input[v]);
            for (size_t t = 0; t < input_triangles; ++t)
                if (kept[t])
                    for (const int32_t v : surface.triangles[t])
                        if (corners_of_group.count(v)) around.insert(surface.patches[t]);
        }
        if (around.empty() && all_patches.size() == 1) around = all_patches;
        if (around.size() != 1)
            return refuse(around.empty()
                              ? std::string("the repair would replace a whole component, whose patch is not known")
                              : "the repair of an intersection would border " + std::to_string(around.size()) +
                                    " patches (it lies where materials meet), so its new triangles have no patch");
        for (const FaceIndex g : group) added_patch[g] = *around.begin();
    }
    std::vector<int32_t> input_of_kept;  // per kept triangle of `repaired`: its index in `surface`
    for (size_t t = 0; t < input_triangles; ++t) {
        if (!kept[t]) {
            ++result.removed_triangles;
            continue;
        }
        // The mesh face's corners, rotated to the input's first corner.
        auto c = corners(mesh, face_of[t]);
        while (vertex_input[c[0]] != surface.triangles[t][0]) std::rotate(c.begin(), c.begin() + 1, c.end());
        repaired.triangles.push_back({new_index[size_t(c[0])], new_index[size_t(c[1])], new_index[size_t(c[2])]});
        repaired.patches.push_back(surface.patches[t]);
        input_of_kept.push_back(int32_t(t));
    }
    for (const FaceIndex f : added) {
        const auto c = corners(mesh, f);
        repaired.triangles.push_back({new_index[size_t(c[0])], new_index[size_t(c[1])], new_index[size_t(c[2])]});
        repaired.patches.push_back(added_patch[f]);
        ++result.added_triangles;
    }
    for (const VertexArray& array : surface.vertex_data) {
        VertexArray out{array.name, array.components, {}};
        out.values.reserve(source_of.size() * size_t(array.components));
        for (const int32_t v : source_of)
            for (int c = 0; c < array.components; ++c)
                out.values.push_back(array.values[size_t(v) * size_t(array.components) + size_t(c)]);
        repaired.vertex_data.push_back(std::move(out));
    }

    // Accepted only if every pair left is one of the input's, between kept triangles: a
    // repair never adds an intersection of its own.
    int64_t left = 0;
    const std::set<std::pair<int32_t, int32_t>> left_pairs = intersecting_pairs(repaired, left, Context{});
    int64_t made = left - int64_t(left_pairs.size());  // beyond the listed ones: not known to be old
    for (const auto& [a, b] : left_pairs) {
        const bool old = size_t(b) < input_of_kept.size() &&
                         input_pairs.count({std::min(input_of_kept[size_t(a)], input_of_kept[size_t(b)]),
                                            std::max(input_of_kept[size_t(a)], input_of_kept[size_t(b)])});
        if (!old) ++made;
    }
    if (made > 0)
        return refuse("the local repairs would make " + plural(made, "new intersecting pair", "new intersecting pairs") +
                      " (" + std::to_string(left) + " in all, of " + std::to_string(result.intersecting_pairs) +
                      " before): too large or tangled for a local repair");
    if (left >= result.intersecting_pairs)
        return refuse("the local repairs left all " + std::to_string(left) + " intersecting pairs");
    result.remaining_pairs = left;

    // How far the surface changed: new points of the repaired surface (vertices and the
    // centroids of new triangles) against the input, removed triangles' corners and
    // centroids against the repaired surface. Near the region first (exact up to the
    // limit); a refusal measures on the whole surfaces, for its message.
    context.report(0.95, "self-intersection repair: measuring the change");
    std::vector<Vec3> new_points, old_points;
    for (size_t v = repaired.vertices.size() - size_t(result.added_vertices); v < repaired.vertices.size(); ++v)
        new_points.push_back(repaired.vertices[v]);
    for (size_t t = repaired.triangles.size() - size_t(result.added_triangles); t < repaired.triangles.size(); ++t) {
        const Tri& tri = repaired.triangles[t];
        new_points.push_back((1.0 / 3.0) * (repaired.vertices[size_t(tri[0])] + repaired.vertices[size_t(tri[1])] +
                                            repaired.vertices[size_t(tri[2])]));
    }
    for (size_t t = 0; t < input_triangles; ++t) {
        if (kept[t]) continue;
        const Tri& tri = surface.triangles[t];
        Vec3 c{0, 0, 0};
        for (int32_t v : tri) {
            old_points.push_back(surface.vertices[size_t(v)]);
            c = c + (1.0 / 3.0) * surface.vertices[size_t(v)];
        }
        old_points.push_back(c);
    }
    const double diagonal = bounding_box_diagonal(surface);
    const double limit = options.max_change * diagonal;
    CGAL::Bbox_3 near;
    for (const auto* points : {&new_points, &old_points})
        for (const Vec3& p : *points) near += to_point(p).bbox();
    const double reach = 1.01 * limit;  // a margin for the rounding of the boxes
    near = CGAL::Bbox_3(near.xmin() - reach, near.ymin() - reach, near.zmin() - reach, near.xmax() + reach,
                        near.ymax() + reach, near.zmax() + reach);
    double largest = std::max(farthest(new_points, surface, &near), farthest(old_points, repaired, &near));
    if (largest > limit)
        largest = std::max(farthest(new_points, surface, nullptr), farthest(old_points, repaired, nullptr));
    result.largest_change = diagonal > 0 ? largest / diagonal : 0.0;
    if (result.largest_change > options.max_change) {
        char text[160];
        std::snprintf(text, sizeof text, "the repair would move the surface by about %.3g of the diagonal, more than "
                                         "max_change = %.3g", result.largest_change, options.max_change);
        return refuse(text);
    }
    const std::string before = describe_topology(compute_topology(surface));
    const std::string after = describe_topology(compute_topology(repaired));
    if (before != after) result.topology_change = before + " -> " + after;
    surface = std::move(repaired);
    context.report(1.0, "self-intersection repair: done");
    return result;
}

}  // namespace bpm
