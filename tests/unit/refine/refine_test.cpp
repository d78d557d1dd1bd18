// Refinement through phi: K = 0 is the coarse surface, new vertices lie on S0, the
// refined surfaces are conforming and free of self-intersections, adaptive refinement
// meets its tolerance, and the refined .bpm is a valid parametrization.

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "bpm/bpm_file.h"
#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/phi_evaluation.h"
#include "bpm/predicates.h"
#include "bpm/refine.h"
#include "bpm/simplify.h"
#include "bpm/smooth.h"
#include "bpm/surface_io.h"
#include "fixtures_phi.h"
#include "fixtures_surfaces.h"
#include "test_support.h"

using namespace bpm;

namespace {

using test_support::check_text;

struct Case {
    std::string name;
    Parametrization param;
};

std::vector<Case> cases(bool with_real = true) {
    std::vector<Case> c;
    c.push_back({"octahedron", test::make_subdivided_octahedron(3)});
    c.push_back({"height field", test::make_height_field(12, 3, test::default_height)});
    c.push_back({"refined cube", fixtures::refined_parametrization(fixtures::cube())});
    if (with_real) {
        if (const Parametrization* f = test_support::simplified_femur()) c.push_back({"femur", *f});
        else WARN("femur.off missing: real-mesh cases skipped");
    }
    return c;
}

// Largest distance of a refined vertex from the point its original triangle and
// barycentric coordinates describe, relative to the diagonal of S0.
double max_off_surface(const Parametrization& p, const RefinedSurface& r) {
    double worst = 0;
    for (size_t v = 0; v < r.surface.vertices.size(); ++v) {
        const Tri& t = p.original.triangles[size_t(r.vertex_original_triangle[v])];
        const Vec3 x = barycentric_point(p.original.vertices[size_t(t[0])], p.original.vertices[size_t(t[1])],
                                         p.original.vertices[size_t(t[2])], r.vertex_original_barycentric[v]);
        worst = std::max(worst, distance(x, r.surface.vertices[v]));
    }
    return worst / bounding_box_diagonal(p.original);
}

// Conforming: every directed edge appears once, and every undirected edge has as many
// triangles as the same edge... checked as: the number of triangles per undirected edge
// is the same as for the coarse edge it lies on (1 on boundaries, 2 inside, more on
// non-manifold edges) -- here simply: no edge is used by exactly one triangle unless the
// coarse surface has boundary edges.
int64_t single_edges(const Surface& s) {
    std::map<std::pair<int32_t, int32_t>, int> uses;
    for (const Tri& t : s.triangles)
        for (int k = 0; k < 3; ++k) {
            int32_t a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
            if (a > b) std::swap(a, b);
            ++uses[{a, b}];
        }
    int64_t n = 0;
    for (auto& [e, u] : uses) n += u == 1;
    return n;
}

// Moves nodes that are not coarse corners by one unit in the last place: interior nodes
// towards corner 1, and of the copies of a node on a coarse edge only the one in the
// odd-numbered coarse triangle (its coordinate at the end with the larger vertex id
// goes up), so that the copies disagree by an ulp, as the simplifier's output does for
// fandisk. A node exactly on a refined vertex or edge (the height field with n = 4 m
// puts original vertices on the refined vertices of K = 2) ends up a rounding error off
// it. Pieces stay positively oriented (they are far larger than an ulp).
Parametrization nudged(Parametrization p) {
    for (int32_t t = 0; t < p.coarse.num_triangles(); ++t) {
        const Tri& ct = p.coarse.triangles[size_t(t)];
        for (int64_t n = p.node_offsets[size_t(t)]; n < p.node_offsets[size_t(t) + 1]; ++n) {
            if (p.node_kind[size_t(n)] == NodeKind::CoarseCorner) continue;
            Vec3& b = p.node_barycentric[size_t(n)];
            int zero = -1;
            for (int k = 0; k < 3; ++k)
                if (b[size_t(k)] == 0) zero = k;
            if (zero < 0) {
                b[1] = std::nextafter(b[1], 2.0);
                b[0] = std::nextafter(b[0], -1.0);
            } else if (t % 2 == 1) {
                const int i = (zero + 1) % 3, j = (zero + 2) % 3;
                const int hi = ct[size_t(i)] > ct[size_t(j)] ? i : j;
                b[size_t(hi)] = std::nextafter(b[size_t(hi)], 2.0);
            }
        }
    }
    return p;
}

}  // namespace

TEST_CASE("refined .bpm is valid when nodes of phi are a rounding error off refined edges", "[refine]") {
    // Without snapping such nodes (and treating crossings a rounding error apart as one
    // point), the overlay has slivers ~1e-17 wide and refined_parametrization throws.
    for (const auto& [n, m] : {std::pair<int, int>{8, 2}, {16, 2}}) {
        const Parametrization exact = test::make_height_field(n, m, test::default_height);
        const Parametrization p = nudged(exact);
        REQUIRE(p.node_barycentric != exact.node_barycentric);
        test_support::require_valid_parametrization(p);
        for (int levels : {1, 2, 3}) {
            INFO("grid " << n << " / " << m << ", levels " << levels);
            RefinedSurface r;
            RefineOptions o;
            o.levels = levels;
            refine(p, o, Context{}, r);
            const Parametrization once = refined_parametrization(p, r);
            test_support::require_valid_parametrization(once);
            // Refinement continues on the refined file (its phi has thin pieces of its own).
            RefinedSurface r2;
            RefineOptions o2;
            o2.levels = 1;
            refine(once, o2, Context{}, r2);
            test_support::require_valid_parametrization(refined_parametrization(once, r2));
        }
    }
}

TEST_CASE("refine with 0 levels reproduces the coarse surface exactly", "[refine]") {
    for (const Case& c : cases()) {
        INFO(c.name);
        RefinedSurface r;
        RefineOptions o;
        o.levels = 0;
        refine(c.param, o, Context{}, r);
        CHECK(r.surface.vertices == c.param.coarse.vertices);
        CHECK(r.surface.triangles == c.param.coarse.triangles);
        CHECK(r.surface.patches == c.param.coarse.patches);
    }
}

