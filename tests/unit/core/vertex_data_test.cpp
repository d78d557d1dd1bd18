// Per-vertex data of the original surface (Surface::vertex_data): read from PLY vertex
// properties, kept in step by the read repairs, stored in /original/point_data of a
// .bpm file, and carried through phi onto refined surfaces and refined .bpm files.

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "bpm/bpm_file.h"
#include "bpm/errors.h"
#include "bpm/refine.h"
#include "bpm/simplify.h"
#include "bpm/surface_io.h"
#include "fixtures_phi.h"
#include "test_support.h"

using namespace bpm;

namespace {

const VertexArray* find_array(const Surface& s, const std::string& name) {
    for (const VertexArray& a : s.vertex_data)
        if (a.name == name) return &a;
    return nullptr;
}

// A linear field of the position: interpolating it linearly over triangles reproduces it
// at every point of the surface, so its transfer through phi is checkable exactly.
double field(const Vec3& x) { return 1.0 + x[0] - 2.0 * x[1] + 0.5 * x[2]; }

void add_linear_field(Surface& s) {
    VertexArray f{"f", 1, {}}, g{"g", 2, {}};
    for (const Vec3& x : s.vertices) {
        f.values.push_back(field(x));
        g.values.push_back(2.0 * field(x));
        g.values.push_back(-7.0);
    }
    s.vertex_data = {f, g};
}

const char* kPly =
    "ply\nformat ascii 1.0\nelement vertex 5\n"
    "property float x\nproperty float y\nproperty float z\n"
    "property float nx\nproperty float ny\nproperty float nz\n"
    "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    "property double quality\nproperty list uchar int ignored_list\n"
    "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0  0 0 1  255 0 0  0.5  1 7\n"
    "1 0 0  0 0 1  0 255 0  1.5  0\n"
    "1 1 0  0 0 1  0 0 255  2.5  2 1 2\n"
    "0 1 0  0 0 1  1 2 3    3.5  0\n"
    "0 0 0  0 0 1  9 9 9    4.5  0\n"
    "3 0 1 2\n3 4 2 3\n";

}  // namespace

TEST_CASE("PLY vertex properties become vertex data arrays", "[vertex-data][io]") {
    SurfaceReadOptions o;
    o.merge_duplicate_vertices = true;  // vertex 4 repeats vertex 0
    const Surface s = read_surface_from_memory(kPly, SurfaceFormat::Ply, "test.ply", o);
    REQUIRE(s.vertices.size() == 4);
    REQUIRE(s.vertex_data.size() == 3);  // the list property is not data
    const VertexArray* n = find_array(s, "normals");
    const VertexArray* c = find_array(s, "colors");
    const VertexArray* q = find_array(s, "quality");
    REQUIRE(n);
    REQUIRE(c);
    REQUIRE(q);
    CHECK(n->components == 3);
    CHECK(c->components == 3);
    CHECK(q->components == 1);
    // The merged vertex keeps the data of the kept one (vertex 0).
    CHECK(q->values == std::vector<double>{0.5, 1.5, 2.5, 3.5});
    CHECK(c->values == std::vector<double>{255, 0, 0, 0, 255, 0, 0, 0, 255, 1, 2, 3});
    CHECK(n->values[11] == 1.0f);
    CHECK(vertex_data_problems(s).empty());
}

TEST_CASE("malformed vertex data is named", "[vertex-data]") {
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    s.triangles = {{0, 1, 2}};
    s.patches = {0};
    s.vertex_data = {{"a", 2, {1, 2, 3}}, {"a", 1, {1, 2, 3}}, {"b/c", 1, {1, 2, 3}}, {"d", 0, {}}};
    const auto problems = vertex_data_problems(s);
    REQUIRE(problems.size() == 4);
    CHECK(problems[0] == "vertex data 'a': 3 values for 3 vertices x 2 components");
    CHECK(problems[1].find("used twice") != std::string::npos);
    CHECK(problems[2].find("'/'") != std::string::npos);
    CHECK(problems[3].find("0 components") != std::string::npos);
}

