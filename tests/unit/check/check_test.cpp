#include <limits>
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>

#include "bpm/check.h"
#include "bpm/predicates.h"
#include "bpm/simplify.h"
#include "bpm/surface_io.h"
#include "fixtures_phi.h"
#include "fixtures_surfaces.h"

using namespace bpm;

namespace {

struct Named {
    std::string name;
    Surface surface;
};

std::vector<Named> all_fixtures() {
    return {{"tetrahedron", fixtures::tetrahedron()},
            {"cube", fixtures::cube()},
            {"cube res 2", fixtures::cube(2)},
            {"torus", fixtures::torus()},
            {"double torus", fixtures::double_torus()},
            {"disk", fixtures::disk()},
            {"two cubes", fixtures::two_cubes()},
            {"cylinder wedges", fixtures::cylinder_wedges()},
            {"octants", fixtures::octants()},
            {"hourglass", fixtures::hourglass()},
            {"moebius", fixtures::moebius()}};
}

std::string problems_text(const CheckResult& r) {
    std::string s = r.name + (r.passed ? " passed" : " failed") + ": " + r.summary;
    for (auto& p : r.problems) s += "\n  " + p.describe();
    return s;
}

void require_all_pass(const Parametrization& p) {
    for (const CheckResult& r : {check_format(p), check_intersections(p.coarse), check_intersections(p.original),
                                 check_topology(p), check_bijectivity(p)}) {
        INFO(problems_text(r));
        CHECK(r.passed);
    }
}

// First problem of a failed check.
CheckProblem first_problem(const CheckResult& r) {
    INFO(problems_text(r));
    REQUIRE_FALSE(r.passed);
    REQUIRE_FALSE(r.problems.empty());
    return r.problems.front();
}

int32_t triangle_of_piece(const Parametrization& p, int64_t q) {
    for (int32_t t = 0; t < p.num_coarse_triangles(); ++t)
        if (q < p.piece_offsets[t + 1]) return t;
    return -1;
}

void drop_piece(Parametrization& p, int64_t q) {
    const int32_t t = triangle_of_piece(p, q);
    p.pieces.erase(p.pieces.begin() + q);
    p.piece_original_triangle.erase(p.piece_original_triangle.begin() + q);
    for (size_t i = static_cast<size_t>(t) + 1; i < p.piece_offsets.size(); ++i) --p.piece_offsets[i];
}

}  // namespace

TEST_CASE("every fixture is free of self-intersections", "[check]") {
    for (const Named& f : all_fixtures()) {
        INFO(f.name);
        const CheckResult r = check_intersections(f.surface);
        INFO(problems_text(r));
        CHECK(r.passed);
        CHECK(r.count("triangles") == f.surface.num_triangles());
    }
}

TEST_CASE("identity parametrizations pass every check", "[check]") {
    for (const Named& f : all_fixtures()) {
        INFO(f.name);
        require_all_pass(fixtures::identity_parametrization(f.surface));
    }
}

TEST_CASE("refined parametrizations (nodes on coarse edges and inside) pass every check", "[check]") {
    for (const Named& f : all_fixtures()) {
        INFO(f.name);
        require_all_pass(fixtures::refined_parametrization(f.surface));
    }
}

TEST_CASE("parametrizations with edge crossings pass every check", "[check]") {
    for (const Surface& s : {fixtures::cube(), fixtures::two_cubes(2), fixtures::octants(), fixtures::double_torus()}) {
        const Parametrization p = fixtures::flipped_diagonal_parametrization(s);
        REQUIRE(p.num_pieces() == 2 * s.num_triangles());
        require_all_pass(p);
    }
}

TEST_CASE("the phi fixtures of the format tests pass every check", "[check]") {
    SECTION("subdivided octahedron") { require_all_pass(test::make_subdivided_octahedron(2)); }
    SECTION("height field with crossings") { require_all_pass(test::make_height_field(6, 2, test::default_height)); }
}

namespace {
// Reverses coarse triangle t of an identity parametrization: corners (c0, c2, c1), so
// its piece maps into the original triangle with negative orientation.
void reverse_coarse_triangle(Parametrization& p, int32_t t) {
    Tri& c = p.coarse.triangles[t];
    std::swap(c[1], c[2]);
    const int64_t n0 = p.node_offsets[t];
    std::swap(p.node_original_vertex[n0 + 1], p.node_original_vertex[n0 + 2]);
    fixtures::recompute_images(p);
}
}  // namespace

TEST_CASE("reversed images are allowed only where the original is not consistently oriented", "[check]") {
    SECTION("Moebius strip: a coarse triangle reversed against its original is fine") {
        Parametrization p = fixtures::identity_parametrization(fixtures::moebius());
        reverse_coarse_triangle(p, 5);
        CHECK(check_format(p).passed);
        const CheckResult r = check_bijectivity(p);
        INFO(problems_text(r));
        CHECK(r.passed);
        CHECK(r.count("reversed_pieces") == 1);
    }
    SECTION("torus: the same is an orientation flip") {
        Parametrization p = fixtures::identity_parametrization(fixtures::torus());
        reverse_coarse_triangle(p, 5);
        const CheckProblem e = first_problem(check_bijectivity(p));
        CHECK(e.id("coarse_triangle") == 5);
        CHECK(e.message.find("reversed orientation") != std::string::npos);
    }
}

