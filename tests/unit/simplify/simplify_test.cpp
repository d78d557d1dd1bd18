// The simplifier against the checker's oracle: every output must be a valid
// parametrization (format, bijectivity, topology, no intersections).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/simplify.h"
#include "bpm/surface_io.h"
#include "fixtures_surfaces.h"
#include "test_support.h"

using namespace bpm;

namespace {

// Format, bijectivity and topology (test_support), and no self-intersections of S.
void require_valid(const Parametrization& p, const std::string& label) {
    INFO(label);
    test_support::require_valid_parametrization(p);
    const CheckResult intersections = check_intersections(p.coarse);
    INFO(test_support::check_text(intersections));
    CHECK(intersections.passed);
}

Parametrization run(const Surface& s, SimplifyOptions options, SimplifyResult* out_result = nullptr) {
    Parametrization p;
    const SimplifyResult r = simplify(s, options, Context{}, p);
    if (out_result) *out_result = r;
    return p;
}

}  // namespace

TEST_CASE("simplify keeps a valid parametrization on synthetic surfaces", "[simplify]") {
    struct Case {
        std::string name;
        Surface surface;
    };
    std::vector<Case> cases = {
        {"torus", fixtures::torus(24, 16)},
        {"double torus", fixtures::double_torus(4)},
        {"disk", fixtures::disk(12)},
        {"cube", fixtures::cube(6)},
        {"two cubes", fixtures::two_cubes(5)},
        {"cylinder wedges", fixtures::cylinder_wedges(24, 6)},
        {"octants", fixtures::octants(4)},
        {"hourglass", fixtures::hourglass(24)},
    };
    int64_t paired_steps = 0;
    for (auto& c : cases) {
        INFO("fixture: " << c.name);
        SimplifyOptions options;
        options.target_ratio = 0.1;
        options.self_check = true;
        SimplifyResult result;
        const Parametrization p = run(c.surface, options, &result);
        INFO(c.name << ": " << result.input_vertices << " -> " << result.output_vertices);
        require_valid(p, c.name);
        paired_steps += result.paired_steps;
    }
    // The self-check ran after second removals of a step too.
    CHECK(paired_steps > 100);
}

TEST_CASE("simplify keeps a valid parametrization on real meshes", "[simplify][real]") {
    const std::string dir = BPM_MESH_DIR;
    for (const std::string name : {"femur", "fandisk", "elephant", "mech-holes-shark"}) {
        const std::string path = dir + "/" + name + ".off";
        if (!std::filesystem::exists(path)) {
            WARN("missing " << path);
            continue;
        }
        const Surface s = read_surface(path);
        SimplifyOptions options;
        options.target_ratio = 0.1;
        SimplifyResult result;
        const Parametrization p = run(s, options, &result);
        INFO(name << ": " << result.input_vertices << " -> " << result.output_vertices << " error " << result.max_error);
        require_valid(p, name);
    }
}

namespace {
Surface scaled(Surface s, double factor) {
    for (auto& v : s.vertices) v = factor * v;
    return s;
}
std::vector<int32_t> kept_vertices(const Parametrization& p) {
    std::vector<int32_t> kept = p.coarse_vertex_origin;
    std::sort(kept.begin(), kept.end());
    return kept;
}
}  // namespace

TEST_CASE("simplify keeps the same vertices when the model is scaled", "[simplify]") {
    const std::string path = std::string(BPM_MESH_DIR) + "/elephant.off";
    if (!std::filesystem::exists(path)) {
        WARN("missing " << path);
        return;
    }
    const Surface s = read_surface(path);
    SimplifyOptions options;
    options.target_ratio = 0.1;
    const auto reference = kept_vertices(run(s, options));
    CHECK(kept_vertices(run(scaled(s, 1e-3), options)) == reference);
    CHECK(kept_vertices(run(scaled(s, 1e4), options)) == reference);
}

TEST_CASE("simplify is deterministic", "[simplify]") {
    const Surface s = fixtures::torus(30, 20);
    SimplifyOptions options;
    options.target_vertices = 60;
    const Parametrization a = run(s, options), b = run(s, options);
    CHECK(a.coarse.triangles == b.coarse.triangles);
    CHECK(a.pieces == b.pieces);
    CHECK(a.node_barycentric == b.node_barycentric);
}

TEST_CASE("simplify taking the surface over gives the same parametrization", "[simplify]") {
    const Surface s = fixtures::torus(30, 20);
    SimplifyOptions options;
    options.target_vertices = 60;
    const Parametrization a = run(s, options);
    Surface moved = s;
    Parametrization b;
    b.node_kind.resize(3);  // whatever was in `out` before is replaced
    simplify(std::move(moved), options, Context{}, b);
    CHECK(b.original.vertices == s.vertices);
    CHECK(b.original.triangles == s.triangles);
    CHECK(a.coarse.triangles == b.coarse.triangles);
    CHECK(a.coarse_vertex_origin == b.coarse_vertex_origin);
    CHECK(a.pieces == b.pieces);
    CHECK(a.node_barycentric == b.node_barycentric);
    CHECK(a.node_image == b.node_image);
    CHECK(a.node_kind == b.node_kind);
    // Options are checked before the surface is taken.
    Surface kept = s;
    options.target_ratio = 2;
    CHECK_THROWS_AS(simplify(std::move(kept), options, Context{}, b), OptionError);
    CHECK(kept.vertices.size() == s.vertices.size());
}