TEST_CASE("refine rejects missing or out-of-range options", "[refine]") {
    const Parametrization p = test::make_subdivided_octahedron(1);
    RefinedSurface r;
    CHECK_THROWS_AS(refine(p, RefineOptions{}, Context{}, r), OptionError);
    RefineOptions o;
    o.levels = 11;
    CHECK_THROWS_AS(refine(p, o, Context{}, r), OptionError);
}

TEST_CASE("uniformly refined vertices lie on the original surface and the mesh is conforming", "[refine]") {
    for (const Case& c : cases()) {
        for (int levels : {1, 2, 3}) {
            INFO(c.name << " levels " << levels);
            RefinedSurface r;
            RefineOptions o;
            o.levels = levels;
            const RefineResult res = refine(c.param, o, Context{}, r);
            CHECK(res.triangles == c.param.coarse.num_triangles() * (int64_t(1) << (2 * levels)));
            CHECK(max_off_surface(c.param, r) < 1e-12);
            CHECK(single_edges(r.surface) == single_edges(c.param.coarse) * (int64_t(1) << levels));
            CHECK(validate_surface(r.surface).empty());
        }
    }
}

TEST_CASE("refined synthetic surfaces do not intersect themselves", "[refine]") {
    for (const Case& c : cases(false)) {
        INFO(c.name);
        RefinedSurface r;
        RefineOptions o;
        o.levels = 2;
        refine(c.param, o, Context{}, r);
        const CheckResult res = check_intersections(r.surface);
        INFO(check_text(res));
        CHECK(res.passed);
    }
}

TEST_CASE("adaptive refinement meets its tolerance and is conforming", "[refine]") {
    for (const Case& c : cases()) {
        for (double tolerance : {1e-2, 2e-3}) {
            INFO(c.name << " tolerance " << tolerance);
            RefinedSurface r;
            RefineOptions o;
            o.tolerance = tolerance;
            o.max_level = 8;
            const RefineResult res = refine(c.param, o, Context{}, r);
            INFO(res.triangles << " triangles, level " << res.max_level << ", error " << res.max_estimated_error);
            // Within the tolerance, or the triangles that could not get there at max_level are
            // counted (femur at 10 %: 3 at 0.002, where phi squeezes a fold; the sampled
            // estimate used to miss them).
            if (res.triangles_at_max_level_above_tolerance == 0) CHECK(res.max_estimated_error <= tolerance);
            else CHECK(res.max_level == o.max_level);
            CHECK(max_off_surface(c.param, r) < 1e-12);
            CHECK(single_edges(r.surface) >= single_edges(c.param.coarse));
            CHECK(validate_surface(r.surface).empty());
            // No hanging nodes: the number of single edges equals that of the boundary only.
            if (single_edges(c.param.coarse) == 0) CHECK(single_edges(r.surface) == 0);
        }
    }
}

TEST_CASE("the refined parametrization is valid", "[refine]") {
    for (const Case& c : cases()) {
        for (int levels : {0, 1, 2}) {
            INFO(c.name << " levels " << levels);
            RefinedSurface r;
            RefineOptions o;
            o.levels = levels;
            refine(c.param, o, Context{}, r);
            const Parametrization p = refined_parametrization(c.param, r);
            CHECK(p.coarse.triangles == r.surface.triangles);
            test_support::require_valid_parametrization(p);
            // Round trip through the file format.
            const BpmFile back = read_bpm_from_memory(write_bpm_to_memory(BpmFile{p, {}, ""}), "refined");
            CHECK(back.param.num_pieces() == p.num_pieces());
        }
    }
}

TEST_CASE("adaptively refined parametrization is valid", "[refine]") {
    for (const Case& c : cases()) {
        INFO(c.name);
        RefinedSurface r;
        RefineOptions o;
        o.tolerance = 3e-3;
        refine(c.param, o, Context{}, r);
        const Parametrization p = refined_parametrization(c.param, r);
        const CheckResult format = check_format(p);
        INFO(check_text(format));
        REQUIRE(format.passed);
        const CheckResult bij = check_bijectivity(p);
        INFO(check_text(bij));
        CHECK(bij.passed);
    }
}

TEST_CASE("normals of the original surface are carried onto refined vertices", "[refine]") {
    const Parametrization p = test::make_subdivided_octahedron(2, 0.0);  // flat faces: normals exact per face
    RefinedSurface r;
    RefineOptions o;
    o.levels = 2;
    refine(p, o, Context{}, r);
    std::vector<double> ones(p.original.vertices.size(), 1.0);
    const std::vector<double> one = transfer_vertex_data(r, p.original, ones, 1);
    for (double x : one) CHECK(x == Approx(1.0));
    std::vector<double> xyz;
    for (const Vec3& x : p.original.vertices) xyz.insert(xyz.end(), x.begin(), x.end());
    const std::vector<double> pos = transfer_vertex_data(r, p.original, xyz, 3);
    for (size_t v = 0; v < r.surface.vertices.size(); ++v)
        for (int k = 0; k < 3; ++k) CHECK(pos[3 * v + size_t(k)] == Approx(r.surface.vertices[v][size_t(k)]).margin(1e-12));
    CHECK_THROWS_AS(transfer_vertex_data(r, p.original, std::vector<double>(3, 0.0), 1), std::invalid_argument);
    const std::vector<Vec3> n = vertex_normals(p.original);
    for (const Vec3& x : n) CHECK(norm(x) == Approx(1.0));
}

TEST_CASE("refined .bpm of two cubes sharing a face passes every check", "[refine][multimaterial]") {
    // Two materials (three sheets along the shared square's border), simplified to 5 %.
    // A piece edge almost parallel to a refined midline crossed it at positions 7e-11
    // apart in the two refined triangles of the midline (each computed the crossing from
    // its own corner order): the bijectivity check failed (exit 5 from bpm-refine).
    const Surface s = fixtures::two_cubes(16);
    SimplifyOptions so;
    so.target_ratio = 0.05;
    Parametrization coarse;
    simplify(s, so, Context{}, coarse);
    for (int levels : {1, 2}) {
        INFO("levels " << levels);
        RefinedSurface r;
        RefineOptions o;
        o.levels = levels;
        refine(coarse, o, Context{}, r);
        const Parametrization p = refined_parametrization(coarse, r);
        test_support::require_valid_parametrization(p);
        const CheckResult intersections = check_intersections(p.coarse);
        INFO(check_text(intersections));
        CHECK(intersections.passed);
    }
}

