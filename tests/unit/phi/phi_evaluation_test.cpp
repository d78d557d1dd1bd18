// Evaluating phi: exactness for the identity, agreement with independently known maps
// for the fixtures (a height field gives phi(x, y) = (x, y, h_PL(x, y))), continuity
// across coarse edges, and tolerance of rounding outside the triangle.

#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include "bpm/phi_evaluation.h"
#include "bpm/simplify.h"
#include "bpm/surface_io.h"
#include "fixtures_phi.h"
#include "test_support.h"

using namespace bpm;

namespace {

Vec3 random_barycentric(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0, 1);
    double a = u(rng), b = u(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    return {1 - a - b, a, b};
}

// Piecewise-linear height of the fixture's original grid at (x, y), computed from the
// grid directly (no pieces involved).
double grid_height(const Parametrization& p, int n, double x, double y) {
    int i = std::min(static_cast<int>(std::floor(x * n)), n - 1);
    int j = std::min(static_cast<int>(std::floor(y * n)), n - 1);
    i = std::max(i, 0), j = std::max(j, 0);
    const double fx = x * n - i, fy = y * n - j;
    const auto z = [&](int a, int b) { return p.original.vertices[static_cast<size_t>(b * (n + 1) + a)][2]; };
    if (fx + fy <= 1) return z(i, j) + fx * (z(i + 1, j) - z(i, j)) + fy * (z(i, j + 1) - z(i, j));
    // upper-right half: corners (i+1,j), (i+1,j+1), (i,j+1)
    return z(i + 1, j + 1) + (1 - fx) * (z(i, j + 1) - z(i + 1, j + 1)) + (1 - fy) * (z(i + 1, j) - z(i + 1, j + 1));
}

void check_sample_consistent(const Parametrization& p, const PhiSample& r) {
    REQUIRE(r.original_triangle >= 0);
    REQUIRE(r.original_triangle < p.original.num_triangles());
    const Tri& tri = p.original.triangles[static_cast<size_t>(r.original_triangle)];
    const auto& x = p.original.vertices;
    const Vec3 b = r.original_barycentric;
    CHECK(b[0] >= -1e-12);
    CHECK(b[1] >= -1e-12);
    CHECK(b[2] >= -1e-12);
    CHECK(b[0] + b[1] + b[2] == Approx(1).margin(1e-12));
    const Vec3 q = barycentric_point(x[static_cast<size_t>(tri[0])], x[static_cast<size_t>(tri[1])],
                                     x[static_cast<size_t>(tri[2])], b);
    CHECK(distance(q, r.position) < 1e-12);
    CHECK(norm(r.normal) == Approx(1).margin(1e-12));
    CHECK(distance(r.normal, triangle_normal(x[static_cast<size_t>(tri[0])], x[static_cast<size_t>(tri[1])],
                                             x[static_cast<size_t>(tri[2])])) == 0);
}

}  // namespace

TEST_CASE("fixture pieces are counter-clockwise and tile their parameter triangle", "[phi]") {
    for (const Parametrization& p : {test::make_subdivided_octahedron(3), test::make_height_field(24, 4, test::default_height),
                                     test::make_height_field(30, 3, test::default_height)}) {
        for (int32_t t = 0; t < p.coarse.num_triangles(); ++t) {
            const int64_t nb = p.node_offsets[static_cast<size_t>(t)];
            double total = 0;
            for (int64_t q = p.piece_offsets[static_cast<size_t>(t)]; q < p.piece_offsets[static_cast<size_t>(t) + 1]; ++q) {
                const Tri& pc = p.pieces[static_cast<size_t>(q)];
                const Vec3& a = p.node_barycentric[static_cast<size_t>(nb + pc[0])];
                const Vec3& b = p.node_barycentric[static_cast<size_t>(nb + pc[1])];
                const Vec3& c = p.node_barycentric[static_cast<size_t>(nb + pc[2])];
                const double area = cross(Vec2{b[1] - a[1], b[2] - a[2]}, Vec2{c[1] - a[1], c[2] - a[2]});
                REQUIRE(area > 1e-9);  // parameter triangle has area 1 in (b1, b2)
                total += area;
            }
            REQUIRE(total == Approx(1).margin(1e-12));
        }
        for (size_t n = 0; n < p.node_image.size(); ++n)
            REQUIRE(p.node_image[n] == node_image_from_kind(p, static_cast<int64_t>(n)));
    }
}