namespace {
// A torus with deterministic noise on every coordinate: many plans go stale, and the
// cheap and full costs often disagree.
Surface noisy_torus() {
    Surface s = fixtures::torus(40, 24);
    for (size_t i = 0; i < s.vertices.size(); ++i)
        for (int k = 0; k < 3; ++k) s.vertices[i][k] += 0.01 * std::sin(12.9898 * double(i) + 78.233 * k);
    return s;
}

// `one` (made with options.threads = 1) is also what two and three threads make.
void check_same_at_two_and_three_threads(const Surface& s, SimplifyOptions options, const Parametrization& one) {
    for (int threads : {2, 3}) {
        options.threads = threads;
        const Parametrization many = run(s, options);
        CHECK(one.coarse.triangles == many.coarse.triangles);
        CHECK(one.pieces == many.pieces);
        CHECK(one.node_barycentric == many.node_barycentric);
        CHECK(one.node_image == many.node_image);
    }
}
}  // namespace

TEST_CASE("simplify gives the same output for every thread count", "[simplify]") {
    // Planning is shared by threads (and planned ahead); which plans are made must
    // never depend on timing. A noisy surface makes many plans go stale.
    const Surface s = noisy_torus();
    SimplifyOptions options;
    options.target_vertices = 80;
    options.threads = 1;
    const Parametrization one = run(s, options);
    check_same_at_two_and_three_threads(s, options, one);
}

TEST_CASE("simplify one closed surface per material once their shared faces are fused", "[simplify]") {
    // What --merge-duplicate-vertices --merge-duplicate-triangles make of two touching
    // cubes given as two closed surfaces: two cubes with a sheet between them.
    Surface s = combine_surfaces({fixtures::voxel_surface(2, 1, 1, {1, 0}, 4), fixtures::voxel_surface(2, 1, 1, {0, 2}, 4)});
    merge_duplicate_vertices(s);
    REQUIRE(fuse_duplicate_triangles(s) == 32);
    SimplifyOptions options;
    options.target_ratio = 0.3;
    SimplifyResult r;
    const Parametrization p = run(s, options, &r);
    require_valid(p, "two cubes fused from one surface per material");
    CHECK(p.coarse.num_vertices() < s.num_vertices());
    // The three patches (two outsides, the interface) stay apart.
    std::vector<int32_t> patches = p.coarse.patches;
    std::sort(patches.begin(), patches.end());
    patches.erase(std::unique(patches.begin(), patches.end()), patches.end());
    CHECK(patches == std::vector<int32_t>{0, 1, 2});
}

TEST_CASE("simplify a cube of eight materials given as eight closed surfaces", "[simplify]") {
    // Octants: edges where four sheets meet, a vertex where six feature lines meet.
    std::vector<Surface> parts;
    for (int k = 0; k < 8; ++k) {
        std::vector<int> labels(8, 0);
        labels[size_t(k)] = k + 1;
        parts.push_back(fixtures::voxel_surface(2, 2, 2, labels, 3));
    }
    Surface s = combine_surfaces(parts);
    merge_duplicate_vertices(s);
    std::vector<FusedPatch> fused;
    CHECK(fuse_duplicate_triangles(s, &fused) == 12 * 18);  // 12 inner squares of 3 x 3 quads
    CHECK(fused.size() == 12);
    CHECK(validate_surface(s).empty());
    SimplifyOptions options;
    options.target_ratio = 0.3;
    const Parametrization p = run(s, options);
    require_valid(p, "eight octants fused from one surface per material");
    CHECK(p.coarse.num_vertices() < s.num_vertices());
}

TEST_CASE("simplify in strict cost order (queue tolerance 0)", "[simplify]") {
    const Surface s = noisy_torus();
    SimplifyOptions options;
    options.target_vertices = 80;
    SECTION("valid, the same for every thread count, and another order than the default's") {
        options.removals_per_step = 1;
        const Parametrization tolerant = run(s, options);
        options.queue_tolerance = 0.0;
        options.threads = 1;
        const Parametrization strict = run(s, options);
        require_valid(strict, "torus in strict cost order");
        CHECK(strict.coarse.num_vertices() == 80);
        options.threads = 2;
        CHECK(run(s, options).pieces == strict.pieces);
        // The tolerance is used: on a noisy surface it changes which vertices go.
        CHECK(kept_vertices(tolerant) != kept_vertices(strict));
    }
    SECTION("a negative tolerance is refused") {
        options.queue_tolerance = -0.1;
        Parametrization p;
        CHECK_THROWS_AS(simplify(s, options, Context{}, p), OptionError);
    }
}