TEST_CASE("refined femur does not intersect itself: new vertices held back from phi", "[refine][remedy][real]") {
    // Femur at 10 %, refined once through phi: 18 new vertices at phi made intersecting
    // triangle pairs (bpm-check of the refined .bpm failed); held back towards the coarse
    // surface they do not, and the refined .bpm passes all four checks.
    const Parametrization* femur = test_support::simplified_femur();
    if (!femur) {
        WARN("missing femur.off");
        return;
    }
    const double diagonal = bounding_box_diagonal(femur->original);
    for (int levels : {1, 2}) {
        INFO("levels " << levels);
        RefineOptions o;
        o.levels = levels;
        RefinedSurface at_phi;
        refine(*femur, o, Context{}, at_phi);
        CHECK_FALSE(check_intersections(at_phi.surface).passed);  // what the remedy is for
        for (double f : at_phi.vertex_phi_fraction) CHECK(f == 1.0);

        o.prevent_intersections = true;
        RefinedSurface r;
        const RefineResult result = refine(*femur, o, Context{}, r);
        CHECK(result.held_back_vertices > 0);
        CHECK(result.max_held_back > 0);
        CHECK(result.max_held_back < 0.01);
        const CheckResult intersections = check_intersections(r.surface);
        INFO(check_text(intersections));
        CHECK(intersections.passed);
        // Held-back vertices are on the segment from their coarse point to phi; the others at phi.
        int64_t held = 0;
        double farthest = 0;
        for (size_t v = 0; v < r.surface.vertices.size(); ++v) {
            if (r.vertex_phi_fraction[v] == 1.0) {
                CHECK(r.surface.vertices[v] == at_phi.surface.vertices[v]);
                continue;
            }
            ++held;
            farthest = std::max(farthest, distance(r.surface.vertices[v], at_phi.surface.vertices[v]) / diagonal);
        }
        CHECK(held == result.held_back_vertices);
        CHECK(farthest == Approx(result.max_held_back));
        const Parametrization p = refined_parametrization(*femur, r);
        test_support::require_valid_parametrization(p);
        CHECK(check_intersections(p.coarse).passed);
    }
}

namespace {

// The parameter positions of the parents of a new vertex at barycentric `b` (the ends of
// the edge it is the midpoint of): b has denominator 2^L (L its level), the parent edge
// is an edge of the level L - 1 grid, so exactly one of the three edge directions
// e_i - e_j (times 2^-L either way from b) leads to two points of that grid.
bool parent_positions(const Vec3& b, Vec3& pa, Vec3& pb) {
    int level = 0;
    auto on_grid = [](const Vec3& x, int l) {
        for (double c : x)
            if (std::ldexp(c, l) != std::floor(std::ldexp(c, l))) return false;
        return true;
    };
    while (!on_grid(b, level)) ++level;
    if (level == 0) return false;
    const double h = std::ldexp(1.0, -level);
    for (int i = 0; i < 3; ++i) {
        Vec3 d{0, 0, 0};
        d[size_t(i)] = h;
        d[size_t((i + 1) % 3)] = -h;
        pa = b + d;
        pb = b - d;
        if (on_grid(pa, level - 1) && on_grid(pb, level - 1)) return true;
    }
    return false;
}

// Held-back vertices follow their ancestors (refine.cpp, HELD-BACK VERTICES): with d the
// distance from phi and c_v = |mid(phi_a, phi_b) - phi_v| the deviation of v's parent
// chord, every new vertex v has d_v <= c_v + (d_a + d_b) / 2; so a held-back vertex is
// bounded by the chord deviations of its ancestors, not by the distance to the coarse
// surface. Returns the number of held-back vertices checked.
int64_t check_held_back_follow_parents(const Parametrization& param, const RefinedSurface& r) {
    const PhiEvaluator phi(param);
    const size_t nv = r.surface.vertices.size(), coarse_vertices = param.coarse.vertices.size();
    // (coarse triangle, barycentric) -> vertex, from the triangles' corners.
    std::map<std::pair<int32_t, std::array<double, 3>>, int32_t> at;
    std::vector<std::vector<size_t>> triangles_of(nv);
    for (size_t t = 0; t < r.surface.triangles.size(); ++t)
        for (size_t k = 0; k < 3; ++k) {
            const Vec3& b = r.triangle_barycentric[t][k];
            at[{r.triangle_coarse[t], {b[0], b[1], b[2]}}] = r.surface.triangles[t][k];
            triangles_of[size_t(r.surface.triangles[t][k])].push_back(t);
        }
    std::vector<Vec3> at_phi(nv);
    for (size_t v = 0; v < nv; ++v)
        at_phi[v] = v < coarse_vertices ? param.coarse.vertices[v]
                                        : phi.evaluate(r.vertex_coarse_triangle[v], r.vertex_barycentric[v]).position;
    const double diagonal = bounding_box_diagonal(param.original);
    auto d = [&](size_t v) { return distance(r.surface.vertices[v], at_phi[v]); };
    int64_t held = 0;
    for (size_t v = coarse_vertices; v < nv; ++v) {
        if (r.vertex_phi_fraction[v] >= 1.0) {
            CHECK(r.surface.vertices[v] == at_phi[v]);
            continue;
        }
        ++held;
        int32_t a = -1, b = -1;
        for (size_t t : triangles_of[v]) {
            const size_t k = size_t(std::find(r.surface.triangles[t].begin(), r.surface.triangles[t].end(), int32_t(v)) -
                                    r.surface.triangles[t].begin());
            Vec3 pa, pb;
            if (!parent_positions(r.triangle_barycentric[t][k], pa, pb)) continue;
            const auto ia = at.find({r.triangle_coarse[t], {pa[0], pa[1], pa[2]}});
            const auto ib = at.find({r.triangle_coarse[t], {pb[0], pb[1], pb[2]}});
            if (ia == at.end() || ib == at.end()) continue;
            a = ia->second, b = ib->second;
            break;
        }
        INFO("vertex " << v);
        REQUIRE(a >= 0);
        const double chord = distance(0.5 * (at_phi[size_t(a)] + at_phi[size_t(b)]), at_phi[v]);
        const double follows = chord + 0.5 * (d(size_t(a)) + d(size_t(b)));
        INFO("distance from phi " << d(v) / diagonal << ", parent chord deviation " << chord / diagonal
                                  << ", parents' distances " << d(size_t(a)) / diagonal << " "
                                  << d(size_t(b)) / diagonal);
        CHECK(d(v) <= follows + 1e-12 * diagonal);
    }
    return held;
}

// Refines `p` with the remedy on (`levels` < 0: adaptive to `tolerance`) and checks that
// vertices were held back, that each follows its parents (check_held_back_follow_parents)
// and that the surface is free of intersections. Returns the result.
RefineResult check_remedy_follows_parents(const Parametrization& p, int levels, double tolerance = 0.0) {
    INFO((levels < 0 ? "adaptive, T = " + std::to_string(tolerance) : "levels " + std::to_string(levels)));
    RefineOptions o;
    o.levels = levels;
    o.tolerance = tolerance;
    o.prevent_intersections = true;
    RefinedSurface r;
    const RefineResult res = refine(p, o, Context{}, r);
    INFO(res.held_back_vertices << " held back up to " << res.max_held_back << ", bound " << res.hausdorff_bound);
    REQUIRE(res.held_back_vertices > 0);  // the case this is about
    CHECK(check_held_back_follow_parents(p, r) == res.held_back_vertices);
    const CheckResult intersections = check_intersections(r.surface);
    INFO(check_text(intersections));
    CHECK(intersections.passed);
    return res;
}

// A crinkled sphere: the octahedron subdivided 4 times (2048 triangles), every vertex
// moved along its ray to a radius in [0.9, 1.1] (a fixed pseudo-random sequence),
// simplified to 20 %. S0 stays star-shaped, so it does not intersect itself, but
// neighbouring triangles turn by up to 144 degrees (197 of 3072 edges by more than 90):
// the femur's CT crinkles in miniature, without the data.
Parametrization crinkled_sphere() {
    Surface s = test::make_subdivided_octahedron(4, 0.0).original;
    uint64_t state = 12345;
    for (Vec3& x : s.vertices) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        const double u = double(state >> 11) / double(1ull << 53);  // in [0, 1)
        x = ((1 + 0.2 * (u - 0.5)) / norm(x)) * x;
    }
    SimplifyOptions so;
    so.target_ratio = 0.2;
    Parametrization p;
    simplify(s, so, Context{}, p);
    return p;
}

}  // namespace

