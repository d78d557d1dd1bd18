// repair_self_intersections (bpm/self_intersection_repair.h): bpm's exact check finds
// whether there is anything to repair and whether the repair helped; CGAL's
// experimental local repair does the surgery on a Surface_mesh copy, and the result is
// mapped back onto the Surface (order, patches, vertex data) only if it is better.
// The one translation unit of libbpm with CGAL's Polygon_mesh_processing repair code
// (it takes minutes to compile).
#include "bpm/self_intersection_repair.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/repair_self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <limits>
#include <map>
#include <set>
#include <vector>

#include "bpm/check.h"
#include "bpm/predicates.h"
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
// copy half-repaired, never the caller's surface.
struct ProgressVisitor : CGAL::Polygon_mesh_processing::experimental::Remove_self_intersection_default_visitor<Mesh> {
    const Context* context = nullptr;
    int round = 0;
    void start_iteration() {
        ++round;
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
// are joined through edges of exactly two triangles at that vertex share a fan id (the
// smallest corner of the fan). A vertex with more than one fan is pinched.
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
        if (j - i == 2) {
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

template <class Tree>
double distance_to(const Tree& tree, const Point& p) {
    return std::sqrt(CGAL::to_double(tree.squared_distance(p)));
}

using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

}  // namespace

SelfIntersectionRepair repair_self_intersections(Surface& surface, const Context& context) {
    SelfIntersectionRepair result;
    context.report(0.0, "self-intersection repair: finding intersections");
    CheckOptions check_options;
    check_options.max_problems = 1;
    result.intersecting_pairs = result.remaining_pairs = check_intersections(surface, check_options).problem_count;
    if (result.intersecting_pairs == 0) return result;

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
        if (f == Mesh::null_face()) {
            result.refused = "triangle " + std::to_string(t) + " (vertices " + std::to_string(tri[0]) + ", " +
                             std::to_string(tri[1]) + ", " + std::to_string(tri[2]) +
                             ") shares an edge with two others or turns against a neighbour; the repair needs an "
                             "orientable surface whose edges have one or two triangles";
            return result;
        }
        face_input[f] = t;
    }
    const Mesh input_mesh = mesh;  // for the distances of the change

    ProgressVisitor visitor;
    visitor.context = &context;
    CGAL::Polygon_mesh_processing::experimental::remove_self_intersections(
        mesh, CGAL::parameters::preserve_genus(true).visitor(visitor).filter(PinchedPairs{&mesh, &vertex_input}));
    context.report(0.85, "self-intersection repair: checking the result");

    // Kept triangles: the input's, still there with the same corners.
    const size_t input_triangles = surface.triangles.size();
    std::vector<char> kept(input_triangles, 0);
    for (const FaceIndex f : mesh.faces()) {
        const int32_t t = face_input[f];
        if (t < 0) continue;
        const auto c = corners(mesh, f);
        if (same_triangle(surface.triangles[size_t(t)], {vertex_input[c[0]], vertex_input[c[1]], vertex_input[c[2]]}))
            kept[size_t(t)] = 1;
    }
    std::vector<FaceIndex> added;  // in the mesh's index order
    for (const FaceIndex f : mesh.faces()) {
        const int32_t t = face_input[f];
        if (t < 0 || !kept[size_t(t)]) added.push_back(f);
    }

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
    std::vector<FaceIndex> face_of(input_triangles, Mesh::null_face());
    for (const FaceIndex f : mesh.faces())
        if (face_input[f] >= 0 && kept[size_t(face_input[f])]) face_of[size_t(face_input[f])] = f;
    for (const FaceIndex f : mesh.faces())  // kept and added: every face left
        for (const VertexIndex v : corners(mesh, f)) used[size_t(v)] = 1;
    std::vector<int32_t> rim;  // kept vertices of new triangles: where new vertices take their data from
    for (const FaceIndex f : added)
        for (const VertexIndex v : corners(mesh, f))
            if (vertex_input[v] >= 0) rim.push_back(vertex_input[v]);
    std::sort(rim.begin(), rim.end());
    rim.erase(std::unique(rim.begin(), rim.end()), rim.end());

    std::vector<int32_t> source_of;  // per repaired vertex: the input vertex its data comes from
    std::vector<VertexIndex> moved_apart;
    for (size_t v = 0; v < surface.vertices.size(); ++v) {
        VertexIndex first = Mesh::null_vertex();
        for (const VertexIndex m : copies[v]) {
            if (!used[size_t(m)]) continue;
            if (first == Mesh::null_vertex()) {
                first = m;
                const Vec3 now = to_vec(mesh.point(m));
                if (now != surface.vertices[v]) ++result.moved_vertices;
                new_index[size_t(m)] = repaired.num_vertices();
                repaired.vertices.push_back(now);
                source_of.push_back(int32_t(v));
            } else if (mesh.point(m) == mesh.point(first)) {
                new_index[size_t(m)] = new_index[size_t(first)];
            } else {
                moved_apart.push_back(m);
            }
        }
        if (first == Mesh::null_vertex()) ++result.removed_vertices;
    }
    for (const VertexIndex v : mesh.vertices()) {
        if (vertex_input[v] >= 0 || !used[size_t(v)]) continue;
        const Vec3 p = to_vec(mesh.point(v));
        int32_t nearest = -1;
        double best = std::numeric_limits<double>::infinity();
        // The rim, or every kept vertex if the repair replaced a whole component.
        auto consider = [&](int32_t u) {
            const double d = distance(p, surface.vertices[size_t(u)]);
            if (d < best) best = d, nearest = u;
        };
        if (!rim.empty())
            for (int32_t u : rim) consider(u);
        else
            for (int32_t u = 0; u < surface.num_vertices(); ++u) consider(u);
        new_index[size_t(v)] = repaired.num_vertices();
        repaired.vertices.push_back(p);
        source_of.push_back(nearest);
        ++result.added_vertices;
    }
    for (const VertexIndex m : moved_apart) {
        new_index[size_t(m)] = repaired.num_vertices();
        repaired.vertices.push_back(to_vec(mesh.point(m)));
        source_of.push_back(vertex_input[m]);
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
        if (around.empty() && all_patches.size() == 1) around = all_patches;
        if (around.size() != 1) {
            const int64_t pairs = result.intersecting_pairs;
            result = SelfIntersectionRepair{};
            result.intersecting_pairs = result.remaining_pairs = pairs;
            result.refused = around.empty()
                                 ? std::string("the repair would replace a whole component, whose patch is not known")
                                 : "the repair of an intersection would border " + std::to_string(around.size()) +
                                       " patches (it lies where materials meet), so its new triangles have no patch";
            return result;
        }
        for (const FaceIndex g : group) added_patch[g] = *around.begin();
    }
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

    result.remaining_pairs = check_intersections(repaired, check_options).problem_count;
    if (result.remaining_pairs >= result.intersecting_pairs) {
        const int64_t before = result.intersecting_pairs, after = result.remaining_pairs;
        result = SelfIntersectionRepair{};
        result.intersecting_pairs = result.remaining_pairs = before;
        result.refused = "the local repairs left " + std::to_string(after) + " of the " + std::to_string(before) +
                         " intersecting pairs (too large or tangled for a local repair)";
        return result;
    }

    // How far the surface changed: changed points of the repaired surface against the
    // input, removed triangles of the input against the repaired surface.
    context.report(0.95, "self-intersection repair: measuring the change");
    double largest = 0.0;
    {
        Tree to_input(faces(input_mesh).first, faces(input_mesh).second, input_mesh);
        to_input.accelerate_distance_queries();
        for (size_t v = 0; v < repaired.vertices.size(); ++v) {
            const int32_t s = source_of[v];
            const bool is_new = v >= repaired.vertices.size() - size_t(result.added_vertices);
            if (is_new || repaired.vertices[v] != surface.vertices[size_t(s)])
                largest = std::max(largest, distance_to(to_input, to_point(repaired.vertices[v])));
        }
        for (size_t t = repaired.triangles.size() - size_t(result.added_triangles); t < repaired.triangles.size(); ++t) {
            const Tri& tri = repaired.triangles[t];
            const Vec3 c = (1.0 / 3.0) * (repaired.vertices[size_t(tri[0])] + repaired.vertices[size_t(tri[1])] +
                                          repaired.vertices[size_t(tri[2])]);
            largest = std::max(largest, distance_to(to_input, to_point(c)));
        }
    }
    {
        Tree to_repaired(faces(mesh).first, faces(mesh).second, mesh);
        to_repaired.accelerate_distance_queries();
        for (size_t t = 0; t < input_triangles; ++t) {
            if (kept[t]) continue;
            const Tri& tri = surface.triangles[t];
            Vec3 c{0, 0, 0};
            for (int32_t v : tri) {
                largest = std::max(largest, distance_to(to_repaired, to_point(surface.vertices[size_t(v)])));
                c = c + (1.0 / 3.0) * surface.vertices[size_t(v)];
            }
            largest = std::max(largest, distance_to(to_repaired, to_point(c)));
        }
    }
    const double diagonal = bounding_box_diagonal(surface);
    result.largest_change = diagonal > 0 ? largest / diagonal : 0.0;
    surface = std::move(repaired);
    context.report(1.0, "self-intersection repair: done");
    return result;
}

}  // namespace bpm