TEST_CASE("simplify with two removals per step and with one", "[simplify]") {
    const Surface s = noisy_torus();
    SimplifyOptions options;
    options.target_vertices = 80;
    options.self_check = true;
    SimplifyResult paired_result;
    const Parametrization paired = run(s, options, &paired_result);
    require_valid(paired, "torus, two removals per step");
    CHECK(paired.coarse.num_vertices() == 80);
    // Most steps pair up on a torus: far-apart vertices have similar costs.
    CHECK(paired_result.paired_steps > paired_result.removed / 4);
    options.removals_per_step = 1;
    SimplifyResult single_result;
    const Parametrization single = run(s, options, &single_result);
    require_valid(single, "torus, one removal per step");
    CHECK(single.coarse.num_vertices() == 80);
    CHECK(single_result.paired_steps == 0);
    CHECK(kept_vertices(paired) != kept_vertices(single));
    options.threads = 2;
    CHECK(run(s, options).pieces == single.pieces);
}

TEST_CASE("simplify with eight removals per step: valid, and the same for every thread count", "[simplify]") {
    // Larger steps are planned and validated in larger rounds; which removals a step
    // takes and commits must depend on the queue only, never on the threads.
    const Surface s = noisy_torus();
    SimplifyOptions options;
    options.target_vertices = 80;
    options.removals_per_step = 8;
    options.self_check = true;
    options.threads = 1;
    SimplifyResult one_result;
    const Parametrization one = run(s, options, &one_result);
    require_valid(one, "torus, eight removals per step");
    CHECK(one.coarse.num_vertices() == 80);
    // Steps commit several removals (the steps are used), fewer steps than at two.
    CHECK(one_result.paired_steps > 0);
    check_same_at_two_and_three_threads(s, options, one);
    // The step size is a parameter of the output: another order than two per step.
    options.removals_per_step = 2;
    CHECK(kept_vertices(run(s, options)) != kept_vertices(one));
    SECTION("out of range is refused") {
        for (int bad : {0, 65}) {
            options.removals_per_step = bad;
            Parametrization p;
            CHECK_THROWS_AS(simplify(s, options, Context{}, p), OptionError);
        }
    }
}

TEST_CASE("simplify reports its phases' times", "[simplify]") {
    const Surface s = fixtures::torus(30, 20);
    SimplifyOptions options;
    options.target_vertices = 100;
    SimplifyResult r;
    run(s, options, &r);
    std::vector<std::string> names;
    for (const SimplifyPhaseTime& p : r.phases) {
        names.push_back(p.name);
        CHECK(p.wall_seconds >= 0);
        CHECK(p.cpu_seconds >= 0);
    }
    // In order, each once: with one thread the set-up, then the input check on its grid;
    // with more the check runs beside the set-up, one phase.
    const std::vector<std::string> tail = {"first ranking", "removals", "edge flips", "export of phi",
                                           "freeing the simplifier's state"};
    REQUIRE(names.size() >= tail.size() + 1);
    CHECK(std::vector<std::string>(names.end() - long(tail.size()), names.end()) == tail);
    const std::vector<std::string> head(names.begin(), names.end() - long(tail.size()));
    CHECK((head == std::vector<std::string>{"set-up", "input intersection check"} ||
           head == std::vector<std::string>{"input intersection check with set-up"}));
}

TEST_CASE("simplify honours its stopping rules", "[simplify]") {
    const Surface s = fixtures::torus(30, 20);  // 600 vertices
    SECTION("vertex target") {
        SimplifyOptions options;
        options.target_vertices = 100;
        SimplifyResult r;
        const Parametrization p = run(s, options, &r);
        CHECK(r.target_reached);
        CHECK(p.coarse.num_vertices() == 100);
    }
    SECTION("error limit is never exceeded") {
        SimplifyOptions options;
        options.max_error = 0.01;
        SimplifyResult r;
        const Parametrization p = run(s, options, &r);
        CHECK(r.max_error <= 0.01);
        CHECK(p.coarse.num_vertices() < 600);
        require_valid(p, "torus with error limit");
    }
    SECTION("bad options are refused") {
        SimplifyOptions options;
        options.target_ratio = 1.5;
        Parametrization p;
        CHECK_THROWS_AS(simplify(s, options, Context{}, p), OptionError);
    }
}