TEST_CASE("held-back vertices of a refined surface follow their parents: off phi by at most the parent chords",
          "[refine][remedy]") {
    // Where S0 folds sharply, chords across the fold cross their neighbours at every
    // level. A vertex that still intersected at its parents' midpoint moved on towards its
    // point on the coarse surface, by up to its coarse triangle's deviation. Now its
    // parents are held back instead and it follows them: d_v <= c_v + (d_a + d_b) / 2
    // (check_held_back_follow_parents). On the crinkled sphere at K = 3 that broke for
    // 24 vertices: 144 held back up to 0.109 of the diagonal, bound 0.110; now 115 up to
    // 0.062, bound 0.063.
    const Parametrization sphere = crinkled_sphere();
    const RefineResult res = check_remedy_follows_parents(sphere, 3);
    CHECK(res.hausdorff_bound < 0.08);
}

TEST_CASE("held-back vertices of the refined femur follow their parents: off phi by at most the parent chords",
          "[refine][remedy][real]") {
    // Femur at 10 %: 497 edges of S0 turn by more than 90 degrees, up to 155. The old
    // remedy held vertices back by up to 4.0e-3 of the diagonal at --max-error 0.0003 (and
    // that was the bound); here it broke d_v <= c_v + (d_a + d_b) / 2 for 3 vertices at
    // T = 0.003 and 5 at K = 3 (e.g. 1.70e-3 where the parents and their chord allowed
    // 1.31e-3; K = 2 held back no vertex that far). K = 2, 3 and T = 0.003 now hold back
    // 13, 25, 15 vertices, at most 2.6e-4, 5.1e-4, 2.1e-3 (were 7.2e-4, 2.1e-3, 4.6e-3).
    const Parametrization* femur = test_support::simplified_femur();
    if (!femur) {
        WARN("missing femur.off");
        return;
    }
    check_remedy_follows_parents(*femur, -1, 3e-3);
    for (int levels : {2, 3}) check_remedy_follows_parents(*femur, levels);
}

namespace {

// The checker's sampled two-sided Hausdorff distance between the refined surface as
// returned (held-back vertices where they are) and S0, relative to the diagonal: an
// independent lower estimate of the true distance (bpm::check_distance).
double sampled_hausdorff(const Parametrization& coarse, const RefinedSurface& r, double spacing) {
    const Parametrization p = refined_parametrization(coarse, r);
    CheckOptions co;
    co.error_sample_spacing = spacing;
    const CheckResult d = check_distance(p, co);
    for (const auto& m : d.measures)
        if (m.name == "coarse_hausdorff") return m.value;
    return -1;
}

// Refines `c` adaptively to `tolerance` (with or without the intersection remedy) and
// checks what the bound promises: every triangle above the tolerance is at max_level, the
// tolerance is met if none is, and the checker's distance sampled `spacing` apart is never
// above the bound.
RefineResult check_adaptive_bound(const Case& c, double tolerance, bool prevent_intersections, double spacing) {
    INFO(c.name << " tolerance " << tolerance << (prevent_intersections ? ", remedy on" : ""));
    RefinedSurface r;
    RefineOptions o;
    o.tolerance = tolerance;
    o.prevent_intersections = prevent_intersections;
    const RefineResult res = refine(c.param, o, Context{}, r);
    INFO(res.triangles << " triangles, bound " << res.hausdorff_bound << ", above " << res.triangles_above_tolerance);
    CHECK(res.triangles_above_tolerance == res.triangles_at_max_level_above_tolerance);
    if (res.triangles_above_tolerance == 0) CHECK(res.hausdorff_bound <= tolerance);
    const double measured = sampled_hausdorff(c.param, r, spacing);
    INFO("sampled Hausdorff " << measured);
    CHECK(measured >= 0);
    CHECK(measured <= res.hausdorff_bound * (1 + 1e-9) + 1e-12);
    return res;
}

}  // namespace