TEST_CASE("mutations fail the right check and name the right element", "[check]") {
    SECTION("flip a piece") {
        Parametrization p = fixtures::refined_parametrization(fixtures::cube());
        const int64_t q = p.piece_offsets[5] + 3;
        std::swap(p.pieces[q][0], p.pieces[q][1]);
        CHECK(check_format(p).passed);
        const CheckProblem e = first_problem(check_bijectivity(p));
        CHECK(e.id("coarse_triangle") == 5);
        CHECK(e.id("piece") == q);
        CHECK(e.message.find("flipped") != std::string::npos);
    }
    SECTION("move a node across a piece edge") {
        Parametrization p = fixtures::refined_parametrization(fixtures::tetrahedron());
        const int64_t n = p.node_offsets[2] + 6;  // the interior node
        p.node_barycentric[n] = {0.125, 0.75, 0.125};  // into the quarter at corner 1
        CHECK(check_format(p).passed);
        const CheckProblem e = first_problem(check_bijectivity(p));
        CHECK(e.id("coarse_triangle") == 2);
        CHECK(e.id("piece") == p.piece_offsets[2] + 3);
    }
    SECTION("drop a piece") {
        Parametrization p = fixtures::refined_parametrization(fixtures::cube());
        drop_piece(p, p.piece_offsets[3] + 4);
        CHECK(check_format(p).passed);
        const CheckResult r = check_bijectivity(p);
        const CheckProblem e = first_problem(r);
        CHECK(e.id("coarse_triangle") == 3);
        bool uncovered = false;
        for (auto& pr : r.problems) uncovered = uncovered || pr.id("original_triangle") == 6 * 3 + 4;
        CHECK(uncovered);
    }
    SECTION("swap two node images") {
        Parametrization p = fixtures::refined_parametrization(fixtures::cube());
        const int64_t a = p.node_offsets[1] + 3, b = p.node_offsets[1] + 6;
        std::swap(p.node_image[a], p.node_image[b]);
        const CheckProblem e = first_problem(check_format(p));
        CHECK(e.id("node") == a);
        CHECK(e.message.find("image") != std::string::npos);
    }
    SECTION("swap two node identities (images follow)") {
        Parametrization p = fixtures::refined_parametrization(fixtures::cube());
        const int32_t t = 4;
        const int64_t a = p.node_offsets[t] + 3, b = p.node_offsets[t] + 4;
        std::swap(p.node_original_vertex[a], p.node_original_vertex[b]);
        fixtures::recompute_images(p);
        CHECK(check_format(p).passed);
        const CheckResult r = check_bijectivity(p);
        first_problem(r);
        bool names_t = false;
        for (auto& pr : r.problems) names_t = names_t || pr.id("coarse_triangle") == t;
        CHECK(names_t);
    }
    SECTION("index out of range") {
        Parametrization p = fixtures::refined_parametrization(fixtures::cube());
        const int64_t q = p.piece_offsets[7] + 2;
        p.pieces[q][1] = 99;
        const CheckProblem e = first_problem(check_format(p));
        CHECK(e.id("coarse_triangle") == 7);
        CHECK(e.id("piece") == q);
        CHECK(e.message.find("out of range") != std::string::npos);
        // the dependent checks refuse instead of crashing
        CHECK(first_problem(check_bijectivity(p)).message.find("not checked") != std::string::npos);
        CHECK(first_problem(check_topology(p)).message.find("not checked") != std::string::npos);
    }
    SECTION("original triangle index out of range") {
        Parametrization p = fixtures::refined_parametrization(fixtures::cube());
        p.piece_original_triangle[10] = -1;
        const CheckResult r = check_format(p);
        const CheckProblem e = first_problem(r);
        CHECK(e.id("piece") == 10);
        CHECK(r.problem_count == 1);
        CHECK(r.summary == "1 structural problem");  // not "1 structural problems"
    }
    SECTION("break a CSR offset") {
        Parametrization p = fixtures::refined_parametrization(fixtures::cube());
        p.node_offsets[2] = p.node_offsets[3] + 1;
        const CheckProblem e = first_problem(check_format(p));
        CHECK(e.id("coarse_triangle") == 2);
        CHECK(e.message.find("node_offsets") != std::string::npos);
        CHECK_FALSE(check_bijectivity(p).passed);
    }
    SECTION("move a coarse vertex so that two triangles intersect") {
        Parametrization p = fixtures::refined_parametrization(fixtures::cube());
        int32_t v = -1;
        for (int32_t i = 0; i < p.coarse.num_vertices(); ++i)
            if (p.coarse.vertices[i] == Vec3{1, 1, 1}) v = i;
        REQUIRE(v >= 0);
        p.coarse.vertices[v] = {0.5, 0.5, -0.5};
        const CheckResult r = check_intersections(p.coarse);
        const CheckProblem e = first_problem(r);
        const int64_t ta = e.id("triangle"), tb = e.id("other_triangle");
        REQUIRE(ta >= 0);
        REQUIRE(tb >= 0);
        auto has_v = [&](int64_t t) {
            const Tri& tri = p.coarse.triangles[t];
            return tri[0] == v || tri[1] == v || tri[2] == v;
        };
        CHECK((has_v(ta) || has_v(tb)));
        // the format check notices that the coarse vertex left its original position
        const CheckProblem f = first_problem(check_format(p));
        CHECK(f.id("coarse_vertex") == v);
        // and the original surface is still fine: the fault is in the result
        CHECK(check_intersections(p.original).passed);
    }
    SECTION("insert NaN") {
        Parametrization p = fixtures::refined_parametrization(fixtures::cube());
        const int64_t n = p.node_offsets[6] + 5;
        p.node_barycentric[n][1] = std::nan("");
        const CheckProblem e = first_problem(check_format(p));
        CHECK(e.id("node") == n);
        CHECK(e.message.find("non-finite") != std::string::npos);
        CHECK_FALSE(check_bijectivity(p).passed);
        Parametrization q = fixtures::refined_parametrization(fixtures::cube());
        q.original.vertices[3][2] = std::nan("");
        CHECK(first_problem(check_format(q)).id("original_vertex") == 3);
        CHECK(first_problem(check_intersections(q.original)).message.find("not checked") != std::string::npos);
    }
    SECTION("move an edge crossing on one side of a coarse edge") {
        Parametrization p = fixtures::flipped_diagonal_parametrization(fixtures::cube());
        const int64_t n = p.node_offsets[1] + 3;
        REQUIRE(p.node_kind[n] == NodeKind::EdgeCrossing);
        p.node_edge_parameter[n] = 0.25;
        fixtures::recompute_images(p);
        CHECK(check_format(p).passed);
        const CheckProblem e = first_problem(check_bijectivity(p));
        CHECK(e.id("coarse_triangle") == 1);
        CHECK(e.id("node") == n);
    }
    SECTION("a crossing on an edge the original surface does not have") {
        Parametrization p = fixtures::flipped_diagonal_parametrization(fixtures::cube());
        const int64_t n = p.node_offsets[0] + 3;
        const Tri& t0 = p.original.triangles[0];
        // the quad's other diagonal (b, d) is a coarse edge, not an original one
        const int32_t b = t0[1], d = p.original.triangles[1][2];
        p.node_original_edge[n] = {std::min(b, d), std::max(b, d)};
        fixtures::recompute_images(p);
        const CheckProblem e = first_problem(check_format(p));
        CHECK(e.id("node") == n);
        CHECK(e.message.find("does not exist") != std::string::npos);
    }
    SECTION("a coarse patch that differs from its original triangles") {
        Parametrization p = fixtures::refined_parametrization(fixtures::two_cubes());
        p.coarse.patches[0] = 77;
        const CheckResult r = check_topology(p);
        const CheckProblem e = first_problem(r);
        CHECK(e.id("coarse_triangle") == 0);
        CHECK(check_bijectivity(p).passed);
    }
    SECTION("a coarse surface with a different topology") {
        // Coarse = a cube with one triangle pair's diagonal made into a fold: use a
        // tetrahedron's original against a cube-shaped coarse surface of another genus
        // by pretending: compare the torus with itself through a parametrization whose
        // coarse surface lost a triangle (a hole).
        Parametrization p = fixtures::identity_parametrization(fixtures::torus());
        p.coarse.triangles.pop_back();
        p.coarse.patches.pop_back();
        p.node_offsets.pop_back();
        p.piece_offsets.pop_back();
        p.node_kind.resize(p.node_offsets.back());
        p.node_barycentric.resize(p.node_offsets.back());
        p.node_image.resize(p.node_offsets.back());
        p.node_original_vertex.resize(p.node_offsets.back());
        p.node_original_edge.resize(p.node_offsets.back());
        p.node_edge_parameter.resize(p.node_offsets.back());
        p.pieces.pop_back();
        p.piece_original_triangle.pop_back();
        CHECK(check_format(p).passed);
        const CheckResult topo = check_topology(p);
        INFO(problems_text(topo));
        CHECK_FALSE(topo.passed);
        const CheckResult bij = check_bijectivity(p);
        const CheckProblem e = first_problem(bij);
        CHECK(e.id("original_triangle") == p.original.num_triangles() - 1);
    }
}