namespace {

// Largest angle (degrees) between a coarse triangle's normal and the normal of the image
// of one of its pieces: computed from the output alone, independently of the simplifier.
double max_normal_deviation(const Parametrization& p) {
    double worst = 0.0;
    for (int32_t t = 0; t < p.coarse.num_triangles(); ++t) {
        const Tri& c = p.coarse.triangles[t];
        const Vec3 n = triangle_normal(p.coarse.vertices[c[0]], p.coarse.vertices[c[1]], p.coarse.vertices[c[2]]);
        const int64_t base = p.node_offsets[t];
        for (int64_t i = p.piece_offsets[t]; i < p.piece_offsets[t + 1]; ++i) {
            const Tri& q = p.pieces[i];
            const Vec3 m = triangle_normal(p.node_image[base + q[0]], p.node_image[base + q[1]], p.node_image[base + q[2]]);
            worst = std::max(worst, std::acos(std::max(-1.0, std::min(1.0, dot(n, m)))) * 180.0 / M_PI);
        }
    }
    return worst;
}

}  // namespace

TEST_CASE("simplify keeps the original's normals within --max-normal-deviation of the coarse triangles",
          "[simplify]") {
    // A flat 16 x 16 square with a steep bump in the middle: the triangles around the
    // raised vertex are tilted by atan(2) = 63 degrees. Simplified to 10 vertices
    // without the limit, the bump ends up on coarse triangles that are turned by more
    // than 90 degrees from some of its pieces (measured: 102).
    Surface s = fixtures::disk(16);
    s.vertices[8 * 17 + 8][2] = 2.0;
    SimplifyOptions options;
    options.target_vertices = 10;
    SECTION("without the limit the bump ends up on coarse triangles turned far from it") {
        const Parametrization p = run(s, options);
        CHECK(max_normal_deviation(p) > 45.0);
    }
    SECTION("with the limit no coarse triangle carries a piece turned by more than it") {
        options.max_normal_deviation_degrees = 45.0;
        SimplifyResult r;
        const Parametrization p = run(s, options, &r);
        require_valid(p, "bump with a normal deviation limit");
        CHECK(max_normal_deviation(p) <= 45.0);
        CHECK(p.coarse.num_vertices() < s.num_vertices());
        if (!r.target_reached) CHECK(r.blocked.count("normal deviation limit (max_normal_deviation_degrees)") == 1);
    }
    SECTION("an angle outside 0..180 is refused") {
        options.max_normal_deviation_degrees = 200.0;
        Parametrization p;
        CHECK_THROWS_AS(simplify(s, options, Context{}, p), OptionError);
    }
}

namespace {

// Coarse vertices that are not corners of the unit cube [0,1]^3.
int count_off_cube_corners(const Surface& s) {
    int off = 0;
    for (const Vec3& x : s.vertices) {
        bool corner = true;
        for (int k = 0; k < 3; ++k) corner = corner && (x[k] == 0.0 || x[k] == 1.0);
        off += corner ? 0 : 1;
    }
    return off;
}

double coarse_hausdorff(const Parametrization& p) {
    CheckOptions options;
    options.error_sample_spacing = 0.01;
    const CheckResult r = check_distance(p, options);
    for (const auto& m : r.measures)
        if (m.name == "coarse_hausdorff") return m.value;
    return -1.0;
}

}  // namespace

TEST_CASE("simplify keeps the corners of a cube: 8 vertices give the cube itself", "[simplify][features]") {
    // 10 x 10 squares per face. Before corners were kept, --vertices 8 kept 6 of the 8
    // corners (error 0.21 of the diagonal).
    const Surface s = fixtures::cube(10);
    SimplifyOptions options;
    options.target_vertices = 8;
    SimplifyResult r;
    const Parametrization p = run(s, options, &r);
    require_valid(p, "cube to 8 vertices");
    CHECK(r.target_reached);
    CHECK(p.coarse.num_vertices() == 8);
    CHECK(count_off_cube_corners(p.coarse) == 0);
    CHECK(coarse_hausdorff(p) < 1e-12);
    CHECK(r.crease_junctions == 8);
}

TEST_CASE("simplify stops at the corners when the target is below them, and says why", "[simplify][features]") {
    const Surface s = fixtures::cube(10);
    SimplifyOptions options;
    options.target_vertices = 4;
    SimplifyResult r;
    const Parametrization p = run(s, options, &r);
    require_valid(p, "cube to 4 vertices");
    CHECK_FALSE(r.target_reached);
    CHECK(p.coarse.num_vertices() == 8);
    CHECK(r.kept_feature_vertices() == 8);
    CHECK(r.stop_reason.find("below the 8 feature vertices") != std::string::npos);
    CHECK(r.blocked.size() == 1);
    CHECK(r.blocked.begin()->second == 8);
}

TEST_CASE("simplify of a cube of two triangles per face keeps the cube", "[simplify][features]") {
    // A cube of 6 quads split into 12 triangles at ratio 0.5 became a tetrahedron.
    const Surface s = fixtures::cube(1);
    SimplifyOptions options;
    options.target_ratio = 0.5;
    SimplifyResult r;
    const Parametrization p = run(s, options, &r);
    require_valid(p, "cube of 12 triangles");
    CHECK(p.coarse.num_vertices() == 8);
    CHECK(coarse_hausdorff(p) < 1e-12);
}