TEST_CASE("the adaptive bound holds: the sampled Hausdorff distance of the refined surface is never above it",
          "[refine][bound]") {
    // The tolerance used to be judged at 7 sample points per triangle: on a CAD part at
    // 10 % --max-error 0.003 gave a measured Hausdorff distance of 0.0045. The deviation
    // is now the maximum over the overlay with phi's pieces; the checker's sampled
    // distance (a lower estimate of the true one) must stay at or below the bound.
    for (const Case& c : cases()) {
        for (double tolerance : {1e-2, 3e-3, 1e-3}) {
            const RefineResult res = check_adaptive_bound(c, tolerance, false, tolerance / 4);
            // Nothing held back (off): the bound is max |flat - phi|, or less on planar
            // regions (the refined cube's faces), where drift within the plane is no error.
            CHECK(res.hausdorff_bound <= res.max_estimated_error);
        }
    }
}

TEST_CASE("adaptive refinement with the intersection remedy meets its tolerance: held-back vertices count",
          "[refine][bound][remedy][real]") {
    // Femur at 10 % with --max-error 0.003: the remedy held 86 vertices back towards the
    // coarse surface, up to 0.00385 of the diagonal from phi, and the proven bound was
    // 0.00685 (the sampled distance 0.00358 > T), with no triangle at max_level. Now the
    // vertices are held back towards their parent edges, the deviation is measured with
    // them where they are, and the triangles still above T are refined further.
    // The coarse surface of that case: without the simplifier's ridge guard (with it, the
    // folds where the remedy held vertices back are gone, and the bound stays above T at
    // one place where the femur's own sharpest edge, 24.6 degrees, lies: bench/RESULTS.md,
    // "Coarse ridges").
    const std::string path = std::string(BPM_MESH_DIR) + "/femur.off";
    if (!std::filesystem::exists(path)) {
        WARN("missing " << path);
        return;
    }
    Parametrization unguarded;
    SimplifyOptions simplify_options;
    simplify_options.target_ratio = 0.1;
    simplify_options.min_ridge_angle_degrees = 0.0;
    simplify(read_surface(path), simplify_options, Context{}, unguarded);
    const Parametrization* femur = &unguarded;
    RefinedSurface r;
    RefineOptions o;
    o.tolerance = 3e-3;
    o.prevent_intersections = true;
    const RefineResult res = refine(*femur, o, Context{}, r);
    INFO(res.triangles << " triangles, level " << res.max_level << ", bound " << res.hausdorff_bound << ", "
                       << res.held_back_vertices << " held back up to " << res.max_held_back << ", "
                       << res.adaptive_passes << " passes");
    CHECK(res.held_back_vertices > 0);  // the case this is about
    CHECK(res.triangles_above_tolerance == 0);
    CHECK(res.hausdorff_bound <= o.tolerance);
    CHECK(check_intersections(r.surface).passed);
    // The per-triangle bounds are the bound, and the sampled distance stays below it.
    REQUIRE(r.triangle_bound.size() == size_t(res.triangles));
    CHECK(*std::max_element(r.triangle_bound.begin(), r.triangle_bound.end()) == res.hausdorff_bound);
    const double measured = sampled_hausdorff(*femur, r, o.tolerance / 4);
    INFO("sampled Hausdorff " << measured);
    CHECK(measured >= 0);
    CHECK(measured <= res.hausdorff_bound * (1 + 1e-9) + 1e-12);
}

TEST_CASE("where phi squeezes a spike into a few parameter cells, the default levels prove the bound",
          "[refine][bound][fold]") {
    // One original vertex of a flat 48 x 48 grid lifted by 1 (a spike whose star, 1/48 wide
    // in parameter space, phi stretches onto walls 1 long: like the femur's folds, where phi
    // squeezes pieces into slivers that cross the refined triangles). The tip is at no dyadic
    // position, so no refined vertex lands on it: |flat - phi| at the tip falls only with the
    // size of the triangle holding it. With max_level 8 (the default before) the bound of
    // femur 10 % at T = 0.0003 stopped at 1.37e-3, and here above the tolerance below; the
    // default is now level 10, reached only where refinement is still needed.
    const double x0 = 31.0 / 48, y0 = 13.0 / 48;  // in coarse triangle (0,0) (1,0) (1,1)
    const Parametrization spike = test::make_height_field(48, 1, [&](double x, double y) {
        return std::abs(x - x0) < 1e-9 && std::abs(y - y0) < 1e-9 ? 1.0 : 0.0;
    });
    // Bound 0.096 at level 8, 0.024 at level 10 (both with and without the remedy).
    const double tolerance = 0.03;
    for (bool remedy : {false, true}) {
        INFO((remedy ? "remedy on" : "remedy off"));
        RefineOptions o;
        o.tolerance = tolerance;
        o.prevent_intersections = remedy;
        RefineOptions at8 = o;
        at8.max_level = 8;
        RefinedSurface r8, r;
        const RefineResult res8 = refine(spike, at8, Context{}, r8);
        const RefineResult res = refine(spike, o, Context{}, r);
        INFO("max_level 8: bound " << res8.hausdorff_bound << ", " << res8.triangles << " triangles; default: bound "
                                   << res.hausdorff_bound << ", " << res.triangles << " triangles, level "
                                   << res.max_level);
        CHECK(res8.triangles_at_max_level_above_tolerance > 0);  // the case this is about
        CHECK(res.triangles_above_tolerance == 0);
        CHECK(res.hausdorff_bound <= tolerance);
        CHECK(res.max_level > 8);
        CHECK(check_intersections(r.surface).passed);
        CHECK(validate_surface(r.surface).empty());
        // Few triangles: only where the spike is.
        CHECK(res.triangles < 4 * res8.triangles);
        const double measured = sampled_hausdorff(spike, r, tolerance / 4);
        INFO("sampled Hausdorff " << measured);
        CHECK(measured >= 0);
        CHECK(measured <= res.hausdorff_bound * (1 + 1e-9) + 1e-12);
    }
}