TEST_CASE("identity phi reproduces the input bit for bit", "[phi]") {
    const Parametrization p = test::make_subdivided_octahedron(2);
    const Parametrization id = make_identity_parametrization(p.original);
    PhiEvaluator eval(id);
    std::mt19937_64 rng(1);
    for (int k = 0; k < 2000; ++k) {
        const int32_t t = static_cast<int32_t>(rng() % static_cast<uint64_t>(id.coarse.num_triangles()));
        const Vec3 b = random_barycentric(rng);
        const Tri& tri = id.original.triangles[static_cast<size_t>(t)];
        const auto& x = id.original.vertices;
        const PhiSample r = eval.evaluate(t, b);
        REQUIRE(r.position == barycentric_point(x[static_cast<size_t>(tri[0])], x[static_cast<size_t>(tri[1])],
                                                x[static_cast<size_t>(tri[2])], b));
        REQUIRE(r.original_triangle == t);
        REQUIRE(r.original_barycentric == b);
    }
}

TEST_CASE("phi interpolates node images at the nodes", "[phi]") {
    for (const Parametrization& p : {test::make_subdivided_octahedron(3), test::make_height_field(8, 2, test::default_height)}) {
        PhiEvaluator eval(p);
        for (int32_t t = 0; t < p.coarse.num_triangles(); ++t)
            for (int64_t n = p.node_offsets[static_cast<size_t>(t)]; n < p.node_offsets[static_cast<size_t>(t) + 1]; ++n) {
                const PhiSample r = eval.evaluate(t, p.node_barycentric[static_cast<size_t>(n)]);
                REQUIRE(distance(r.position, p.node_image[static_cast<size_t>(n)]) < 1e-12);
                check_sample_consistent(p, r);
            }
    }
}

TEST_CASE("height-field phi with edge crossings equals the vertical projection", "[phi]") {
    const int n = 12, m = 3;
    const Parametrization p = test::make_height_field(n, m, test::default_height);
    int crossings = 0;
    for (auto k : p.node_kind) crossings += k == NodeKind::EdgeCrossing;
    REQUIRE(crossings > 0);
    PhiEvaluator eval(p);
    std::mt19937_64 rng(7);
    for (int k = 0; k < 20000; ++k) {
        const int32_t t = static_cast<int32_t>(rng() % static_cast<uint64_t>(p.coarse.num_triangles()));
        const Vec3 b = random_barycentric(rng);
        const Tri& ct = p.coarse.triangles[static_cast<size_t>(t)];
        const auto& cx = p.coarse.vertices;
        const Vec3 flat = barycentric_point(cx[static_cast<size_t>(ct[0])], cx[static_cast<size_t>(ct[1])],
                                            cx[static_cast<size_t>(ct[2])], b);
        const PhiSample r = eval.evaluate(t, b);
        INFO("triangle " << t << " b " << b[0] << " " << b[1] << " " << b[2]);
        REQUIRE(std::fabs(r.position[0] - flat[0]) < 1e-12);
        REQUIRE(std::fabs(r.position[1] - flat[1]) < 1e-12);
        REQUIRE(std::fabs(r.position[2] - grid_height(p, n, flat[0], flat[1])) < 1e-12);
        check_sample_consistent(p, r);
    }
}