TEST_CASE("vertex data round-trips through the bpm file, also with crash isolation", "[vertex-data][format]") {
    BpmFile f;
    f.param = test::make_height_field(6, 3, test::default_height);
    add_linear_field(f.param.original);
    const std::string bytes = write_bpm_to_memory(f);
    for (bool isolated : {false, true}) {
        set_hdf5_isolation(isolated);
        const BpmFile g = read_bpm_from_memory(bytes, "mem");
        REQUIRE(g.param.original.vertex_data.size() == 2);
        for (size_t i = 0; i < 2; ++i) {
            CHECK(g.param.original.vertex_data[i].name == f.param.original.vertex_data[i].name);
            CHECK(g.param.original.vertex_data[i].components == f.param.original.vertex_data[i].components);
            CHECK(g.param.original.vertex_data[i].values == f.param.original.vertex_data[i].values);
        }
    }
    set_hdf5_isolation(false);
    // A file without data has no /original/point_data group and reads back without data.
    BpmFile plain;
    plain.param = test::make_height_field(6, 3, test::default_height);
    CHECK(read_bpm_from_memory(write_bpm_to_memory(plain), "mem").param.original.vertex_data.empty());
}

TEST_CASE("the writer refuses vertex data of the wrong size or not finite", "[vertex-data][format]") {
    BpmFile f;
    f.param = test::make_height_field(6, 3, test::default_height);
    add_linear_field(f.param.original);
    SECTION("too few rows") {
        f.param.original.vertex_data[0].values.pop_back();
        CHECK_THROWS_AS(write_bpm_to_memory(f), OutputError);
    }
    SECTION("NaN") {
        f.param.original.vertex_data[1].values[3] = std::nan("");
        try {
            (void)write_bpm_to_memory(f);
            FAIL("no error");
        } catch (const OutputError& e) {
            CHECK(std::string(e.what()).find("/original/point_data/g: entry [1, 1] is not finite") != std::string::npos);
        }
    }
}

TEST_CASE("vertex data is carried through phi onto refined surfaces and refined bpm files", "[vertex-data][refine]") {
    // Simplify a subdivided height field carrying a linear field, refine, and compare
    // the transferred values with the field at the refined positions.
    Parametrization p = test::make_height_field(16, 1, test::default_height);
    Surface original = p.original;
    add_linear_field(original);
    SimplifyOptions so;
    so.target_ratio = 0.2;
    Parametrization coarse;
    simplify(original, so, Context{}, coarse);
    REQUIRE(coarse.original.vertex_data.size() == 2);
    const double scale = bounding_box_diagonal(original);

    RefinedSurface r;
    RefineOptions ro;
    ro.levels = 2;
    refine(coarse, ro, Context{}, r);
    const VertexArray& f = coarse.original.vertex_data[0];
    const std::vector<double> values = transfer_vertex_data(r, coarse.original, f.values, 1);
    double worst = 0;
    for (size_t v = 0; v < r.surface.vertices.size(); ++v)
        worst = std::max(worst, std::abs(values[v] - field(r.surface.vertices[v])));
    CHECK(worst < 1e-12 * (1 + scale));

    // The refined .bpm: its original surface is S0 cut into pieces, with the data
    // interpolated onto the new vertices.
    const Parametrization rp = refined_parametrization(coarse, r, Context{});
    REQUIRE(rp.original.vertex_data.size() == 2);
    const VertexArray& rf = rp.original.vertex_data[0];
    const VertexArray& rg = rp.original.vertex_data[1];
    REQUIRE(rf.values.size() == rp.original.vertices.size());
    REQUIRE(rg.values.size() == 2 * rp.original.vertices.size());
    worst = 0;
    for (size_t v = 0; v < rp.original.vertices.size(); ++v) {
        worst = std::max(worst, std::abs(rf.values[v] - field(rp.original.vertices[v])));
        worst = std::max(worst, std::abs(rg.values[2 * v] - 2.0 * field(rp.original.vertices[v])));
        CHECK(rg.values[2 * v + 1] == Approx(-7.0));
    }
    CHECK(worst < 1e-12 * (1 + scale));
    // The S0 vertices keep their values exactly.
    for (size_t v = 0; v < original.vertices.size(); ++v) CHECK(rf.values[v] == f.values[v]);
    BpmFile out;
    out.param = rp;
    CHECK(read_bpm_from_memory(write_bpm_to_memory(out), "mem").param.original.vertex_data.size() == 2);
}