TEST_CASE("simplify without keep_corners may remove the corners of creases", "[simplify][features]") {
    const Surface s = fixtures::cube(10);
    SimplifyOptions options;
    options.target_vertices = 4;
    options.keep_corners = false;
    SimplifyResult r;
    const Parametrization p = run(s, options, &r);
    require_valid(p, "cube to 4 vertices without corners");
    CHECK(r.target_reached);
    CHECK(p.coarse.num_vertices() == 4);
    CHECK(r.kept_feature_vertices() == 0);
}

TEST_CASE("simplify keeps the corners of an L-shaped block and reaches them exactly", "[simplify][features]") {
    // Three unit cubes in an L: 12 corners (6 of the L profile, top and bottom), the
    // inner vertical edge concave. Both diagonals of a grid square's fan pass through
    // original vertices and one runs along original edges: the planner must take the other.
    const Surface s = fixtures::voxel_surface(2, 2, 1, {1, 1, 1, 0}, 6);
    SimplifyOptions options;
    options.target_vertices = 12;
    SimplifyResult r;
    const Parametrization p = run(s, options, &r);
    require_valid(p, "L-block to 12 vertices");
    CHECK(r.target_reached);
    CHECK(p.coarse.num_vertices() == 12);
    CHECK(coarse_hausdorff(p) < 1e-12);
}

TEST_CASE("simplify does not take short noisy creases for corners", "[simplify][features][real]") {
    // Femur (a scan): 293 vertices where three creases sharper than 60 degrees meet, all
    // on creases at most 1.8 % of the diagonal long. Taken for corners they stopped the
    // 10 % target at 403 vertices with a Hausdorff distance of 0.058 (0.0078 before).
    const std::string path = std::string(BPM_MESH_DIR) + "/femur.off";
    if (!std::filesystem::exists(path)) {
        WARN("missing " << path);
        return;
    }
    const Surface s = read_surface(path);
    SimplifyOptions options;
    options.target_ratio = 0.1;
    SimplifyResult r;
    const Parametrization p = run(s, options, &r);
    CHECK(r.target_reached);
    CHECK(r.crease_junctions == 0);
    CHECK(r.kept_feature_vertices() < 10);
}

namespace {

// The smallest ridge angle (180 minus the angle between the normals, compared as oriented:
// the interior dihedral angle of a convex edge, the exterior one of a concave edge) over
// the edges of `s` with two triangles.
double sharpest_ridge(const Surface& s) {
    std::map<std::pair<int32_t, int32_t>, std::vector<std::pair<Vec3, bool>>> edges;  // normal, runs lo -> hi
    for (const Tri& t : s.triangles) {
        const Vec3 n = triangle_normal(s.vertices[t[0]], s.vertices[t[1]], s.vertices[t[2]]);
        for (int k = 0; k < 3; ++k) {
            const int32_t a = t[k], b = t[(k + 1) % 3];
            edges[{std::min(a, b), std::max(a, b)}].push_back({n, a < b});
        }
    }
    double sharpest = 180.0;
    for (const auto& [e, sides] : edges) {
        if (sides.size() != 2) continue;
        const double c = dot(sides[0].first, sides[1].first) * (sides[0].second == sides[1].second ? -1.0 : 1.0);
        sharpest = std::min(sharpest, 180.0 - std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / M_PI);
    }
    return sharpest;
}

}  // namespace

TEST_CASE("simplify does not fold coarse ridges sharper than the original (min_ridge_angle_degrees)",
          "[simplify][ridge][real]") {
    // Femur (a scan): its sharpest edge has a ridge angle of 24.6 degrees. Without the
    // guard the coarse surface at 10 % had non-feature ridges of 2.5 degrees (7.1 at 1000
    // vertices) where the original is nowhere sharper than 35: a tetrahedron of 4.99
    // degrees bounded by the coarse surface itself in bpm-mesh, and held-back vertices of
    // the adaptively refined surface there. Feature lines off, so that every coarse edge
    // is guarded (feature edges are exempt): none may be sharper than min(floor,
    // 24.6 - 5) = 19.6 degrees.
    const std::string path = std::string(BPM_MESH_DIR) + "/femur.off";
    if (!std::filesystem::exists(path)) {
        WARN("missing " << path);
        return;
    }
    const Surface s = read_surface(path);
    const double original = sharpest_ridge(s);
    REQUIRE(original == Approx(24.6).margin(0.1));
    for (const bool by_ratio : {true, false}) {
        SimplifyOptions options;
        options.feature_angle_degrees = 180.0;
        if (by_ratio) options.target_ratio = 0.1;
        else options.target_vertices = 1000;
        INFO((by_ratio ? "10 %" : "1000 vertices"));
        const double limit = std::min(options.min_ridge_angle_degrees, original - 5.0);
        SimplifyResult r;
        const Parametrization p = run(s, options, &r);
        CHECK(r.target_reached);
        CHECK(sharpest_ridge(p.coarse) >= limit);
        options.min_ridge_angle_degrees = 0.0;  // the guard off: the folds come back
        CHECK(sharpest_ridge(run(s, options).coarse) < limit);
    }
}