TEST_CASE("the intersection check agrees with the predicate on random small-integer pairs", "[check]") {
    // Small integer coordinates make coplanar, collinear and touching configurations
    // common, which is where the check's shortcuts for neighbouring triangles could
    // go wrong.
    uint32_t state = 12345;
    auto next = [&]() {
        state = state * 1664525u + 1013904223u;
        return static_cast<double>(static_cast<int>((state >> 16) % 5) - 2);
    };
    int tested = 0, intersecting = 0;
    for (int iter = 0; iter < 20000; ++iter) {
        Surface s;
        for (int v = 0; v < 6; ++v) s.vertices.push_back({next(), next(), next() * (iter % 3 == 0 ? 0.0 : 1.0)});
        const int shared = iter % 3;  // 0, 1 or 2 shared vertices
        Tri a{0, 1, 2}, b{3, 4, 5};
        if (shared >= 1) b[(iter / 3) % 3] = a[0];
        if (shared >= 2) b[(iter / 3 + 1) % 3] = a[(iter / 9) % 2 + 1];
        s.triangles = {a, b};
        s.patches = {0, 0};
        const Vec3 pa[3] = {s.vertices[a[0]], s.vertices[a[1]], s.vertices[a[2]]};
        const Vec3 pb[3] = {s.vertices[b[0]], s.vertices[b[1]], s.vertices[b[2]]};
        if (collinear3d(pa[0], pa[1], pa[2]) || collinear3d(pb[0], pb[1], pb[2])) continue;
        int map[3] = {-1, -1, -1};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                if (a[i] == b[j]) map[i] = j;
        const bool expected = triangles_intersect_improperly(pa, pb, map);
        const CheckResult r = check_intersections(s);
        INFO("iteration " << iter);
        CHECK(r.passed == !expected);
        ++tested;
        intersecting += expected;
    }
    CHECK(tested > 5000);
    CHECK(intersecting > 500);
    CHECK(tested - intersecting > 500);
}

TEST_CASE("quality gates", "[check]") {
    Surface s = fixtures::cube();
    CheckOptions o;
    o.max_aspect_ratio = 3.0;  // right isosceles triangles have R/r = 1 + sqrt(2) = 2.414
    CHECK(check_quality(s, o).passed);
    o.max_aspect_ratio = 2.2;
    const CheckResult r = check_quality(s, o);
    CHECK_FALSE(r.passed);
    CHECK(r.problem_count == 12);
    REQUIRE(r.worst);
    CHECK(r.worst->value == Approx(1 + std::sqrt(2.0)));
    CheckOptions a;
    a.min_angle_degrees = 44.0;
    CHECK(check_quality(s, a).passed);
    a.min_angle_degrees = 46.0;
    CHECK_FALSE(check_quality(s, a).passed);
}

TEST_CASE("report text and JSON", "[check]") {
    CheckReport report;
    report.input = "dir/\"odd\"\\name.bpm";
    report.checks.push_back(check_intersections(fixtures::cube()));
    CheckResult bad;
    bad.name = "bijectivity";
    bad.add_problem({{{"coarse_triangle", 17}, {"piece", 4}}, "line1\nline2\t\"q\" \x01"}, 10);
    bad.add_problem({{{"coarse_triangle", 18}}, "second"}, 10);
    bad.add_problem({{{"coarse_triangle", 19}}, "third"}, 10);
    report.checks.push_back(bad);
    const std::string text = check_report_to_text(report);
    CHECK(text.find("PASS intersections  12 triangles, 0 intersecting pairs\n") == 0);
    CHECK(text.find("FAIL bijectivity  3 problems; first: coarse triangle 17 piece 4: line1") != std::string::npos);
    const std::string json = check_report_to_json(report);
    CHECK(json.find("\"input\": \"dir/\\\"odd\\\"\\\\name.bpm\"") != std::string::npos);
    CHECK(json.find("line1\\nline2\\t\\\"q\\\" \\u0001") != std::string::npos);
    CHECK(json.find("\"ids\": {\"coarse_triangle\": 17, \"piece\": 4}") != std::string::npos);
    CHECK(json.find("\"passed\": false") != std::string::npos);
    CHECK(json.find("\"problem_count\": 3") != std::string::npos);
    // no raw control characters inside strings
    for (char c : json) CHECK((c == '\n' || static_cast<unsigned char>(c) >= 0x20));
    CHECK_FALSE(report.passed());
}

TEST_CASE("run_checks runs the selection", "[check]") {
    BpmFile file;
    file.param = fixtures::refined_parametrization(fixtures::octants());
    CheckSelection sel;
    sel.original_intersections = true;
    CheckOptions options;
    options.max_aspect_ratio = 10;
    const CheckReport r = run_checks(file, sel, options);
    std::vector<std::string> names;
    for (auto& c : r.checks) names.push_back(c.name);
    CHECK(names == std::vector<std::string>{"format", "original-intersections", "intersections", "topology",
                                            "junctions", "bijectivity", "quality"});
    CHECK(r.passed());
}