TEST_CASE("OFF vertex normals, colours and texture coordinates become vertex data", "[vertex-data][io]") {
    const std::string square_faces = "3 0 1 2\n3 0 2 3\n";
    SECTION("CNOFF (normals, then RGBA colours) ") {
        const Surface s = read_surface_from_memory("CNOFF\n4 2 0\n"
                                                   "0 0 0  0 0 1  255 0 0 255\n"
                                                   "1 0 0  0 0 1  0 255 0 255\n"
                                                   "1 1 0  0 0 1  0 0 255 255\n"
                                                   "0 1 0  0 0 1  9 9 9 128\n" + square_faces,
                                                   SurfaceFormat::Off, "t.off", {});
        REQUIRE(s.vertex_data.size() == 2);
        CHECK(s.vertex_data[0].name == "normals");
        CHECK(s.vertex_data[0].values == std::vector<double>{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
        CHECK(s.vertex_data[1].name == "colors");
        CHECK(s.vertex_data[1].components == 4);
        CHECK(s.vertex_data[1].values[15] == 128);
    }
    SECTION("STCOFF with RGB colours") {
        const Surface s = read_surface_from_memory("STCOFF 4 2 0\n"
                                                   "0 0 0  1 0 0  0 0\n1 0 0  0 1 0  1 0\n"
                                                   "1 1 0  0 0 1  1 1\n0 1 0  1 1 1  0 1\n" + square_faces,
                                                   SurfaceFormat::Off, "t.off", {});
        REQUIRE(s.vertex_data.size() == 2);
        CHECK(s.vertex_data[0].name == "colors");
        CHECK(s.vertex_data[0].components == 3);
        CHECK(s.vertex_data[1].name == "texture_coordinates");
        CHECK(s.vertex_data[1].values == std::vector<double>{0, 0, 1, 0, 1, 1, 0, 1});
    }
    SECTION("a vertex line that does not fit the layout leaves the data out, with a note") {
        SurfaceReadReport report;
        const Surface s = read_surface_from_memory("COFF\n4 2 0\n0 0 0 1 0 0\n1 0 0 0 1 0\n1 1 0 0 0\n0 1 0 1 1 1\n" +
                                                       square_faces,
                                                   SurfaceFormat::Off, "t.off", {}, &report);
        CHECK(s.vertex_data.empty());
        REQUIRE(report.notes.size() == 1);
        CHECK(report.notes[0].find("vertex 2 has 2 values after its coordinates") != std::string::npos);
    }
    SECTION("plain OFF has no vertex data") {
        const Surface s = read_surface_from_memory("OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n" + square_faces,
                                                   SurfaceFormat::Off, "t.off", {});
        CHECK(s.vertex_data.empty());
    }
}

TEST_CASE("several inputs are combined with their patches apart and their common vertex data", "[vertex-data][io]") {
    Surface a, b;
    a.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    a.triangles = {{0, 1, 2}};
    a.patches = {7};
    a.vertex_data = {{"t", 1, {1, 2, 3}}, {"only_a", 1, {0, 0, 0}}};
    b.vertices = {{5, 0, 0}, {6, 0, 0}, {5, 1, 0}, {6, 1, 0}};
    b.triangles = {{0, 1, 2}, {2, 1, 3}};
    b.patches = {7, 8};
    b.vertex_data = {{"t", 1, {4, 5, 6, 7}}, {"only_a", 2, {0, 0, 0, 0, 0, 0, 0, 0}}};
    std::vector<std::pair<int, int32_t>> origin;
    std::vector<std::string> dropped;
    const Surface c = combine_surfaces({a, b}, &origin, &dropped);
    REQUIRE(c.vertices.size() == 7);
    CHECK(c.triangles == std::vector<Tri>{{0, 1, 2}, {3, 4, 5}, {5, 4, 6}});
    // Patch 7 of a and patch 7 of b are different materials: different ids.
    CHECK(c.patches == std::vector<int32_t>{0, 1, 2});
    CHECK(origin == std::vector<std::pair<int, int32_t>>{{0, 7}, {1, 7}, {1, 8}});
    REQUIRE(c.vertex_data.size() == 1);  // "only_a" has other components in b
    CHECK(c.vertex_data[0].values == std::vector<double>{1, 2, 3, 4, 5, 6, 7});
    CHECK(dropped == std::vector<std::string>{"only_a"});
    CHECK(vertex_data_problems(c).empty());
}