TEST_CASE("phi of the subdivided octahedron lands on the right sub-triangle", "[phi]") {
    const int levels = 3, N = 1 << levels;
    const Parametrization p = test::make_subdivided_octahedron(levels);
    PhiEvaluator eval(p);
    std::mt19937_64 rng(3);
    for (int k = 0; k < 20000; ++k) {
        const int32_t t = static_cast<int32_t>(rng() % 8);
        const Vec3 b = random_barycentric(rng);
        const PhiSample r = eval.evaluate(t, b);
        check_sample_consistent(p, r);
        // Sub-triangle by the lattice cell of (b1, b2): its lower-left lattice point is
        // a corner of the original triangle unless the point is on a cell boundary.
        const double a = b[1] * N, c = b[2] * N;
        const double fa = a - std::floor(a), fc = c - std::floor(c);
        if (fa < 1e-9 || fc < 1e-9 || std::fabs(fa + fc - 1) < 1e-9) continue;
        const Tri& tri = p.original.triangles[static_cast<size_t>(r.original_triangle)];
        const bool lower = fa + fc < 1;
        // The piece's nodes: count how many have the expected lattice coordinates.
        int matched = 0;
        const int64_t nb = p.node_offsets[static_cast<size_t>(t)];
        for (int64_t q = p.piece_offsets[static_cast<size_t>(t)]; q < p.piece_offsets[static_cast<size_t>(t) + 1]; ++q) {
            if (p.piece_original_triangle[static_cast<size_t>(q)] != r.original_triangle) continue;
            for (int cnr = 0; cnr < 3; ++cnr) {
                const Vec3& nbary = p.node_barycentric[static_cast<size_t>(nb + p.pieces[static_cast<size_t>(q)][cnr])];
                const double na = nbary[1] * N, nc = nbary[2] * N;
                const bool inside_cell = na >= std::floor(a) && na <= std::floor(a) + 1 && nc >= std::floor(c) &&
                                         nc <= std::floor(c) + 1;
                const bool right_half = lower ? (na + nc <= std::floor(a) + std::floor(c) + 1)
                                              : (na + nc >= std::floor(a) + std::floor(c) + 1);
                matched += inside_cell && right_half;
            }
        }
        (void)tri;
        REQUIRE(matched == 3);
    }
}

TEST_CASE("phi is continuous across coarse edges", "[phi]") {
    const Parametrization p = test::make_height_field(12, 3, test::default_height);
    PhiEvaluator eval(p);
    // Coarse triangles 2c and 2c+1 share their diagonal: corners 0 and 2 of the first are
    // corners 0 and 1 of the second.
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    for (int k = 0; k < 5000; ++k) {
        const int32_t c = static_cast<int32_t>(rng() % 9);
        const double s = u(rng);
        const PhiSample a = eval.evaluate(2 * c, {1 - s, 0, s});
        const PhiSample b = eval.evaluate(2 * c + 1, {1 - s, s, 0});
        REQUIRE(distance(a.position, b.position) < 1e-12);
    }
}

TEST_CASE("points a rounding error outside the triangle get the nearest piece", "[phi]") {
    const Parametrization p = test::make_height_field(8, 2, test::default_height);
    PhiEvaluator eval(p);
    for (int32_t t = 0; t < p.coarse.num_triangles(); ++t) {
        for (const Vec3& b : {Vec3{1 + 1e-14, -1e-14, 0}, Vec3{0.5, 0.5 + 1e-15, -1e-15}, Vec3{-2e-16, 0.3, 0.7 + 2e-16},
                              Vec3{0.2, 0.4, 0.4}}) {
            const PhiSample r = eval.evaluate(t, b);
            check_sample_consistent(p, r);
        }
    }
}