TEST_CASE("self-intersections of the real meshes", "[check][meshes]") {
    const std::string dir = BPM_MESH_DIR;
    // Expected counts cross-checked with CGAL::Polygon_mesh_processing::self_intersections.
    const std::vector<std::pair<const char*, int64_t>> meshes{
        {"femur.off", 0},         {"fandisk.off", 0},          {"elephant.off", 0}, {"armadillo.off", 0},
        {"mech-holes-shark.off", 0}, {"bones.off", 366}, {"man.off", 848}};
    for (const auto& [name, expected] : meshes) {
        const std::string path = dir + "/" + name;
        if (!std::filesystem::exists(path)) {
            WARN("missing " << path);
            continue;
        }
        Surface s;
        try {
            s = read_surface(path);
        } catch (const std::exception& e) {
            // read_surface refuses invalid input (duplicate vertices ...); fall back to
            // the plain loader so the intersection check still sees the mesh.
            WARN(name << ": read_surface: " << e.what());
            s = fixtures::load_off(path);
            s.patches.assign(s.triangles.size(), 0);
        }
        const auto start = std::chrono::steady_clock::now();
        const CheckResult r = check_intersections(s);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        WARN(name << ": " << r.summary << " (" << seconds << " s)"
                  << (r.problems.empty() ? "" : "; first: " + r.problems.front().describe()));
        CHECK(r.count("triangles") == s.num_triangles());
        CHECK(r.count("intersecting_pairs") == expected);
        // with the plain loader, the result must not depend on how the file was read
        const CheckResult again = check_intersections(fixtures::load_off(path));
        CHECK(again.count("intersecting_pairs") == r.count("intersecting_pairs"));
    }
}

TEST_CASE("intersection check on a million triangles", "[.perf]") {
    const Surface s = fixtures::torus(1000, 500);
    auto start = std::chrono::steady_clock::now();
    const CheckResult r = check_intersections(s);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    WARN("torus 1M: " << r.summary << " in " << seconds << " s, candidates " << r.count("candidate_pairs"));
    CHECK(r.passed);
    const Surface sub = fixtures::subdivide(fixtures::subdivide(fixtures::load_off(std::string(BPM_MESH_DIR) + "/armadillo.off")));
    start = std::chrono::steady_clock::now();
    const CheckResult ra = check_intersections(sub);
    WARN("armadillo subdivided twice: " << ra.summary << ", candidates " << ra.count("candidate_pairs") << " in "
                                        << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
                                        << " s");
}