TEST_CASE("simplify puts off removals that fold phi (fold_weight)", "[simplify][fold][real]") {
    // Femur (a CT scan with hundreds of noise spikes): phi folds the original over the
    // coarse triangles in many places (pieces turned more than 90 degrees against their
    // coarse triangle: 834 at 10 %, 456 at 1000 vertices without the fold term), and the
    // refined surface through phi converges slowly there. With fold_weight 1 a removal
    // that folds goes after removals of about the same error that do not: 746 and 371.
    const std::string path = std::string(BPM_MESH_DIR) + "/femur.off";
    if (!std::filesystem::exists(path)) {
        WARN("missing " << path);
        return;
    }
    const Surface s = read_surface(path);
    for (const bool by_ratio : {true, false}) {
        SimplifyOptions options;
        if (by_ratio) options.target_ratio = 0.1;
        else options.target_vertices = 1000;
        INFO((by_ratio ? "10 %" : "1000 vertices"));
        options.fold_weight = 0.0;
        const int64_t folds_without = check_distortion(run(s, options)).count("pieces_turned_over_90_degrees");
        options.fold_weight = 1.0;
        SimplifyResult r;
        const Parametrization p = run(s, options, &r);
        CHECK(r.target_reached);
        const int64_t folds_with = check_distortion(p).count("pieces_turned_over_90_degrees");
        INFO("pieces turned > 90 degrees: " << folds_without << " without, " << folds_with << " with");
        CHECK(double(folds_with) < 0.95 * double(folds_without));
    }
    SimplifyOptions bad;
    bad.fold_weight = -1.0;
    Parametrization out;
    CHECK_THROWS_AS(simplify(s, bad, Context{}, out), OptionError);
}

TEST_CASE("simplify removes the input's slivers: no coarse triangle above max_aspect_ratio", "[simplify][real]") {
    // Femur (a scan) has a needle around an edge 1e-4 of the diagonal long (vertices 2 and
    // 73). Before removals that repair such slivers went first, it stayed to the end: a
    // coarse triangle of R/r 92.8 at 10 % and 1000 vertices, and bpm-mesh's tets of 0.55
    // degrees on it.
    const std::string path = std::string(BPM_MESH_DIR) + "/femur.off";
    if (!std::filesystem::exists(path)) {
        WARN("missing " << path);
        return;
    }
    const Surface s = read_surface(path);
    for (const double ratio : {0.1, 0.25}) {
        SimplifyOptions options;
        options.target_ratio = ratio;
        SimplifyResult r;
        const Parametrization p = run(s, options, &r);
        INFO("ratio " << ratio);
        CHECK(r.target_reached);
        CHECK(r.worst_aspect_ratio <= options.max_aspect_ratio);
    }
}

namespace {

// `s` with one cap sliver on a flat part of patch `patch`: in a triangle whose corners are
// all flat vertices of that patch (every triangle around them in the patch, with the same
// normal), the corner opposite the longest edge moved to that edge's midpoint, `offset`
// times its length off the edge's line towards where it was. The area stays positive, so
// the reader accepts it (R/r ~ 1 / (4 offset^2)). What a gmsh surface with one vertex
// snapped onto an edge looks like.
Surface with_cap_sliver(Surface s, int32_t patch, double offset) {
    const int32_t nv = s.num_vertices();
    std::vector<Vec3> normal(s.triangles.size());
    for (size_t t = 0; t < s.triangles.size(); ++t) {
        const Tri& c = s.triangles[t];
        const Vec3 n = cross(s.vertices[c[1]] - s.vertices[c[0]], s.vertices[c[2]] - s.vertices[c[0]]);
        normal[t] = (1.0 / norm(n)) * n;
    }
    std::vector<int32_t> first(nv, -1);
    std::vector<char> flat(nv, 1);
    for (size_t t = 0; t < s.triangles.size(); ++t)
        for (int32_t v : s.triangles[t]) {
            if (s.patches[t] != patch) flat[v] = 0;
            if (first[v] < 0) first[v] = int32_t(t);
            else if (dot(normal[t], normal[first[v]]) < 1.0 - 1e-12) flat[v] = 0;
        }
    std::vector<size_t> candidates;
    for (size_t t = 0; t < s.triangles.size(); ++t) {
        const Tri& c = s.triangles[t];
        if (s.patches[t] == patch && flat[c[0]] && flat[c[1]] && flat[c[2]]) candidates.push_back(t);
    }
    REQUIRE(!candidates.empty());
    const Tri c = s.triangles[candidates[candidates.size() / 2]];
    int k = 0;  // corner opposite the longest edge
    double longest = 0.0;
    for (int i = 0; i < 3; ++i) {
        const double l = distance(s.vertices[c[(i + 1) % 3]], s.vertices[c[(i + 2) % 3]]);
        if (l > longest) longest = l, k = i;
    }
    const Vec3 a = s.vertices[c[(k + 1) % 3]], b = s.vertices[c[(k + 2) % 3]];
    const Vec3 mid = 0.5 * (a + b), up = s.vertices[c[k]] - mid;
    s.vertices[c[k]] = mid + (offset * longest / norm(up)) * up;
    return s;
}

}  // namespace