namespace {

// Adaptive refinement of femur 10 % (the shared fixture) with the remedy at tolerance T:
// checks that it proves T with vertices held back, no intersections, the sampled distance
// within the bound; returns the result for the case's own checks.
RefineResult femur_proves(double tolerance) {
    const Parametrization* femur = test_support::simplified_femur();
    if (!femur) {
        WARN("femur.off missing");
        return {};
    }
    RefinedSurface r;
    RefineOptions o;
    o.tolerance = tolerance;
    o.prevent_intersections = true;
    const RefineResult res = refine(*femur, o, Context{}, r);
    INFO("T " << tolerance << ": " << res.triangles << " triangles, bound " << res.hausdorff_bound << ", "
              << res.held_back_vertices << " held back up to " << res.max_held_back << ", " << res.adaptive_passes
              << " passes");
    CHECK(res.held_back_vertices > 0);  // the remedy is at work
    CHECK(res.triangles_above_tolerance == 0);
    CHECK(res.hausdorff_bound <= o.tolerance);
    CHECK(check_intersections(r.surface).passed);
    REQUIRE(r.triangle_bound.size() == size_t(res.triangles));
    const double measured = sampled_hausdorff(*femur, r, o.tolerance / 4);
    INFO("sampled Hausdorff " << measured);
    CHECK(measured <= res.hausdorff_bound * (1 + 1e-9) + 1e-12);
    return res;
}

}  // namespace

TEST_CASE("held-back vertices that set the bound are tried back at phi one by one: femur 10 % proves 0.001",
          "[refine][bound][remedy][real]") {
    // The remedy's last step (grow_back) moves every held-back vertex at once and only
    // within its last halving, so a vertex whose intersections later moves of others had
    // resolved stayed held back: femur 10 %, T = 0.001, bound 1.28e-3 from vertices held
    // back by up to 1.18e-3 (the farthest one of pass 1, 1.04e-3 from phi, intersected
    // nothing when put back alone). Now each vertex held back farther than T is tried alone.
    femur_proves(1e-3);
}

TEST_CASE("a pass worse than the one before gets one more pass: femur 10 % proves 0.003",
          "[refine][bound][remedy][real]") {
    // Pass 2 refined the triangles next to held-back vertices and the remedy then held back
    // more (bound 0.00374 -> 0.00376, 4 -> 7 triangles above T), so the passes stopped as
    // diverging and returned pass 1, unproved; pass 3 meets T.
    if (!test_support::simplified_femur()) return;
    CHECK(femur_proves(3e-3).adaptive_passes >= 3);
}

TEST_CASE("adaptive passes that tie on the bound return the one with fewer triangles above the tolerance",
          "[refine][bound][remedy][real]") {
    // Where phi folds, triangles at max_level set the bound and it stays the same from pass
    // to pass while the passes still split the triangles around held-back vertices. Only a
    // smaller bound counted: femur at 1000 vertices, T = 0.001, max_level 5 had bounds
    // 0.002969, 0.002679, 0.002676, 0.002676 in passes 1-4 with 142, 162, 115, 105
    // triangles above T (63, 106, 111, 105 at max_level) and returned pass 3, four triangles
    // above T that refining could still split. (At T = 0.0003, max_level 8, the same rule
    // returned pass 1 with vertices held back by up to 0.0036 of the diagonal and a sampled
    // distance of 0.0016 instead of pass 3 with 0.00038 and 0.000298.)
    const std::string path = std::string(BPM_MESH_DIR) + "/femur.off";
    if (!std::filesystem::exists(path)) {
        WARN("missing femur.off");
        return;
    }
    SimplifyOptions so;
    so.target_vertices = 1000;
    Parametrization femur;
    simplify(read_surface(path), so, Context{}, femur);
    RefinedSurface r;
    RefineOptions o;
    o.tolerance = 1e-3;
    o.max_level = 5;
    o.prevent_intersections = true;
    const RefineResult res = refine(femur, o, Context{}, r);
    INFO(res.triangles << " triangles, bound " << res.hausdorff_bound << ", " << res.triangles_above_tolerance
                       << " above T (" << res.triangles_at_max_level_above_tolerance << " at max_level), "
                       << res.adaptive_passes << " passes, " << res.held_back_vertices << " held back");
    REQUIRE(res.triangles_above_tolerance > 0);  // the fold of phi at max_level: what this is about
    CHECK(res.triangles_above_tolerance == res.triangles_at_max_level_above_tolerance);
    CHECK(res.hausdorff_bound == *std::max_element(r.triangle_bound.begin(), r.triangle_bound.end()));
    CHECK(check_intersections(r.surface).passed);
}

TEST_CASE("the proven bound with held-back vertices is above the sampled distance, multi-material too",
          "[refine][bound][remedy][multimaterial]") {
    // Two materials (two cubes sharing a face) at 5 %, eight octants at 10 % and two
    // synthetic fixtures: adaptive
    // and uniform refinement with the remedy on; RefineResult::hausdorff_bound (max over
    // the triangles of |x - phi(x)| with the vertices where they are) must be at least
    // the checker's sampled two-sided distance, and the tolerance met where no triangle
    // is at max_level.
    std::vector<Case> cs;
    {
        SimplifyOptions so;
        so.target_ratio = 0.05;
        Parametrization coarse;
        simplify(fixtures::two_cubes(16), so, Context{}, coarse);
        cs.push_back({"two cubes", coarse});
        Parametrization octants;  // 8 materials, 4 sheets along 6 internal feature lines
        so.target_ratio = 0.1;
        simplify(fixtures::octants(4), so, Context{}, octants);
        cs.push_back({"octants", octants});
    }
    cs.push_back({"octahedron", test::make_subdivided_octahedron(3)});
    cs.push_back({"height field", test::make_height_field(12, 3, test::default_height)});
    for (const Case& c : cs) {
        // Samples 2e-3 apart at the finest (the uniform cases below too): every sample
        // must stay below the bound whatever the spacing, and T / 4 (2.5e-4) and 1e-3
        // made this test take 111 s and 31 s, many times that under ASan.
        for (double tolerance : {1e-2, 3e-3, 1e-3}) check_adaptive_bound(c, tolerance, true, std::max(tolerance / 4, 2e-3));
        for (int levels : {1, 2}) {
            INFO(c.name << " levels " << levels);
            RefinedSurface r;
            RefineOptions o;
            o.levels = levels;
            o.prevent_intersections = true;
            const RefineResult res = refine(c.param, o, Context{}, r);
            CHECK(res.hausdorff_bound <= res.max_estimated_error + res.max_held_back + 1e-15);
            const double measured = sampled_hausdorff(c.param, r, 2e-3);
            INFO("bound " << res.hausdorff_bound << ", sampled Hausdorff " << measured);
            CHECK(measured <= res.hausdorff_bound * (1 + 1e-9) + 1e-12);
        }
    }
}