TEST_CASE("batched evaluation matches single evaluation", "[phi]") {
    const Parametrization p = test::make_subdivided_octahedron(2);
    PhiEvaluator eval(p);
    std::mt19937_64 rng(5);
    std::vector<int32_t> tris;
    std::vector<Vec3> bs;
    for (int k = 0; k < 500; ++k) {
        tris.push_back(static_cast<int32_t>(rng() % 8));
        bs.push_back(random_barycentric(rng));
    }
    std::vector<PhiSample> out;
    eval.evaluate(tris, bs, out);
    REQUIRE(out.size() == tris.size());
    for (size_t i = 0; i < out.size(); ++i) {
        const PhiSample r = eval.evaluate(tris[i], bs[i]);
        CHECK(r.position == out[i].position);
        CHECK(r.original_triangle == out[i].original_triangle);
    }
    bs.pop_back();
    CHECK_THROWS(eval.evaluate(tris, bs, out));
}

TEST_CASE("SurfacePoint queries give the parallel-list results bit for bit", "[phi]") {
    // Large enough to be grouped and chunked (2^20 + a few), on two threads.
    const Parametrization p = test::make_height_field(12, 3, test::default_height);
    PhiEvaluator eval(p);
    std::mt19937_64 rng(19);
    const size_t n = (size_t(1) << 20) + 33;
    std::vector<int32_t> tris(n);
    std::vector<Vec3> bs(n);
    std::vector<SurfacePoint> points(n);
    for (size_t i = 0; i < n; ++i) {
        tris[i] = static_cast<int32_t>(rng() % static_cast<uint64_t>(p.coarse.num_triangles()));
        bs[i] = random_barycentric(rng);
        points[i] = {tris[i], bs[i]};
    }
    std::vector<PhiSample> lists, structs;
    std::vector<Vec3> lists_positions, structs_positions;
    eval.evaluate(tris, bs, lists, 2);
    eval.evaluate(points, structs, 2);
    eval.evaluate_positions(tris, bs, lists_positions, 1);
    eval.evaluate_positions(points, structs_positions, 2);
    REQUIRE(structs.size() == n);
    REQUIRE(structs_positions.size() == n);
    size_t mismatches = 0;
    for (size_t i = 0; i < n; ++i) {
        mismatches += !(lists[i].position == structs[i].position &&
                        lists[i].original_triangle == structs[i].original_triangle &&
                        lists[i].original_barycentric == structs[i].original_barycentric &&
                        lists[i].normal == structs[i].normal && lists_positions[i] == structs_positions[i]);
        if (i % 4099 == 0) mismatches += !(eval.evaluate(points[i]).position == lists[i].position);
    }
    CHECK(mismatches == 0);
    points[n / 3].triangle = -1;  // an invalid SurfacePoint
    CHECK_THROWS_AS(eval.evaluate(points, structs, 2), std::out_of_range);
    CHECK_THROWS_AS(eval.evaluate_positions(points, structs_positions), std::out_of_range);
}

TEST_CASE("large batches: grouped, chunked and threaded evaluation gives the single-query results", "[phi]") {
    // More than one chunk of 2^20 queries, so chunking, grouping by coarse triangle and
    // two threads are all exercised.
    const Parametrization p = test::make_height_field(12, 3, test::default_height);
    PhiEvaluator eval(p);
    std::mt19937_64 rng(9);
    const size_t n = (size_t(1) << 20) + 4097;
    std::vector<int32_t> tris(n);
    std::vector<Vec3> bs(n);
    for (size_t i = 0; i < n; ++i) {
        tris[i] = static_cast<int32_t>(rng() % static_cast<uint64_t>(p.coarse.num_triangles()));
        bs[i] = random_barycentric(rng);
    }
    std::vector<PhiSample> one, two;
    std::vector<Vec3> positions;
    eval.evaluate(tris, bs, one, 1);
    eval.evaluate(tris, bs, two, 2);
    eval.evaluate_positions(tris, bs, positions, 0);
    REQUIRE(one.size() == n);
    REQUIRE(two.size() == n);
    REQUIRE(positions.size() == n);
    size_t mismatches = 0;
    for (size_t i = 0; i < n; i += (i < 5000 ? 1 : 97)) {
        const PhiSample r = eval.evaluate(tris[i], bs[i]);
        mismatches += !(r.position == one[i].position && r.original_triangle == one[i].original_triangle &&
                        r.original_barycentric == one[i].original_barycentric && r.normal == one[i].normal);
        mismatches += !(r.position == two[i].position && r.original_triangle == two[i].original_triangle);
        mismatches += !(r.position == positions[i]);
    }
    CHECK(mismatches == 0);
    tris[n / 2] = p.coarse.num_triangles();
    CHECK_THROWS_AS(eval.evaluate(tris, bs, one, 2), std::out_of_range);
    CHECK_THROWS_AS(eval.evaluate_positions(tris, bs, positions), std::out_of_range);
    tris[n / 2] = 0;
    CHECK_THROWS_AS(eval.evaluate(tris, bs, one, -1), std::invalid_argument);
}