TEST_CASE("simplify removes a near-degenerate input sliver on a flat face, one material and two",
          "[simplify][sliver]") {
    // Defect D2 of a new-user audit (issue 19 item 5): a gmsh surface with a vertex 1e-12
    // of an edge off its line kept that triangle (R/r 1e21) in the coarse surface, silently:
    // every removal that takes it out put a node or a cut within the transfer's 1e-9
    // margin of a side, which the original sliver itself puts there (phi_transfer.h,
    // original_sliver). Before the fix: worst R/r 1.1e21 (cube), 2.5e23 (interface).
    struct Case {
        const char* name;
        Surface surface;
        int32_t patch;
    };
    const Case cases[] = {{"cube, outer face", fixtures::cube(8), 1},
                          {"two cubes, interface", fixtures::two_cubes(8), 102},
                          {"two cubes, outer face", fixtures::two_cubes(8), 2}};
    for (const Case& c : cases) {
        for (const double offset : {1e-10, 1e-12, 1e-14}) {
            INFO(c.name << ", offset " << offset);
            const Surface s = with_cap_sliver(c.surface, c.patch, offset);
            double worst_input = 0.0;
            for (const Tri& t : s.triangles)
                worst_input = std::max(worst_input, aspect_ratio(s.vertices[t[0]], s.vertices[t[1]], s.vertices[t[2]]));
            REQUIRE(worst_input > 1e15);
            SimplifyOptions options;
            options.target_ratio = 0.2;
            options.threads = 1;
            SimplifyResult r;
            const Parametrization p = run(s, options, &r);
            require_valid(p, c.name);
            CHECK(r.target_reached);
            CHECK(r.worst_aspect_ratio <= options.max_aspect_ratio);
            CHECK(r.slivers == 0);
            CHECK(r.worst_slivers.empty());
        }
    }
}

TEST_CASE("simplify removes an input sliver whose normal is noise, next to a crease", "[simplify][sliver]") {
    // A triangle with a corner on a cube edge, its right-angle corner (a face vertex) moved
    // to 1e-13 of the hypotenuse's length off the hypotenuse and 3e-13 out of the face (its
    // normal turned by 72 degrees). Fails without original_sliver (phi_transfer.h). The
    // crease rule for such triangles (core/crease.h: thinner than 1e-10, no direction) is
    // tested in tests/internal/core/crease_test.cpp; here it takes no part (the cube's
    // corners are kept either way), it did on a gmsh cylinder whose rim vertex was snapped
    // 1e-16 off a chord (R/r 1.2e30 kept: its edges were creases, its corner a crease corner).
    Surface s = fixtures::cube(8);
    auto on_edges = [&](int32_t v) {
        int n = 0;
        for (int k = 0; k < 3; ++k) n += s.vertices[v][k] == 0.0 || s.vertices[v][k] == 1.0;
        return n;
    };
    bool made = false;
    for (size_t t = s.triangles.size() / 3; t < s.triangles.size() && !made; ++t) {
        const Tri c = s.triangles[t];
        for (int k = 0; k < 3 && !made; ++k) {
            const int32_t v = c[k], a = c[(k + 1) % 3], b = c[(k + 2) % 3];
            // v opposite the longest edge, a face vertex; a or b on a cube edge.
            if (on_edges(v) != 1 || on_edges(a) + on_edges(b) != 3) continue;
            const Vec3 &pa = s.vertices[a], &pb = s.vertices[b], pv = s.vertices[v];
            const double ab = distance(pa, pb);
            if (ab <= distance(pv, pa) || ab <= distance(pv, pb)) continue;
            const Vec3 mid = 0.5 * (pa + pb), up = pv - mid, n = cross(pb - pa, pv - pa);
            s.vertices[v] = mid + (1e-13 * ab / norm(up)) * up + (3e-13 * ab / norm(n)) * n;
            made = true;
        }
    }
    REQUIRE(made);
    SimplifyOptions options;
    options.target_ratio = 0.2;
    options.threads = 1;
    SimplifyResult r;
    const Parametrization p = run(s, options, &r);
    require_valid(p, "cube with a snapped face vertex");
    CHECK(r.target_reached);
    CHECK(r.worst_aspect_ratio <= options.max_aspect_ratio);
    CHECK(r.slivers == 0);
    CHECK(r.max_error < 1e-9);
}

