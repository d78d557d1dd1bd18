// Uniform red refinement with boundary vertices moved to phi (bpm/tet_refine.h).
//
// References: J. Bey, "Simplicial grid refinement: on Freudenthal's algorithm and the
// optimal number of congruence classes", Numer. Math. 85 (2000) 1-29 (the child
// ordering below); Krause & Sander §3.3 (the lambda remedy).

#include "bpm/tet_refine.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "bpm/errors.h"
#include "bpm/phi_evaluation.h"
#include "bpm/predicates.h"
#include "core/number_text.h"
#include "core/tetrahedron_quality.h"
#include "tetmesh/boundary_repair_internal.h"
#include "tetmesh/tet_flips.h"
#include "tetmesh/tetmesh_internal.h"

namespace bpm {

namespace {

using Edge = std::array<int32_t, 2>;

// Bey's children of (x0, x1, x2, x3) in terms of local indices: 0..3 corners, 4 + e the
// midpoint of edge e in the order 01, 02, 03, 12, 13, 23.
enum : int { X0, X1, X2, X3, M01, M02, M03, M12, M13, M23 };
const int kChildren[8][4] = {
    {X0, M01, M02, M03}, {M01, X1, M12, M13}, {M02, M12, X2, M23}, {M03, M13, M23, X3},
    {M01, M02, M03, M13}, {M01, M02, M12, M13}, {M02, M03, M13, M23}, {M02, M12, M13, M23},
};
const int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

// Does child k have the opposite orientation of its parent? Computed once on a reference
// tetrahedron (an affine property of the rule, independent of the geometry).
std::array<bool, 8> child_flips() {
    const Vec3 x[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    Vec3 p[10];
    for (int i = 0; i < 4; ++i) p[i] = x[i];
    for (int e = 0; e < 6; ++e) p[4 + e] = 0.5 * (x[kEdges[e][0]] + x[kEdges[e][1]]);
    const int parent = orient3d(x[0], x[1], x[2], x[3]);
    std::array<bool, 8> flips{};
    for (int k = 0; k < 8; ++k)
        flips[k] = orient3d(p[kChildren[k][0]], p[kChildren[k][1]], p[kChildren[k][2]], p[kChildren[k][3]]) != parent;
    return flips;
}

Edge make_edge(int32_t a, int32_t b) { return a < b ? Edge{a, b} : Edge{b, a}; }

// The smallest unsigned dihedral angle (radians) of Bey's eight children of (p0, p1, p2, p3)
// with the new vertices at the edge midpoints.
double worst_child_angle(const Vec3 (&p)[4]) {
    Vec3 q[10];
    for (int i = 0; i < 4; ++i) q[i] = p[i];
    for (int e = 0; e < 6; ++e) q[4 + e] = 0.5 * (p[kEdges[e][0]] + p[kEdges[e][1]]);
    double worst = 3.14159265358979323846;  // pi, above every angle
    for (int k = 0; k < 8; ++k) {
        double angles[6];
        detail::dihedral_angles(q[kChildren[k][0]], q[kChildren[k][1]], q[kChildren[k][2]], q[kChildren[k][3]],
                                angles);
        for (const double a : angles) worst = std::min(worst, std::abs(a));
    }
    return worst;
}

// Bey's rule keeps all later levels within three congruence classes of the first level's
// children, but which of the octahedron's three inner diagonals the first level cuts
// (here M02 -- M13) depends on the corner order. Reorders `tet` so that its children get
// the largest smallest dihedral angle: the identity, swapping corners 1 and 2 (cuts
// M01 -- M23) or 2 and 3 (cuts M03 -- M12); a swap reverses the orientation, so
// `negative` flips with it. Keeps the first of equal choices. Femur at 1000 vertices: the
// worst child of the level-0 mesh 1.73 degrees in TetGen's order, 3.04 with this choice.
void order_for_best_children(const std::vector<Vec3>& x, Tet& tet, bool& negative) {
    static constexpr int kSwaps[3][2] = {{0, 0}, {1, 2}, {2, 3}};
    double best = -1;
    int best_swap = 0;
    for (int s = 0; s < 3; ++s) {
        Tet t = tet;
        std::swap(t[kSwaps[s][0]], t[kSwaps[s][1]]);
        const Vec3 p[4] = {x[t[0]], x[t[1]], x[t[2]], x[t[3]]};
        const double worst = worst_child_angle(p);
        if (worst > best) {
            best = worst;
            best_swap = s;
        }
    }
    if (best_swap == 0) return;
    std::swap(tet[kSwaps[best_swap][0]], tet[kSwaps[best_swap][1]]);
    negative = !negative;
}

struct State {
    std::vector<Vec3> x;
    std::vector<Tet> tets;               // in Bey order
    std::vector<bool> negative;          // Bey order is negatively oriented
    std::vector<int32_t> regions, ancestor;
    std::vector<Tri> faces;
    std::vector<int32_t> face_triangle;
    std::vector<std::array<Vec3, 3>> face_bary;  // corners' barycentrics in the face's coarse triangle
    std::vector<int32_t> coarse_vertex;
    std::vector<SurfacePoint> param;  // parameter point of each vertex (invalid for interior ones)
};

}  // namespace

TetRefineResult refine_tetmesh(const Parametrization& param, const TetMesh& coarse, const TetRefineOptions& options,
                               const Context& context, TetMesh& out) {
    using clock = std::chrono::steady_clock;
    const auto start = clock::now();
    if (options.levels < 0) throw OptionError("the number of refinement levels must be >= 0");
    detail::check_repair_options(options.repair);
    const double final_tets = double(coarse.tetrahedra.size()) * std::pow(8.0, options.levels);
    if (final_tets > double(std::numeric_limits<int32_t>::max()))
        throw OptionError("refining " + std::to_string(coarse.tetrahedra.size()) + " tetrahedra " +
                          std::to_string(options.levels) + " times gives more than 2^31-1 tetrahedra");
    if (auto problem = find_tetmesh_inconsistency(coarse, param.coarse); !problem.empty())
        throw AlgorithmError("the tetrahedral mesh does not fit the parametrization: " + problem);

    static const std::array<bool, 8> kFlip = child_flips();
    const Surface& S = param.coarse;
    State s;
    s.x = coarse.vertices;
    s.tets = coarse.tetrahedra;
    s.negative.assign(s.tets.size(), false);
    if (options.levels > 0)
        for (size_t t = 0; t < s.tets.size(); ++t) {
            bool negative = false;
            order_for_best_children(s.x, s.tets[t], negative);
            s.negative[t] = negative;
        }
    s.regions = coarse.regions;
    s.ancestor = coarse.tet_ancestor;
    if (s.ancestor.empty()) {
        s.ancestor.resize(s.tets.size());
        for (size_t t = 0; t < s.tets.size(); ++t) s.ancestor[t] = static_cast<int32_t>(t);
    }
    s.faces = coarse.faces;
    s.face_triangle = coarse.face_coarse_triangle;
    s.coarse_vertex = coarse.vertex_coarse_vertex;
    s.param = coarse.vertex_parameter_points;
    // Barycentrics of each face corner in the face's own coarse triangle: at level 0 the
    // faces are the coarse triangles (unit vectors); for a refined input, locate the corner
    // parameter positions in the face's triangle.
    s.face_bary.resize(s.faces.size());
    for (size_t f = 0; f < s.faces.size(); ++f) {
        const int32_t t = s.face_triangle[f];
        for (int c = 0; c < 3; ++c) {
            const int32_t v = s.faces[f][c];
            if (!s.param[v].valid())
                throw AlgorithmError("vertex " + std::to_string(v) + " of boundary face " + std::to_string(f) +
                                     " has no parameter position");
            if (s.param[v].triangle == t) {
                s.face_bary[f][c] = s.param[v].barycentric;
                continue;
            }
            // Same point expressed in triangle t: map through the coarse vertices.
            const Tri& from = S.triangles[s.param[v].triangle];
            const Tri& to = S.triangles[t];
            Vec3 b{0, 0, 0};
            for (int i = 0; i < 3; ++i) {
                if (s.param[v].barycentric[i] == 0) continue;
                int j = -1;
                for (int k = 0; k < 3; ++k)
                    if (to[k] == from[i]) j = k;
                if (j < 0)
                    throw AlgorithmError("boundary vertex " + std::to_string(v) + " is not on coarse triangle " +
                                         std::to_string(t) + " of its face");
                b[j] = s.param[v].barycentric[i];
            }
            s.face_bary[f][c] = b;
        }
    }

    PhiEvaluator phi(param);
    const double diagonal = bounding_box_diagonal(param.original);
    TetRefineResult result;
    // Every boundary vertex v lies on the segment from seg.base[v] (lambda = 1: the edge
    // midpoint x it was created at, or its input position) to seg.target[v] = phi(parameter
    // position) (lambda = 0), at seg.fraction[v] = 1 - lambda. Coarse vertices and input
    // vertices already at phi have fraction 1; an input vertex off S0 (an earlier remedy)
    // starts at 0 and may get closer.
    detail::RepairSegments seg;
    seg.base.assign(s.x.size(), Vec3{0, 0, 0});
    seg.target.assign(s.x.size(), Vec3{0, 0, 0});
    seg.fraction.assign(s.x.size(), 1.0);
    for (size_t v = 0; v < s.x.size(); ++v) {
        if (!s.param[v].valid()) continue;
        seg.base[v] = s.x[v];
        seg.target[v] =
            s.coarse_vertex[v] >= 0 ? s.x[v] : phi.evaluate(s.param[v].triangle, s.param[v].barycentric).position;
        if (seg.target[v] != seg.base[v]) seg.fraction[v] = 0;
    }
    auto off_surface = [&](size_t v) {
        return options.move_to_surface && s.param[v].valid() && seg.fraction[v] < 1 && s.x[v] != seg.target[v];
    };
    std::vector<char> movable;  // interior vertices, for smoothing

    for (int level = 0; level < options.levels; ++level) {
        const double base_progress = double(level) / options.levels;
        context.report(base_progress, "red refinement, level " + std::to_string(level + 1));
        // 1. Edges and their midpoints.
        std::vector<Edge> edges;
        edges.reserve(s.tets.size() * 7);
        for (const Tet& t : s.tets)
            for (const auto& e : kEdges) edges.push_back(make_edge(t[e[0]], t[e[1]]));
        std::sort(edges.begin(), edges.end());
        edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
        const int32_t nv_old = static_cast<int32_t>(s.x.size());
        if (double(nv_old) + double(edges.size()) > double(std::numeric_limits<int32_t>::max()))
            throw OptionError("refinement gives more than 2^31-1 vertices");
        auto midpoint = [&](int32_t a, int32_t b) {
            const Edge e = make_edge(a, b);
            return nv_old + static_cast<int32_t>(std::lower_bound(edges.begin(), edges.end(), e) - edges.begin());
        };
        const size_t nv = nv_old + edges.size();
        std::vector<Vec3> flat(edges.size());
        for (size_t e = 0; e < edges.size(); ++e) flat[e] = 0.5 * (s.x[edges[e][0]] + s.x[edges[e][1]]);
        s.x.resize(nv);
        for (size_t e = 0; e < edges.size(); ++e) s.x[nv_old + e] = flat[e];
        s.coarse_vertex.resize(nv, -1);
        s.param.resize(nv);

        // 2. Faces on S: 1 -> 4, and the parameter positions of the new boundary vertices.
        std::vector<Tri> faces;
        std::vector<int32_t> face_triangle;
        std::vector<std::array<Vec3, 3>> face_bary;
        faces.reserve(4 * s.faces.size());
        face_triangle.reserve(4 * s.faces.size());
        face_bary.reserve(4 * s.faces.size());
        for (size_t f = 0; f < s.faces.size(); ++f) {
            const Tri& F = s.faces[f];
            const auto& B = s.face_bary[f];
            const int32_t t = s.face_triangle[f];
            const int32_t m[3] = {midpoint(F[0], F[1]), midpoint(F[1], F[2]), midpoint(F[2], F[0])};
            Vec3 mb[3];
            for (int k = 0; k < 3; ++k) {
                const Vec3& a = B[k];
                const Vec3& b = B[(k + 1) % 3];
                mb[k] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
                if (!s.param[m[k]].valid()) s.param[m[k]] = {t, mb[k]};
            }
            const Tri children[4] = {{F[0], m[0], m[2]}, {m[0], F[1], m[1]}, {m[2], m[1], F[2]}, {m[0], m[1], m[2]}};
            const std::array<Vec3, 3> cb[4] = {
                {B[0], mb[0], mb[2]}, {mb[0], B[1], mb[1]}, {mb[2], mb[1], B[2]}, {mb[0], mb[1], mb[2]}};
            for (int k = 0; k < 4; ++k) {
                faces.push_back(children[k]);
                face_triangle.push_back(t);
                face_bary.push_back(cb[k]);
            }
        }
        s.faces = std::move(faces);
        s.face_triangle = std::move(face_triangle);
        s.face_bary = std::move(face_bary);

        // 3. Tetrahedra: 1 -> 8 by Bey's rule.
        std::vector<Tet> tets;
        std::vector<bool> negative;
        std::vector<int32_t> regions, ancestor;
        tets.reserve(8 * s.tets.size());
        negative.reserve(8 * s.tets.size());
        regions.reserve(8 * s.tets.size());
        ancestor.reserve(8 * s.tets.size());
        for (size_t t = 0; t < s.tets.size(); ++t) {
            const Tet& T = s.tets[t];
            int32_t local[10];
            for (int i = 0; i < 4; ++i) local[i] = T[i];
            for (int e = 0; e < 6; ++e) local[4 + e] = midpoint(T[kEdges[e][0]], T[kEdges[e][1]]);
            for (int k = 0; k < 8; ++k) {
                tets.push_back({local[kChildren[k][0]], local[kChildren[k][1]], local[kChildren[k][2]],
                                local[kChildren[k][3]]});
                negative.push_back(s.negative[t] != kFlip[k]);
                regions.push_back(s.regions[t]);
                ancestor.push_back(s.ancestor[t]);
            }
        }
        s.tets = std::move(tets);
        s.negative = std::move(negative);
        s.regions = std::move(regions);
        s.ancestor = std::move(ancestor);

        // 4. Move the boundary vertices towards phi (the §3.3 remedy where a tetrahedron
        //    would invert or collapse), in steps, smoothing the interior after each.
        TetRefineLevel info;
        const std::vector<Vec3> reference = s.x;  // plain red refinement: new vertices at the midpoints x
        seg.base.resize(nv);
        seg.target.resize(nv);
        seg.fraction.resize(nv, 1.0);
        std::vector<int32_t> fresh;  // new boundary vertices
        for (size_t v = nv_old; v < nv; ++v)
            if (s.param[v].valid()) fresh.push_back(static_cast<int32_t>(v));
        info.new_boundary_vertices = static_cast<int64_t>(fresh.size());
        {
            std::vector<PhiSample> samples;
            std::vector<int32_t> triangles(fresh.size());
            std::vector<Vec3> barycentrics(fresh.size());
            for (size_t i = 0; i < fresh.size(); ++i) {
                triangles[i] = s.param[fresh[i]].triangle;
                barycentrics[i] = s.param[fresh[i]].barycentric;
            }
            phi.evaluate(triangles, barycentrics, samples, 1);
            for (size_t i = 0; i < fresh.size(); ++i) {
                const int32_t v = fresh[i];
                seg.base[v] = s.x[v];
                seg.target[v] = samples[i].position;
                seg.fraction[v] = seg.target[v] == seg.base[v] ? 1.0 : 0.0;
            }
        }
        // Vertices that move: the new boundary vertices and every older one still off S0.
        std::vector<int32_t> movers;
        if (options.move_to_surface)
            for (size_t v = 0; v < nv; ++v)
                if (s.param[v].valid() && seg.fraction[v] < 1) movers.push_back(static_cast<int32_t>(v));
        movable.assign(nv, 0);
        for (size_t v = 0; v < nv; ++v) movable[v] = !s.param[v].valid();
        const double span = 1.0 / options.levels;
        info.smoothing_seconds = detail::repair_boundary_vertices(
            s.x, s.tets, s.negative, reference, movers, movable, seg, options.repair, context,
            base_progress + 0.3 * span, 0.6 * span, "level " + std::to_string(level + 1) + ": boundary vertices towards phi");

        if (options.flip) {
            std::vector<char> created;
            const detail::TetFlipResult fr = detail::flip_tetrahedra(s.x, s.tets, &s.negative, s.regions, &s.ancestor,
                                                                     s.faces, {}, &created);
            info.flips = fr.flips_23 + fr.edge_removals;
            info.flip_seconds = fr.seconds;
            // The next level cuts the new tetrahedra too: give them the corner order with the
            // best children, as the input's got.
            if (level + 1 < options.levels)
                for (size_t t = 0; t < s.tets.size(); ++t)
                    if (created[t]) {
                        bool negative = s.negative[t];
                        order_for_best_children(s.x, s.tets[t], negative);
                        s.negative[t] = negative;
                    }
        }
        for (int32_t v : fresh)
            if (off_surface(v)) {
                ++info.remedied_vertices;
                if (seg.fraction[v] == 0) ++info.flat_vertices;
            }
        for (size_t v = 0; v < nv; ++v) {
            if (off_surface(v)) {
                ++info.off_surface_vertices;
                info.max_remedy_distance = std::max(info.max_remedy_distance, distance(s.x[v], seg.target[v]));
            }
            if (movable[v] && s.x[v] != reference[v]) ++info.smoothed_vertices;
        }
        {
            const detail::TetQuality q = detail::tet_quality(s.x, s.tets, s.negative);
            info.min_dihedral_degrees = q.min_dihedral_degrees;
            info.below_1_degree = q.below_1_degree;
            info.below_5_degrees = q.below_5_degrees;
            info.below_10_degrees = q.below_10_degrees;
        }
        info.vertices = static_cast<int64_t>(s.x.size());
        info.tetrahedra = static_cast<int64_t>(s.tets.size());
        result.levels.push_back(info);
        context.debug("level " + std::to_string(level + 1) + ": " + std::to_string(info.tetrahedra) + " tetrahedra, " +
                      std::to_string(info.new_boundary_vertices) + " new boundary vertices, " +
                      std::to_string(info.off_surface_vertices) + " kept off the surface, " +
                      std::to_string(info.flips) + " flips, min dihedral angle " +
                      detail::three_digit_text(info.min_dihedral_degrees) + " degrees");
    }

    // Vertices off S0 at the end (this call's remedies, and the input's that stayed).
    for (size_t v = 0; v < s.x.size(); ++v)
        if (off_surface(v)) {
            ++result.remedied_vertices;
            result.max_remedy_distance = std::max(result.max_remedy_distance, distance(s.x[v], seg.target[v]));
            result.min_phi_fraction = std::min(result.min_phi_fraction, seg.fraction[v]);
        }
    if (!options.move_to_surface) result.min_phi_fraction = options.levels > 0 ? 0 : 1;
    result.max_remedy_distance_relative = diagonal > 0 ? result.max_remedy_distance / diagonal : 0;

    // Output, every tetrahedron positively oriented.
    out = TetMesh{};
    out.vertices = std::move(s.x);
    out.tetrahedra = std::move(s.tets);
    for (size_t t = 0; t < out.tetrahedra.size(); ++t)
        if (s.negative[t]) std::swap(out.tetrahedra[t][2], out.tetrahedra[t][3]);
    out.regions = std::move(s.regions);
    out.faces = std::move(s.faces);
    out.face_coarse_triangle = std::move(s.face_triangle);
    out.face_patches.resize(out.faces.size());
    for (size_t f = 0; f < out.faces.size(); ++f) out.face_patches[f] = S.patches[out.face_coarse_triangle[f]];
    out.vertex_coarse_vertex = std::move(s.coarse_vertex);
    out.vertex_parameter_points = std::move(s.param);
    out.level = coarse.level + options.levels;
    out.tet_ancestor = options.levels > 0 || !coarse.tet_ancestor.empty() ? std::move(s.ancestor) : std::vector<int32_t>();
    // Refinement keeps every region, so it keeps their materials.
    out.region_material = coarse.region_material;
    out.material_names = coarse.material_names;

    result.vertices = out.num_vertices();
    result.tetrahedra = out.num_tetrahedra();
    result.faces = static_cast<int64_t>(out.faces.size());
    for (const SurfacePoint& p : out.vertex_parameter_points) result.boundary_vertices += p.valid();
    for (const Tet& t : out.tetrahedra)
        if (orient3d(out.vertices[t[0]], out.vertices[t[1]], out.vertices[t[2]], out.vertices[t[3]]) != 1)
            ++result.inverted;
    result.seconds = std::chrono::duration<double>(clock::now() - start).count();
    context.report(1.0, "refinement done");
    return result;
}

std::string describe_level(const TetRefineLevel& l, size_t number) {
    char line[512];
    std::snprintf(line, sizeof line,
                  "level %zu: %lld tetrahedra, min dihedral angle %.3g degrees, %lld/%lld/%lld below 1/5/10 degrees, "
                  "%lld boundary vertices off the surface (max distance %.3g), %lld interior vertices smoothed",
                  number, (long long)l.tetrahedra, l.min_dihedral_degrees, (long long)l.below_1_degree,
                  (long long)l.below_5_degrees, (long long)l.below_10_degrees, (long long)l.off_surface_vertices,
                  l.max_remedy_distance, (long long)l.smoothed_vertices);
    return line;
}

}  // namespace bpm