namespace {

// Brute-force reference for the point location of PhiEvaluator: every piece of the
// coarse triangle is tested (no grid). A piece's barycentrics of a query are computed
// as documented (inverse of the matrix of its corners' coarse barycentrics, rows
// (b x c, c x a, a x b) / det); the rule: the first piece (lowest index) that contains
// the point (all coordinates >= 0; this decides points on piece edges and nodes),
// otherwise (rounding outside, or a query outside the triangle) the piece the point is
// least outside of, where within 1e-9 any such piece is fine; the coordinates are then
// clamped into the piece.
struct ReferenceEvaluator {
    const Parametrization& p;
    std::vector<std::array<Vec3, 3>> rows;  // per piece
    std::vector<Vec3> normals;              // per original triangle

    explicit ReferenceEvaluator(const Parametrization& param) : p(param) {
        const auto& x = p.original.vertices;
        for (const Tri& t : p.original.triangles)
            normals.push_back(triangle_normal(x[size_t(t[0])], x[size_t(t[1])], x[size_t(t[2])]));
        for (int32_t t = 0; t < p.num_coarse_triangles(); ++t) {
            const int64_t nb = p.node_offsets[size_t(t)];
            for (int64_t q = p.piece_offsets[size_t(t)]; q < p.piece_offsets[size_t(t) + 1]; ++q) {
                const Tri& piece = p.pieces[size_t(q)];
                const Vec3& a = p.node_barycentric[size_t(nb + piece[0])];
                const Vec3& b = p.node_barycentric[size_t(nb + piece[1])];
                const Vec3& c = p.node_barycentric[size_t(nb + piece[2])];
                std::array<Vec3, 3> r{cross(b, c), cross(c, a), cross(a, b)};
                const double det = dot(a, r[0]);
                if (det == 0 || !std::isfinite(det)) {
                    r.fill(Vec3{-1, -1, -1});
                } else {
                    const double inv = 1.0 / det;
                    for (Vec3& row : r)
                        for (double& v : row) v = v * inv;
                }
                rows.push_back(r);
            }
        }
    }

    Vec3 lambda(int64_t q, const Vec3& b) const {
        const auto& r = rows[size_t(q)];
        return {dot(r[0], b), dot(r[1], b), dot(r[2], b)};
    }
    static double min3(const Vec3& v) { return std::min(v[0], std::min(v[1], v[2])); }

    // The pieces the evaluator may choose for b (exactly one if b is in some piece).
    std::vector<int64_t> acceptable(int32_t t, const Vec3& b) const {
        const int64_t q0 = p.piece_offsets[size_t(t)], q1 = p.piece_offsets[size_t(t) + 1];
        double best = -std::numeric_limits<double>::infinity();
        for (int64_t q = q0; q < q1; ++q) {
            const double m = min3(lambda(q, b));
            if (m >= 0) return {q};
            best = std::max(best, m);
        }
        std::vector<int64_t> ok;
        for (int64_t q = q0; q < q1; ++q) {
            const double m = min3(lambda(q, b));
            if (best >= -1e-9 ? m >= -1e-9 : m == best) ok.push_back(q);
        }
        return ok;
    }