TEST_CASE("simplify reports the coarse triangles above max_aspect_ratio and what kept their corners",
          "[simplify][sliver]") {
    // A limit no triangle of the grid meets (its right triangles have R/r 2.41): every
    // removal is refused by the shape limit, and every triangle is reported.
    const Surface s = fixtures::cube(3);
    SimplifyOptions options;
    options.target_ratio = 0.5;
    options.max_aspect_ratio = 2.2;
    options.threads = 1;
    SimplifyResult r;
    const Parametrization p = run(s, options, &r);
    int64_t above = 0;
    for (const Tri& t : p.coarse.triangles)
        above += aspect_ratio(p.coarse.vertices[t[0]], p.coarse.vertices[t[1]], p.coarse.vertices[t[2]]) > 2.2;
    CHECK(above > 0);
    CHECK(r.slivers == above);
    REQUIRE(r.worst_slivers.size() == std::min<size_t>(size_t(above), SimplifyResult::kListedSlivers));
    for (size_t i = 0; i < r.worst_slivers.size(); ++i) {
        const SliverReport& w = r.worst_slivers[i];
        CHECK(w.aspect_ratio > 2.2);
        if (i > 0) CHECK(w.aspect_ratio <= r.worst_slivers[i - 1].aspect_ratio);
        for (const std::string& why : w.kept) CHECK(!why.empty());
    }
    CHECK(r.worst_slivers[0].aspect_ratio == Approx(r.worst_aspect_ratio));
}

TEST_CASE("simplify: the final edge flips keep phi valid, and can be turned off", "[simplify][flip]") {
    const Surface s = noisy_torus();
    SimplifyOptions options;
    options.target_vertices = 80;
    options.threads = 1;
    SECTION("flips under thin tetrahedra (flip_min_dihedral_degrees) happen and keep phi valid") {
        options.flip_min_dihedral_degrees = 10.0;
        Parametrization p;
        const SimplifyResult r = simplify(s, options, Context{}, p);
        CHECK(r.sliver_flips > 0);
        require_valid(p, "torus with sliver flips");
        options.flip_edges = false;
        Parametrization off;
        const SimplifyResult r_off = simplify(s, options, Context{}, off);
        CHECK(r_off.sliver_flips + r_off.needle_flips == 0);
        CHECK(off.coarse.triangles != p.coarse.triangles);
        // The flips stay within the largest error a removal reached, which may be a little
        // above the final error without them.
        CHECK(r.max_error <= r_off.max_error * 1.05);
    }
    SECTION("an out-of-range dihedral bound is refused") {
        options.flip_min_dihedral_degrees = 61;
        Parametrization p;
        CHECK_THROWS_AS(simplify(s, options, Context{}, p), OptionError);
    }
}

namespace {
// A flat sheet meshed as a regular triangular lattice (rows sqrt(3)/2 apart, odd rows
// shifted by half a spacing), as gmsh meshes the faces of a box: in doubles, the lattice
// lines through the rows' points are straight only up to rounding.
Surface lattice_sheet(int n) {
    Surface s;
    const double h = 1.0 / n;
    auto id = [n](int i, int j) { return int32_t(j * (n + 1) + i); };
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) s.vertices.push_back({(i + 0.5 * (j % 2)) * h, j * h * std::sqrt(3.0) / 2.0, 0.0});
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int32_t a = id(i, j), b = id(i + 1, j), c = id(i, j + 1), d = id(i + 1, j + 1);
            if (j % 2 == 0) {
                s.triangles.push_back({a, b, c});
                s.triangles.push_back({b, d, c});
            } else {
                s.triangles.push_back({a, d, c});
                s.triangles.push_back({a, b, d});
            }
        }
    s.patches.assign(s.triangles.size(), 0);
    return s;
}
}  // namespace

TEST_CASE("simplify takes a flat lattice down without error", "[simplify]") {
    // Issue 19 (quality): removals in the sqrt(3) sub-lattice that ties leave on a regular
    // lattice had an original edge along every ear's diagonal (its ends put on it within
    // rounding distance) and were refused, so the flat interior froze and the budget went
    // to the boundary (a gmsh sphere in a box: max error 0.00928, with the box rounded to
    // float32 0.00159). This sheet: max error 0.0112 of the diagonal before, 2e-16 now.
    SimplifyOptions options;
    options.target_ratio = 0.1;
    SimplifyResult result;
    const Parametrization p = run(lattice_sheet(30), options, &result);
    require_valid(p, "lattice sheet");
    CHECK(result.output_vertices <= 97);
    CHECK(result.max_error < 1e-9);
}