TEST_CASE("uniform refinement with held-back vertices reports a bound the sampled distance stays below",
          "[refine][bound][remedy][real]") {
    // Femur at 10 %, K = 1, 2: vertices are held back; the bound is now measured with them
    // where they are (it was max |flat - phi| + the farthest held-back distance, larger).
    const Parametrization* femur = test_support::simplified_femur();
    if (!femur) {
        WARN("missing femur.off");
        return;
    }
    for (int levels : {1, 2}) {
        INFO("levels " << levels);
        RefinedSurface r;
        RefineOptions o;
        o.levels = levels;
        o.prevent_intersections = true;
        const RefineResult res = refine(*femur, o, Context{}, r);
        REQUIRE(res.held_back_vertices > 0);
        CHECK(res.hausdorff_bound <= res.max_estimated_error + res.max_held_back + 1e-15);
        const double measured = sampled_hausdorff(*femur, r, 1e-3);
        INFO("bound " << res.hausdorff_bound << ", sampled Hausdorff " << measured);
        CHECK(measured <= res.hausdorff_bound * (1 + 1e-9) + 1e-12);
    }
}

TEST_CASE("adaptive refinement reports progress that never goes back and names the pass and the remedy",
          "[refine][remedy][real]") {
    // bpm-refine --max-error on two boxes sharing a face (a polyhedral input) ran 220 s:
    // the terminal showed "refining 0 % .. 87 %" and then 0 % again for every pass, and
    // nothing during the intersection remedy's rounds, where the time went. The femur case
    // of the remedy test above (10 %, no ridge guard, T = 0.003) holds vertices back (one
    // pass: the fractions of later passes follow the same rule, (pass - 1 + within) / 12).
    const std::string path = std::string(BPM_MESH_DIR) + "/femur.off";
    if (!std::filesystem::exists(path)) {
        WARN("missing femur.off");
        return;
    }
    SimplifyOptions so;
    so.target_ratio = 0.1;
    so.min_ridge_angle_degrees = 0.0;
    Parametrization femur;
    simplify(read_surface(path), so, Context{}, femur);
    std::vector<std::pair<double, std::string>> reports;
    Context context;
    context.progress = [&](double fraction, const std::string& stage) {
        reports.emplace_back(fraction, stage);
        return true;
    };
    RefinedSurface r;
    RefineOptions o;
    o.tolerance = 3e-3;
    o.prevent_intersections = true;
    const RefineResult res = refine(femur, o, context, r);
    REQUIRE(res.held_back_vertices > 0);  // the remedy ran: what this is about
    REQUIRE(!reports.empty());
    bool pass = false, remedy = false;
    for (size_t i = 0; i < reports.size(); ++i) {
        INFO("report " << i << ": " << reports[i].first << " " << reports[i].second);
        CHECK(reports[i].first >= 0.0);
        CHECK(reports[i].first <= 1.0);
        if (i > 0) CHECK(reports[i].first >= reports[i - 1].first);
        pass = pass || reports[i].second.rfind("pass 1: ", 0) == 0;
        remedy = remedy || reports[i].second.find("holding back intersecting vertices, round ") != std::string::npos;
    }
    CHECK(pass);
    CHECK(remedy);
    CHECK(reports.back().first == 1.0);
}

TEST_CASE("the refinement's bound is max |flat - phi| over the overlay, as the checker finds it on the refined phi",
          "[refine][bound][real]") {
    // RefineResult::hausdorff_bound is max |flat - phi| over the corners of the overlay of
    // each refined triangle with phi's pieces; the refined parametrization has exactly those
    // cells, and bpm-check's coarse_to_original_bound is the same maximum over its nodes,
    // computed independently. On elephant at 10 % after bpm-smooth, K = 3, the bound was
    // 5.74e-3 against 5.37e-3: a piece edge on the same coarse edge as an edge of a refined
    // triangle counted as crossing it (their determinant rounded to ~1e-17, not 0) at a
    // point outside the triangle, where the flat map extrapolates.
    const std::string path = std::string(BPM_MESH_DIR) + "/elephant.off";
    if (!std::filesystem::exists(path)) {
        WARN("missing " << path);
        return;
    }
    SimplifyOptions so;
    so.target_ratio = 0.1;
    Parametrization elephant;
    simplify(read_surface(path), so, Context{}, elephant);
    smooth(elephant, SmoothOptions{});
    for (int levels : {2, 3}) {
        INFO("levels " << levels);
        RefinedSurface r;
        RefineOptions o;
        o.levels = levels;
        o.prevent_intersections = false;  // every vertex at phi: the overlay's cells as computed
        const RefineResult res = refine(elephant, o, Context{}, r);
        CheckOptions co;
        co.error_sample_spacing = 1.0;  // the node bound is exact; the samples are not needed
        const CheckResult d = check_distance(refined_parametrization(elephant, r), co);
        double node_bound = -1;
        for (const auto& m : d.measures)
            if (m.name == "coarse_to_original_bound") node_bound = m.value;
        INFO("refine's bound " << res.hausdorff_bound << ", checker's " << node_bound);
        CHECK(res.hausdorff_bound == Approx(node_bound).epsilon(1e-9));
    }
}