    // Position and original triangle of phi(b) through piece q.
    PhiSample through(int64_t q, const Vec3& b) const {
        Vec3 l = lambda(q, b);
        if (min3(l) < 0) {
            for (double& v : l) v = std::max(v, 0.0);
            const double sum = l[0] + l[1] + l[2];
            l = (1.0 / sum) * l;
        }
        const int64_t nb = p.node_offsets[size_t(std::upper_bound(p.piece_offsets.begin(), p.piece_offsets.end(), q) -
                                                 p.piece_offsets.begin() - 1)];
        const Tri& piece = p.pieces[size_t(q)];
        PhiSample r;
        r.position = barycentric_point(p.node_image[size_t(nb + piece[0])], p.node_image[size_t(nb + piece[1])],
                                       p.node_image[size_t(nb + piece[2])], l);
        r.original_triangle = p.piece_original_triangle[size_t(q)];
        r.normal = normals[size_t(r.original_triangle)];
        return r;
    }
};

// Query points of coarse triangle t: every node of every piece, points on every piece
// edge (midpoint and a random point) and the piece centroids, random points, points on
// the coarse edges and corners, points a rounding error, a little and far outside.
void reference_queries(const Parametrization& p, int32_t t, std::mt19937_64& rng, std::vector<int32_t>& tris,
                       std::vector<Vec3>& bs) {
    std::uniform_real_distribution<double> u(0, 1);
    const auto add = [&](const Vec3& b) { tris.push_back(t), bs.push_back(b); };
    const int64_t nb = p.node_offsets[size_t(t)];
    for (int64_t q = p.piece_offsets[size_t(t)]; q < p.piece_offsets[size_t(t) + 1]; ++q) {
        const Tri& piece = p.pieces[size_t(q)];
        Vec3 c[3];
        for (int k = 0; k < 3; ++k) c[k] = p.node_barycentric[size_t(nb + piece[k])];
        for (int k = 0; k < 3; ++k) {
            add(c[k]);
            const Vec3& a = c[k];
            const Vec3& b = c[(k + 1) % 3];
            for (const double s : {0.5, u(rng)}) add((1 - s) * a + s * b);
        }
        add((1.0 / 3) * (c[0] + c[1] + c[2]));
    }
    for (int k = 0; k < 50; ++k) add(random_barycentric(rng));
    for (int k = 0; k < 10; ++k) {
        const double s = u(rng);
        for (const Vec3& e : {Vec3{1 - s, s, 0}, Vec3{0, 1 - s, s}, Vec3{s, 0, 1 - s}}) {
            add(e);
            for (const double eps : {1e-16, 1e-13, 1e-10, 1e-6, 1e-3, 0.2}) {
                // Pushed out across the edge (the zero component becomes negative).
                Vec3 o = e;
                for (int c = 0; c < 3; ++c) o[c] += e[c] == 0 ? -eps : eps / 2;
                add(o);
            }
        }
    }
    for (const Vec3& v : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}, Vec3{1 + 1e-14, -1e-14, 0},
                          Vec3{-1e-15, 0.5, 0.5 + 1e-15}, Vec3{-0.5, 0.75, 0.75}, Vec3{2, -0.5, -0.5}})
        add(v);
}