TEST_CASE("parametrization checks on a million pieces", "[.perf]") {
    const Parametrization p = fixtures::refined_parametrization(fixtures::torus(300, 280));
    REQUIRE(p.num_pieces() > 1000000);
    for (const auto& [name, run] : std::vector<std::pair<std::string, std::function<CheckResult()>>>{
             {"format", [&] { return check_format(p); }},
             {"topology", [&] { return check_topology(p); }},
             {"bijectivity", [&] { return check_bijectivity(p); }},
             {"original-intersections", [&] { return check_intersections(p.original); }}}) {
        const auto start = std::chrono::steady_clock::now();
        const CheckResult r = run();
        WARN(name << ": " << r.summary << " in "
                  << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s");
        CHECK(r.passed);
    }
}

TEST_CASE("random discrete mutations never pass and never crash", "[check]") {
    // Every mutation below breaks phi (none is a no-op), so at least one of the
    // parametrization checks must fail, whatever the element.
    const Parametrization base = fixtures::refined_parametrization(fixtures::two_cubes());
    uint32_t state = 777;
    auto rnd = [&](int64_t n) {
        state = state * 1664525u + 1013904223u;
        return static_cast<int64_t>((state >> 8) % static_cast<uint32_t>(n));
    };
    int mutations = 0;
    for (int iter = 0; iter < 300; ++iter) {
        Parametrization p = base;
        const int kind = iter % 4;
        std::string what;
        if (kind == 0) {  // one corner of one piece to another local node
            const int64_t q = rnd(p.num_pieces());
            const int32_t t = triangle_of_piece(p, q);
            const int64_t count = p.node_offsets[t + 1] - p.node_offsets[t];
            const int k = static_cast<int>(rnd(3));
            const int32_t old = p.pieces[q][k];
            const int32_t now = static_cast<int32_t>((old + 1 + rnd(count - 1)) % count);
            p.pieces[q][k] = now;
            what = "piece " + std::to_string(q) + " corner " + std::to_string(k);
        } else if (kind == 1) {  // a piece into another original triangle
            const int64_t q = rnd(p.num_pieces());
            p.piece_original_triangle[q] =
                static_cast<int32_t>((p.piece_original_triangle[q] + 1 + rnd(p.original.num_triangles() - 1)) %
                                     p.original.num_triangles());
            what = "piece " + std::to_string(q) + " original triangle";
        } else if (kind == 2) {  // a node names another original vertex (image follows)
            const int64_t n = rnd(p.num_nodes());
            p.node_original_vertex[n] =
                static_cast<int32_t>((p.node_original_vertex[n] + 1 + rnd(p.original.num_vertices() - 1)) %
                                     p.original.num_vertices());
            fixtures::recompute_images(p);
            what = "node " + std::to_string(n) + " identity";
        } else {  // two corners of a piece swapped
            const int64_t q = rnd(p.num_pieces());
            std::swap(p.pieces[q][0], p.pieces[q][2]);
            what = "piece " + std::to_string(q) + " swapped";
        }
        INFO(what);
        const bool all_pass = check_format(p).passed && check_topology(p).passed && check_bijectivity(p).passed;
        CHECK_FALSE(all_pass);
        ++mutations;
    }
    CHECK(mutations == 300);
}

TEST_CASE("surface-level intersection cases", "[check]") {
    SECTION("a duplicate triangle") {
        Surface s = fixtures::cube();
        s.triangles.push_back({s.triangles[3][1], s.triangles[3][2], s.triangles[3][0]});
        s.patches.push_back(1);
        const CheckResult r = check_intersections(s);
        const CheckProblem e = first_problem(r);
        CHECK(e.id("triangle") == 3);
        CHECK(e.id("other_triangle") == 12);
        CHECK(e.message.find("same three vertices") != std::string::npos);
    }
    SECTION("a coplanar fold over an edge") {
        Surface s = fixtures::disk(2);
        // fold the last triangle's free corner back over its neighbour, in the plane
        s.vertices[s.triangles.back()[2]] = {1.5, 1.2, 0.0};
        const CheckResult r = check_intersections(s);
        CHECK_FALSE(r.passed);
    }
    SECTION("a degenerate triangle is reported once, not paired") {
        Surface s = fixtures::disk(2);
        s.vertices.push_back({0.5, 0.0, 0.0});  // on the edge (0,0)-(1,0)
        s.triangles.push_back({0, 1, static_cast<int32_t>(s.vertices.size() - 1)});
        s.patches.push_back(0);
        const CheckResult r = check_intersections(s);
        const CheckProblem e = first_problem(r);
        CHECK(e.id("triangle") == s.num_triangles() - 1);
        CHECK(e.message.find("degenerate") != std::string::npos);
        CHECK(r.count("degenerate_triangles") == 1);
    }
    SECTION("two surfaces touching at a point without sharing the vertex") {
        Surface s = fixtures::tetrahedron();
        Surface t = fixtures::tetrahedron();
        const int32_t off = s.num_vertices();
        for (auto v : t.vertices) s.vertices.push_back({-v[0], -v[1], -v[2]});  // touches at the origin
        for (auto tri : t.triangles) s.triangles.push_back({tri[0] + off, tri[2] + off, tri[1] + off});
        s.patches.resize(s.triangles.size(), 0);
        CHECK_FALSE(check_intersections(s).passed);
        // merging the two origin vertices makes it a proper vertex contact (an hourglass)
        for (auto& tri : s.triangles)
            for (auto& v : tri)
                if (v == off) v = 0;
        CHECK(check_intersections(s).passed);
    }
}

// ---- distance (--max-distance) ----------------------------------------------------

namespace {

const WorstValue* measure(const CheckResult& r, const std::string& name) {
    for (const WorstValue& m : r.measures)
        if (m.name == name) return &m;
    return nullptr;
}

int64_t id_of(const std::vector<std::pair<std::string, int64_t>>& ids, const std::string& kind) {
    for (const auto& [k, v] : ids)
        if (k == kind) return v;
    return -1;
}

// S0: the unit square as a 2 x 2 grid with the centre vertex lifted by h (a tent);
// S: the flat square (two triangles). Every point of S0 is at most h above the plane
// of S, the apex exactly h, and every point of S is at most h below S0, so both
// Hausdorff distances between S and S0 are exactly h.
Parametrization tent(double h) {
    return test::make_height_field(2, 1, [h](double x, double y) { return x == 0.5 && y == 0.5 ? h : 0.0; });
}

}  // namespace

TEST_CASE("distance gate: a coarse surface that deviates by a known amount fails below it and passes above",
          "[check][distance]") {
    const double h = 0.1;
    const Parametrization p = tent(h);
    require_all_pass(p);
    const double expected = h / bounding_box_diagonal(p.original);  // h / sqrt(2 + h^2)
    CheckOptions o;
    o.max_error = 0.99 * expected;
    const CheckResult below = check_distance(p, o);
    INFO(problems_text(below));
    CHECK_FALSE(below.passed);
    REQUIRE(below.worst);
    CHECK(below.worst->name == "coarse_hausdorff");
    CHECK(below.worst->value == Approx(expected).epsilon(1e-12));
    // The apex is where S0 is farthest from S: in original triangles at vertex 4, over
    // the coarse triangles (both touch the apex's position on the diagonal).
    CHECK(id_of(below.worst->ids, "coarse_triangle") >= 0);
    CHECK(id_of(below.worst->ids, "original_triangle") >= 0);
    REQUIRE(below.problem_count == 1);
    CHECK(below.problems[0].message.find("coarse surface") != std::string::npos);
    // The exact bound max |phi(x) - x| is attained at the apex node: also h.
    REQUIRE(measure(below, "coarse_to_original_bound"));
    CHECK(measure(below, "coarse_to_original_bound")->value == Approx(expected).epsilon(1e-12));
    REQUIRE(measure(below, "original_to_coarse"));
    CHECK(measure(below, "original_to_coarse")->value == Approx(expected).epsilon(1e-12));
    REQUIRE(measure(below, "coarse_to_original"));
    CHECK(measure(below, "coarse_to_original")->value <= expected * (1 + 1e-12));
    CHECK(measure(below, "coarse_to_original")->value > 0.5 * expected);
    REQUIRE(measure(below, "image_hausdorff"));
    CHECK(measure(below, "image_hausdorff")->value < 1e-14);

    o.max_error = 1.01 * expected;
    const CheckResult above = check_distance(p, o);
    INFO(problems_text(above));
    CHECK(above.passed);
    CHECK(above.worst->value == below.worst->value);
}

TEST_CASE("distance gate: a broken image of phi is caught where it is", "[check][distance]") {
    Parametrization p = test::make_height_field(8, 2, test::default_height);
    CheckOptions o;
    o.max_error = 0.2;  // the coarse surface is about 0.09 of the diagonal away
    const CheckResult good = check_distance(p, o);
    INFO(problems_text(good));
    CHECK(good.passed);
    CHECK(measure(good, "image_hausdorff")->value < 1e-14);
    // Move the image of one node inside coarse triangle 5 off the surface.
    int64_t node = -1;
    for (int64_t n = p.node_offsets[5]; n < p.node_offsets[6] && node < 0; ++n)
        if (p.node_kind[n] == NodeKind::OriginalVertex) node = n;
    REQUIRE(node >= 0);
    p.node_image[node][2] += 2.0;
    const CheckResult bad = check_distance(p, o);
    INFO(problems_text(bad));
    CHECK_FALSE(bad.passed);
    const WorstValue* image = measure(bad, "image_hausdorff");
    REQUIRE(image);
    CHECK(image->value > 0.5);
    CHECK(id_of(image->ids, "coarse_triangle") == 5);
    REQUIRE(bad.problem_count >= 1);
    CHECK(bad.problems[0].message.find("phi's image") != std::string::npos);
    CHECK(bad.problems[0].id("coarse_triangle") == 5);
}

TEST_CASE("distance gate: coordinates too large for double-precision distances are refused, not measured",
          "[check][distance]") {
    // Found by fuzz_read_bpm: a node image of 8e252 overflowed to inf/NaN in squared
    // distances, and NaN handed to CGAL's exact number types raises SIGFPE.
    for (double huge : {8e252, 1e200, -1e151}) {
        Parametrization p = test::make_height_field(8, 2, test::default_height);
        CheckOptions o;
        o.max_error = 0.2;
        p.node_image[p.node_offsets[3]][0] = huge;
        const CheckResult r = check_distance(p, o);
        INFO(problems_text(r));
        CHECK_FALSE(r.passed);
        REQUIRE(r.problem_count == 1);
        CHECK(r.problems[0].message.find("too large") != std::string::npos);
    }
    Parametrization p = test::make_height_field(8, 2, test::default_height);
    CheckOptions o;
    o.max_error = 0.2;
    p.original.vertices[0][1] = std::numeric_limits<double>::infinity();
    const CheckResult r = check_distance(p, o);
    CHECK_FALSE(r.passed);
    REQUIRE(r.problem_count >= 1);
}

TEST_CASE("distance gate: pieces too small for CGAL's closest points are measured, not handed to it",
          "[check][distance]") {
    // Found by fuzz_read_bpm: node images of 1e-155 made pieces whose squared normals
    // underflow; CGAL's closest point on them is NaN, and its exact fallback raised SIGFPE.
    for (double scale : {1e-155, 1e-90, 0.0}) {
        Parametrization p = test::make_height_field(8, 2, test::default_height);
        CheckOptions o;
        o.max_error = 0.2;
        for (int t : {0, 3})
            for (int64_t n = p.node_offsets[t]; n < p.node_offsets[t + 1]; ++n)
                for (int k = 0; k < 3; ++k) p.node_image[n][k] *= scale;
        const CheckResult r = check_distance(p, o);
        INFO("scale " << scale << ": " << problems_text(r));
        // Measured: the collapsed pieces are far from S0 (the intact file: about 1e-15).
        const WorstValue* image = measure(r, "image_hausdorff");
        REQUIRE(image);
        CHECK(image->value > 0.1);
    }
    {
        // The fuzzer's file: the spec example with every node image within 1e-154 of the origin.
        Parametrization p = test::make_two_triangles_example().param;
        const double a = 7.458340731200207e-155, b = 4.475004438720124e-155;
        const std::vector<Vec3> images = {{0, 0, 0}, {a, 0, b}, {a, a, b}, {a, a, 0},
                                          {0, 0, 0}, {a, a, b}, {0, a, b}, {a, a, 0}};
        REQUIRE(p.node_image.size() == images.size());
        p.node_image = images;
        CheckOptions o;
        o.max_error = 0.01;
        o.error_sample_spacing = 0.05;
        const CheckResult r = check_distance(p, o);
        INFO(problems_text(r));
        CHECK_FALSE(r.passed);
        const WorstValue* image = measure(r, "image_hausdorff");
        REQUIRE(image);
        CHECK(image->value > 0.5);
    }
    // A whole surface that small is refused.
    Parametrization p = test::make_height_field(8, 2, test::default_height);
    for (auto* points : {&p.original.vertices, &p.coarse.vertices, &p.node_image})
        for (Vec3& x : *points)
            for (double& c : x) c *= 1e-40;
    CheckOptions o;
    o.max_error = 0.2;
    const CheckResult r = check_distance(p, o);
    INFO(problems_text(r));
    CHECK_FALSE(r.passed);
    REQUIRE(r.problem_count == 1);
    CHECK(r.problems[0].message.find("too small") != std::string::npos);
}

TEST_CASE("distance: sampled estimates respect the exact bound and are deterministic", "[check][distance]") {
    for (const Parametrization& p : {test::make_height_field(12, 3, test::default_height),
                                     test::make_subdivided_octahedron(3)}) {
        CheckOptions o;
        o.max_error = 1.0;
        o.error_sample_spacing = 1e-2;
        const CheckResult a = check_distance(p, o);
        INFO(problems_text(a));
        CHECK(a.passed);
        const double bound = measure(a, "coarse_to_original_bound")->value;
        // The one-sided distance S -> S0 is at most max |phi(x) - x| (phi's image is S0).
        CHECK(measure(a, "coarse_to_original")->value <= bound * (1 + 1e-9));
        CHECK(measure(a, "coarse_to_original")->value > 0.1 * bound);
        CHECK(measure(a, "image_hausdorff")->value < 1e-14);
        CHECK(a.count("samples") > 0);
        const CheckResult b = check_distance(p, o);
        REQUIRE(a.measures.size() == b.measures.size());
        for (size_t i = 0; i < a.measures.size(); ++i) {
            CHECK(a.measures[i].value == b.measures[i].value);
            CHECK(a.measures[i].ids == b.measures[i].ids);
        }
        // A finer grid samples more and still stays below the exact bound.
        CHECK(measure(a, "sample_spacing")->value <= 1e-2);
        o.error_sample_spacing = 0.25e-2;
        const CheckResult fine = check_distance(p, o);
        CHECK(fine.count("samples") > a.count("samples"));
        CHECK(measure(fine, "sample_spacing")->value <= 0.25e-2);
        CHECK(measure(fine, "coarse_to_original")->value <= bound * (1 + 1e-9));
    }
}

TEST_CASE("distance: a flat face whose coarse triangles cover many original ones needs few closest-point queries",
          "[check][distance]") {
    // A CAD face as gmsh and OpenCASCADE write it: flat up to ~1e-11 (rounding of the
    // geometry kernel, above the checker's rounding floor), simplified to a few large
    // coarse triangles. Each coarse triangle here covers 2048 original ones, more than the
    // local candidates the checker tries, and every one of its 33 153 samples asked the
    // AABB tree (33 187 queries before, 60 now; a gmsh L-block at 1 %: 980 000 queries, 6.7 s of
    // bpm-check --max-distance). The original triangle phi maps a sample into bounds its
    // distance first; only samples that could raise the maximum are queried.
    const double amplitude = 3e-11;
    const Parametrization p = test::make_height_field(
        32, 1, [amplitude](double x, double y) { return amplitude * std::sin(40 * x) * std::cos(37 * y); });
    CheckOptions o;
    o.max_error = 0.01;
    const CheckResult r = check_distance(p, o);
    INFO(problems_text(r));
    CHECK(r.passed);
    INFO("samples " << r.count("samples") << ", closest-point queries " << r.count("closest_point_queries"));
    CHECK(r.count("samples") > 60000);
    CHECK(r.count("closest_point_queries") < r.count("samples") / 100);
    // The same distance as before (3.53807e-11): S -> S0 is attained at a node, where
    // the exact bound max |phi(x) - x| is (the surfaces are flat up to 1e-11).
    REQUIRE(measure(r, "coarse_to_original"));
    const double bound = measure(r, "coarse_to_original_bound")->value;
    CHECK(measure(r, "coarse_to_original")->value <= bound * (1 + 1e-9));
    CHECK(measure(r, "coarse_to_original")->value == Approx(bound).epsilon(1e-6));
}

TEST_CASE("distance check of a file in run_checks and the JSON report", "[check][distance]") {
    BpmFile written;
    written.param = tent(0.1);
    const BpmFile file = read_bpm_from_memory(write_bpm_to_memory(written), "tent.bpm");
    const double expected = 0.1 / bounding_box_diagonal(file.param.original);
    CheckOptions options;
    options.max_error = 1.01 * expected;
    CHECK(run_checks(file, CheckSelection{}, options).passed());
    options.max_error = 0.99 * expected;
    const CheckReport r = run_checks(file, CheckSelection{}, options);
    REQUIRE(r.find("distance"));
    CHECK_FALSE(r.find("distance")->passed);
    CHECK(r.find("format")->passed);
    CHECK(r.find("bijectivity")->passed);
    CHECK_FALSE(r.passed());
    const std::string json = check_report_to_json(r);
    CHECK(json.find("\"measures\": [") != std::string::npos);
    CHECK(json.find("{\"name\": \"coarse_to_original_bound\", \"value\": ") != std::string::npos);
    // Checks without measures keep their JSON as before.
    CheckReport plain;
    plain.checks.push_back(check_intersections(fixtures::cube()));
    CHECK(check_report_to_json(plain).find("measures") == std::string::npos);
}

// ---- replay of recorded simplification steps ---------------------------------------

namespace {

// Simplifies `s` with the removals recorded, as bpm-simplify --record-steps does.
BpmFile simplified_with_steps(const Surface& s, double ratio) {
    SimplifyOptions o;
    o.target_ratio = ratio;
    o.record_steps = true;
    BpmFile f;
    SimplifyResult r = simplify(s, o, Context{}, f.param);
    REQUIRE(r.steps);
    REQUIRE(r.steps->num_steps() == r.removed);
    f.simplification_steps = std::move(r.steps);
    return f;
}

bool has_vertex(const Tri& t, int32_t v) { return t[0] == v || t[1] == v || t[2] == v; }

// The surface after applying steps [0, count) without any check (test oracle).
struct PlainReplay {
    std::vector<Tri> triangles;
    explicit PlainReplay(const Surface& s) : triangles(s.triangles) {}
    void apply(const SimplificationSteps& st, int64_t s) {
        std::vector<Tri> kept;
        for (const Tri& t : triangles)
            if (!has_vertex(t, st.vertex[s])) kept.push_back(t);
        for (int64_t j = st.triangle_offsets[s]; j < st.triangle_offsets[s + 1]; ++j) kept.push_back(st.triangles[j]);
        triangles = std::move(kept);
    }
    bool has_edge(int32_t a, int32_t b) const {
        for (const Tri& t : triangles)
            if (has_vertex(t, a) && has_vertex(t, b)) return true;
        return false;
    }
};

// The boundary cycle of the recorded triangles of step s, if they form one disk whose
// boundary is a simple cycle (a removal of a regular vertex); else empty.
std::vector<int32_t> recorded_cycle(const SimplificationSteps& st, int64_t s) {
    std::map<std::pair<int32_t, int32_t>, int> count;
    for (int64_t j = st.triangle_offsets[s]; j < st.triangle_offsets[s + 1]; ++j)
        for (int k = 0; k < 3; ++k) {
            int32_t a = st.triangles[j][k], b = st.triangles[j][(k + 1) % 3];
            ++count[{std::min(a, b), std::max(a, b)}];
        }
    std::map<int32_t, std::vector<int32_t>> next;
    for (const auto& [e, c] : count)
        if (c == 1) {
            next[e.first].push_back(e.second);
            next[e.second].push_back(e.first);
        }
    for (const auto& [v, list] : next)
        if (list.size() != 2) return {};
    std::vector<int32_t> cycle{next.begin()->first};
    int32_t prev = -1, cur = cycle[0];
    while (true) {
        const int32_t n = next[cur][0] != prev ? next[cur][0] : next[cur][1];
        if (n == cycle[0]) break;
        cycle.push_back(n);
        prev = cur;
        cur = n;
        if (cycle.size() > next.size()) return {};
    }
    if (cycle.size() != next.size() ||
        st.triangle_offsets[s + 1] - st.triangle_offsets[s] != static_cast<int64_t>(cycle.size()) - 2)
        return {};
    return cycle;
}

std::string all_problems(const CheckResult& r) {
    std::string s;
    for (const auto& p : r.problems) s += p.describe() + "\n";
    return s;
}

}  // namespace

TEST_CASE("recorded simplifications replay clean", "[check][replay]") {
    struct Case {
        std::string name;
        Surface surface;
        double ratio;
        bool feature_lines;  // expect half-disk removals along boundaries / sheets
    };
    const std::vector<Case> cases{{"torus", fixtures::torus(24, 16), 0.1, false},
                                  {"disk (boundary)", fixtures::disk(8), 0.2, true},
                                  {"two cubes (3 sheets)", fixtures::two_cubes(4), 0.2, true},
                                  {"cylinder wedges", fixtures::cylinder_wedges(12, 3), 0.3, true},
                                  {"octants", fixtures::octants(3), 0.3, true},
                                  {"hourglass", fixtures::hourglass(12), 0.5, false},
                                  {"moebius", fixtures::moebius(24), 0.5, true}};
    for (const Case& c : cases) {
        INFO(c.name);
        const BpmFile f = simplified_with_steps(c.surface, c.ratio);
        REQUIRE(f.simplification_steps->num_steps() > 0);
        CheckOptions o;
        o.replay_check_interval = 1;  // the full invariants after every step
        const CheckResult r = check_replay(f, o);
        INFO(problems_text(r));
        CHECK(r.passed);
        CHECK(r.count("replayed_steps") == f.simplification_steps->num_steps());
        CHECK(r.count("full_topology_checks") == f.simplification_steps->num_steps());
        CHECK(r.count("triangles") == f.param.coarse.num_triangles());
        if (c.feature_lines) CHECK(r.count("feature_line_removals") > 0);
        // The record survives the file format.
        const BpmFile g = read_bpm_from_memory(write_bpm_to_memory(f), "mem");
        REQUIRE(g.simplification_steps);
        CHECK(g.simplification_steps->vertex == f.simplification_steps->vertex);
        CHECK(check_replay(g).passed);
    }
}

TEST_CASE("replay: a step whose retriangulation uses an existing edge is caught at that step", "[check][replay]") {
    const BpmFile f = simplified_with_steps(fixtures::torus(24, 16), 0.05);
    REQUIRE(check_replay(f).passed);
    const SimplificationSteps& st = *f.simplification_steps;
    // Find a step whose link polygon has a chord that is already an edge (the simplifier
    // must have avoided it) and replace its triangles by the fan through that chord.
    PlainReplay state(f.param.original);
    int64_t tampered = -1;
    SimplificationSteps bad = st;
    for (int64_t s = 0; s < st.num_steps() && tampered < 0; ++s) {
        const std::vector<int32_t> cycle = recorded_cycle(st, s);
        const int32_t n = static_cast<int32_t>(cycle.size());
        for (int32_t i = 0; i < n && tampered < 0; ++i)
            for (int32_t j = 2; j + 1 < n && tampered < 0; ++j) {
                const int32_t x = cycle[i], y = cycle[(i + j) % n];
                if (!state.has_edge(x, y)) continue;
                for (int32_t k = 1; k + 1 < n; ++k)
                    bad.triangles[st.triangle_offsets[s] + k - 1] = {x, cycle[(i + k) % n], cycle[(i + k + 1) % n]};
                tampered = s;
            }
        state.apply(st, s);
    }
    REQUIRE(tampered > 0);
    BpmFile g = f;
    g.simplification_steps = bad;
    const CheckResult r = check_replay(g);
    INFO(problems_text(r));
    REQUIRE_FALSE(r.passed);
    CHECK(r.problems[0].id("step") == tampered);
    CHECK(r.problems[0].id("original_vertex") == st.vertex[tampered]);
    CHECK(all_problems(r).find("is already an edge of the surface (local condition of Conjecture 2.1)") !=
          std::string::npos);
    CHECK(r.count("replayed_steps") == tampered);
}

TEST_CASE("replay: a step that does not fill the hole is caught at that step", "[check][replay]") {
    const BpmFile f = simplified_with_steps(fixtures::two_cubes(4), 0.2);
    SimplificationSteps st = *f.simplification_steps;
    const int64_t s = st.num_steps() / 2;
    // Drop the last triangle of step s: the surface would get a hole (a boundary loop).
    const int64_t drop = st.triangle_offsets[s + 1] - 1;
    st.triangles.erase(st.triangles.begin() + drop);
    st.triangle_patches.erase(st.triangle_patches.begin() + drop);
    for (int64_t i = s + 1; i < static_cast<int64_t>(st.triangle_offsets.size()); ++i) --st.triangle_offsets[i];
    BpmFile g = f;
    g.simplification_steps = st;
    const CheckResult r = check_replay(g);
    INFO(problems_text(r));
    REQUIRE_FALSE(r.passed);
    CHECK(r.problems[0].id("step") == s);
    CHECK(r.problems[0].id("original_vertex") == st.vertex[s]);
    CHECK(all_problems(r).find("in no recorded triangle") != std::string::npos);
}

TEST_CASE("replay: a wrong patch, a repeated vertex and a record that stops early", "[check][replay]") {
    const BpmFile f = simplified_with_steps(fixtures::two_cubes(4), 0.2);
    const SimplificationSteps& st = *f.simplification_steps;
    SECTION("a new triangle with the patch of another material") {
        SimplificationSteps bad = st;
        const int64_t s = st.num_steps() / 3;
        bad.triangle_patches[st.triangle_offsets[s]] += 1000;
        BpmFile g = f;
        g.simplification_steps = bad;
        const CheckResult r = check_replay(g);
        INFO(problems_text(r));
        REQUIRE_FALSE(r.passed);
        CHECK(r.problems[0].id("step") == s);
        CHECK(all_problems(r).find("has patch") != std::string::npos);
    }
    SECTION("a vertex removed twice") {
        SimplificationSteps bad = st;
        bad.append(st.vertex[0], {st.triangles[0]}, {st.triangle_patches[0]});
        BpmFile g = f;
        g.simplification_steps = bad;
        const CheckResult r = check_replay(g);
        INFO(problems_text(r));
        REQUIRE_FALSE(r.passed);
        CHECK(r.problems[0].id("step") == st.num_steps());
        CHECK(r.problems[0].message.find("has no triangles") != std::string::npos);
    }
    SECTION("the last step missing: the result is not the coarse surface") {
        SimplificationSteps bad = st;
        const int64_t last = st.num_steps() - 1;
        bad.vertex.pop_back();
        bad.triangle_offsets.pop_back();
        bad.triangles.resize(static_cast<size_t>(bad.triangle_offsets.back()));
        bad.triangle_patches.resize(bad.triangles.size());
        BpmFile g = f;
        g.simplification_steps = bad;
        const CheckResult r = check_replay(g);
        INFO(problems_text(r));
        REQUIRE_FALSE(r.passed);
        CHECK(r.count("replayed_steps") == last);
        CHECK(r.count("mismatched_triangles") > 0);
        CHECK(all_problems(r).find("not in the replayed surface") != std::string::npos);
    }
    SECTION("no record at all") {
        BpmFile g = f;
        g.simplification_steps.reset();
        const CheckResult r = check_replay(g);
        REQUIRE_FALSE(r.passed);
        CHECK(r.problems[0].message.find("no recorded simplification steps") != std::string::npos);
    }
}

TEST_CASE("replay: the degree-3 case, a new triangle that already exists", "[check][replay]") {
    // Removing a vertex of a tetrahedron: its link is the opposite triangle, which exists.
    BpmFile f;
    f.param = fixtures::identity_parametrization(fixtures::tetrahedron());
    SimplificationSteps st;
    st.append(3, {{0, 1, 2}}, {0});
    f.simplification_steps = st;
    const CheckResult r = check_replay(f);
    INFO(problems_text(r));
    REQUIRE_FALSE(r.passed);
    CHECK(r.problems[0].id("step") == 0);
    CHECK(r.problems[0].id("original_vertex") == 3);
    CHECK(all_problems(r).find("is already a triangle of the surface") != std::string::npos);
}

TEST_CASE("replay: removing the apex of two touching cones is a counterexample to Conjecture 2.1",
          "[check][replay]") {
    // The apex's star is two disks; filling both holes adds only new edges, so the
    // conjecture's local condition holds, but the complex falls apart into two spheres.
    const int n = 8;
    BpmFile f;
    f.param = fixtures::identity_parametrization(fixtures::hourglass(n));
    std::vector<Tri> fill;
    std::vector<int32_t> patches;
    for (int side = 0; side < 2; ++side) {
        const int32_t first = 3 + side * n;
        for (int j = 1; j + 1 < n; ++j) {
            fill.push_back({first, first + j, first + j + 1});
            patches.push_back(side + 1);
        }
    }
    SimplificationSteps st;
    st.append(0, fill, patches);
    f.simplification_steps = st;
    const CheckResult r = check_replay(f);
    INFO(problems_text(r));
    REQUIRE_FALSE(r.passed);
    const std::string text = all_problems(r);
    CHECK(text.find("vertex 0 is a feature vertex") != std::string::npos);
    CHECK(text.find("counterexample to Conjecture 2.1") != std::string::npos);
    CHECK(text.find("already") == std::string::npos);  // the local condition holds
    for (const auto& p : r.problems) CHECK(p.id("step") == 0);
}

TEST_CASE("run_checks runs the replay when selected", "[check][replay]") {
    const BpmFile f = simplified_with_steps(fixtures::cube(3), 0.3);
    CheckSelection sel;
    sel.replay = true;
    const CheckReport r = run_checks(f, sel);
    REQUIRE(r.find("replay"));
    INFO(check_report_to_text(r));
    CHECK(r.passed());
    CHECK(check_report_to_text(r).find("PASS replay  replayed ") != std::string::npos);
}