namespace {

// phi with tangential drift, as bpm-smooth or an older simplifier leaves it: every node
// inside a coarse triangle (all three coordinates > 0) is moved `fraction` of the way to
// the triangle's centroid in the parameter triangle, where every piece around it keeps
// its orientation (exact); images stay. On a planar face phi then moves points within the
// face: max |flat - phi| grows, the geometry does not change.
Parametrization drifted(Parametrization p, double fraction) {
    const Vec3 centroid{1.0 / 3, 1.0 / 3, 1.0 / 3};
    for (int32_t t = 0; t < p.coarse.num_triangles(); ++t) {
        const int64_t n0 = p.node_offsets[size_t(t)];
        auto orientations = [&]() {
            std::vector<int> o;
            for (int64_t q = p.piece_offsets[size_t(t)]; q < p.piece_offsets[size_t(t) + 1]; ++q) {
                const Tri& pc = p.pieces[size_t(q)];
                const auto& b = p.node_barycentric;
                o.push_back(orient3d({0, 0, 0}, b[size_t(n0 + pc[0])], b[size_t(n0 + pc[1])], b[size_t(n0 + pc[2])]));
            }
            return o;
        };
        const std::vector<int> before = orientations();
        for (int64_t n = n0; n < p.node_offsets[size_t(t) + 1]; ++n) {
            Vec3& b = p.node_barycentric[size_t(n)];
            if (!(b[0] > 0 && b[1] > 0 && b[2] > 0)) continue;
            const Vec3 old = b;
            b = old + fraction * (centroid - old);
            b[0] = 1.0 - b[1] - b[2];
            if (orientations() != before) b = old;
        }
    }
    return p;
}

// A flat round sheet (z = 0, radius 1) from the n x n grid, its boundary on the circle.
Surface round_sheet(int n) {
    Surface s = fixtures::disk(n);
    for (Vec3& v : s.vertices) {
        const double x = 2 * v[0] / n - 1, y = 2 * v[1] / n - 1;
        v = {x * std::sqrt(1 - y * y / 2), y * std::sqrt(1 - x * x / 2), 0.0};
    }
    return s;
}

}  // namespace

TEST_CASE("tangential drift of phi on planar faces costs no refinement and no bound", "[refine][bound][planar]") {
    // A gmsh box or two boxes sharing a face, simplified before commit cc134bb, had phi
    // moving points within the box faces by up to 0.0139 of the diagonal: max |flat - phi|
    // counted that, so adaptive refinement split the faces (two cubes at 5 %, T = 0.001:
    // 2787 triangles at level 5 where the 283 coarse ones are exact) and reported a bound
    // of ~T for a surface that is S0 up to rounding. On a planar region the bound now
    // comes from the region's boundary and offsets from the plane (refine.cpp, PLANAR
    // REGIONS).
    SimplifyOptions so;
    so.target_ratio = 0.1;
    Parametrization two;
    simplify(fixtures::two_cubes(8), so, Context{}, two);
    const std::vector<Case> cs = {{"cube", drifted(fixtures::refined_parametrization(fixtures::cube()), 1.0)},
                                  {"two cubes", drifted(two, 0.5)}};
    for (const Case& c : cs) {
        INFO(c.name);
        REQUIRE(check_bijectivity(c.param).passed);
        {
            RefinedSurface r;
            RefineOptions o;
            o.levels = 2;
            const RefineResult res = refine(c.param, o, Context{}, r);
            INFO("max |flat - phi| " << res.max_estimated_error << ", bound " << res.hausdorff_bound);
            CHECK(res.max_estimated_error > 0.005);  // the drift: what this is about
            CHECK(res.hausdorff_bound <= 1e-12);
            CHECK(sampled_hausdorff(c.param, r, 0.05) <= res.hausdorff_bound + 1e-12);
        }
        RefinedSurface r;
        RefineOptions o;
        o.tolerance = 1e-3;
        o.prevent_intersections = true;
        const RefineResult res = refine(c.param, o, Context{}, r);
        INFO(res.triangles << " triangles, level " << res.max_level << ", bound " << res.hausdorff_bound);
        CHECK(res.triangles == int64_t(c.param.coarse.triangles.size()));
        CHECK(res.hausdorff_bound <= 1e-12);
        CHECK(sampled_hausdorff(c.param, r, 0.05) <= res.hausdorff_bound + 1e-12);
    }
}

TEST_CASE("the planar-region bound stays above the sampled distance where the region's boundary is curved",
          "[refine][bound][planar]") {
    // A flat round sheet: the coarse boundary edges are chords of the circle, so the
    // region's bound is the chords' distance from S0's boundary, and phi drifts inside.
    // Whatever the bound gains from the region, the checker's sampled two-sided distance
    // must stay below it; also on polyhedral multi-material shapes with drift (planar
    // regions meeting at non-manifold feature lines: 8 octants, a prism in 3 wedges).
    SimplifyOptions so;
    so.target_ratio = 0.15;
    Parametrization sheet, octants, wedges;
    simplify(round_sheet(16), so, Context{}, sheet);
    simplify(fixtures::octants(3), so, Context{}, octants);
    simplify(fixtures::cylinder_wedges(24, 3), so, Context{}, wedges);
    const std::vector<Case> cs = {{"round sheet", drifted(sheet, 0.5)},
                                  {"octants", drifted(octants, 0.5)},
                                  {"prism in 3 wedges", drifted(wedges, 0.5)}};
    for (const Case& c : cs) {
        REQUIRE(check_bijectivity(c.param).passed);
        // Samples 5e-3 apart: 2e-3 took 13 s on the sheet alone.
        for (double tolerance : {1e-2, 3e-3, 1e-3}) check_adaptive_bound(c, tolerance, true, 5e-3);
        for (int levels : {0, 1, 2}) {
            INFO(c.name << " levels " << levels);
            RefinedSurface r;
            RefineOptions o;
            o.levels = levels;
            const RefineResult res = refine(c.param, o, Context{}, r);
            const double measured = sampled_hausdorff(c.param, r, 5e-3);
            INFO("bound " << res.hausdorff_bound << ", max |flat - phi| " << res.max_estimated_error << ", sampled "
                          << measured);
            if (c.name == "round sheet") CHECK(res.hausdorff_bound > 0);  // the chords
            CHECK(res.hausdorff_bound <= res.max_estimated_error);
            CHECK(measured <= res.hausdorff_bound * (1 + 1e-9) + 1e-12);
        }
    }
}