void check_against_reference(const Parametrization& p, uint64_t seed) {
    const PhiEvaluator eval(p);
    const ReferenceEvaluator ref(p);
    std::mt19937_64 rng(seed);
    std::vector<int32_t> tris;
    std::vector<Vec3> bs;
    for (int32_t t = 0; t < p.num_coarse_triangles(); ++t) reference_queries(p, t, rng, tris, bs);
    // Shuffled, so that the batched calls really regroup them.
    std::vector<size_t> order(tris.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<int32_t> st(tris.size());
    std::vector<Vec3> sb(tris.size());
    for (size_t i = 0; i < order.size(); ++i) st[i] = tris[order[i]], sb[i] = bs[order[i]];
    std::vector<PhiSample> one, two;
    std::vector<Vec3> positions;
    eval.evaluate(st, sb, one, 1);
    eval.evaluate(st, sb, two, 2);
    eval.evaluate_positions(st, sb, positions, 2);
    REQUIRE(one.size() == st.size());
    size_t wrong_piece = 0, batch_differs = 0, inside = 0;
    for (size_t i = 0; i < st.size(); ++i) {
        const PhiSample r = eval.evaluate(st[i], sb[i]);
        const std::vector<int64_t> ok = ref.acceptable(st[i], sb[i]);
        inside += ok.size() == 1;
        bool match = false;
        for (const int64_t q : ok) {
            const PhiSample e = ref.through(q, sb[i]);
            match = match || (e.position == r.position && e.original_triangle == r.original_triangle &&
                              e.normal == r.normal);
        }
        wrong_piece += !match;
        if (!match && wrong_piece <= 5)
            WARN("query " << i << ": coarse triangle " << st[i] << ", b = (" << sb[i][0] << ", " << sb[i][1] << ", "
                          << sb[i][2] << "): not the reference piece");
        batch_differs += !(r.position == one[i].position && r.original_triangle == one[i].original_triangle &&
                           r.original_barycentric == one[i].original_barycentric && r.normal == one[i].normal &&
                           r.position == two[i].position && r.original_triangle == two[i].original_triangle &&
                           r.original_barycentric == two[i].original_barycentric && r.normal == two[i].normal &&
                           r.position == positions[i]);
    }
    INFO(st.size() << " queries, " << inside << " with a unique reference piece");
    CHECK(inside > st.size() / 2);
    CHECK(wrong_piece == 0);
    CHECK(batch_differs == 0);
}

}  // namespace

TEST_CASE("point location agrees with a brute-force search over all pieces", "[phi]") {
    SECTION("fixtures") {
        check_against_reference(test::make_subdivided_octahedron(3), 11);
        check_against_reference(test::make_height_field(24, 4, test::default_height), 12);
        check_against_reference(test::make_height_field(30, 3, test::default_height), 13);
    }
    SECTION("femur simplified to 10%") {
        const Parametrization* femur = test_support::simplified_femur();
        if (!femur) {
            WARN("femur.off missing: real-mesh case skipped");
            return;
        }
        check_against_reference(*femur, 14);
    }
}

// Hidden: bpm_unit_tests "[.benchmark]" (build with -DCMAKE_BUILD_TYPE=Release).
TEST_CASE("phi evaluation throughput", "[.benchmark]") {
    const Parametrization p = test::make_height_field(400, 40, test::default_height);
    const auto t0 = std::chrono::steady_clock::now();
    PhiEvaluator eval(p);
    const auto t1 = std::chrono::steady_clock::now();
    std::mt19937_64 rng(1);
    const size_t q = 4000000;
    std::vector<int32_t> tris(q);
    std::vector<Vec3> bs(q);
    for (size_t i = 0; i < q; ++i) {
        tris[i] = static_cast<int32_t>(rng() % static_cast<uint64_t>(p.coarse.num_triangles()));
        bs[i] = random_barycentric(rng);
    }
    std::vector<PhiSample> out;
    const auto t2 = std::chrono::steady_clock::now();
    eval.evaluate(tris, bs, out);
    const auto t3 = std::chrono::steady_clock::now();
    const double build = std::chrono::duration<double>(t1 - t0).count();
    const double run = std::chrono::duration<double>(t3 - t2).count();
    WARN("coarse triangles " << p.coarse.num_triangles() << ", pieces " << p.num_pieces() << " ("
                             << double(p.num_pieces()) / p.coarse.num_triangles() << " per coarse triangle), build "
                             << build << " s, " << q / run / 1e6 << " million evaluations/s");
}
