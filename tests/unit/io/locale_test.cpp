// libbpm's files do not depend on the C locale: a program that links libbpm and has called
// setlocale(LC_ALL, "") under a locale with a decimal comma (GUI programs, Python after
// locale.setlocale) must write and read the same bytes as under "C". The test switches to
// de_DE.UTF-8 (test_support::CommaLocale), which scripts/setup.sh generates; without it the
// test fails rather than skips.

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include <catch2/catch.hpp>

#include "bpm/check.h"
#include "bpm/surface_io.h"
#include "bpm/surface_topology.h"
#include "bpm/tetmesh.h"
#include "bpm/write_tetmesh.h"
#include "comma_locale.h"
#include "fixtures_surfaces.h"
#include "test_support.h"

using namespace bpm;

namespace {

// Every text format a tet mesh is written in.
std::string mesh_texts(const TetMesh& m) {
    return write_tetmesh_to_string(m, TetMeshFormat::Medit) + write_tetmesh_to_string(m, TetMeshFormat::Msh) +
           write_tetmesh_to_string(m, TetMeshFormat::Msh22) + write_tetmesh_to_string(m, TetMeshFormat::Vtu);
}

}  // namespace

TEST_CASE("locale: TetGen's input and output and the mesh files do not depend on a decimal-comma C locale",
          "[io][tetmesh][locale]") {
    REQUIRE_TETGEN();
    // A small real surface whose coordinates have fractions (0.18987 ...).
    const Parametrization p =
        fixtures::identity_parametrization(fixtures::load_off(std::string(BPM_MESH_DIR) + "/joint.off"));
    TetMesh in_c;
    generate_tetmesh(p, TetMeshOptions{}, Context{}, in_c);
    const std::string texts_in_c = mesh_texts(in_c);
    REQUIRE(texts_in_c.find("0.18987") != std::string::npos);

    const test_support::CommaLocale comma;
    // The writers alone, on the mesh made under "C".
    CHECK(mesh_texts(in_c) == texts_in_c);
    // TetGen's .poly written and its .node/.ele read under the comma locale.
    TetMesh in_comma;
    generate_tetmesh(p, TetMeshOptions{}, Context{}, in_comma);
    CHECK(in_comma.vertices == in_c.vertices);
    CHECK(in_comma.tetrahedra == in_c.tetrahedra);
    CHECK(mesh_texts(in_comma) == texts_in_c);
}

TEST_CASE("locale: surface files and check reports do not depend on a decimal-comma C locale",
          "[io][locale]") {
    // 1.5e-400 is below the smallest double: read as 0, like strtod in "C" (the readers'
    // out-of-range path); 0.25 must not become "0,25" in the written file.
    const std::string off = "OFF\n4 4 0\n0 0 1.5e-400\n1 0 0\n0 1 0.25\n0 0 1\n"
                            "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    const std::string vtk = "# vtk DataFile Version 3.0\ntet\nASCII\nDATASET POLYDATA\nPOINTS 4 double\n"
                            "0 0 1.5e-400 1 0 0 0 1 0.25 0 0 1\nPOLYGONS 4 16\n"
                            "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    CheckReport report;
    report.input = "x.bpm";
    CheckResult r;
    r.name = "quality";
    r.worst = WorstValue{"aspect_ratio", 2.5, {{"coarse_triangle", 3}}};
    report.checks.push_back(r);

    const test_support::ScratchDir dir("locale_test");
    auto written = [&](const Surface& s, const char* name) {
        write_surface(dir.file(name), s);
        std::ifstream in(dir.file(name), std::ios::binary);
        std::ostringstream text;
        text << in.rdbuf();
        return text.str();
    };
    auto outputs = [&] {
        const Surface a = read_surface_from_memory(off, SurfaceFormat::Off, "t.off");
        const Surface b = read_surface_from_memory(vtk, SurfaceFormat::Vtk, "t.vtk");
        CHECK(a.vertices[0][2] == 0.0);
        CHECK(b.vertices[0][2] == 0.0);
        CHECK(a.vertices[2][2] == 0.25);
        return written(a, "a.off") + written(b, "b.obj") + check_report_to_json(report);
    };
    const std::string in_c = outputs();
    REQUIRE(in_c.find("2.5") != std::string::npos);

    const test_support::CommaLocale comma;
    CHECK(outputs() == in_c);
}

TEST_CASE("locale: messages and text reports do not group digits or use a decimal comma under a host's locale",
          "[io][locale]") {
    // A host that calls std::locale::global(std::locale("")) makes every stream created
    // afterwards write 12345 as "12.345" and 0.25 as "0,25" (de_DE): libbpm's text reports
    // and its error messages must read the same as under "C".
    CheckReport report;
    report.input = "x.bpm";
    CheckResult r;
    r.name = "intersections";
    r.passed = false;
    r.problem_count = 12345;
    CheckProblem first;
    first.message = "triangles intersect";
    first.ids = {{"triangle", 23456}, {"other_triangle", 34567}};
    r.problems.push_back(first);
    report.checks.push_back(r);
    Surface scattered;  // 1234 separate triangles: 1234 components
    for (int32_t i = 0; i < 1234; ++i) {
        const double x = 0.25 * i;
        scattered.vertices.insert(scattered.vertices.end(), {Vec3{x, 0, 0}, Vec3{x + 0.125, 0, 0}, Vec3{x, 0.125, 0}});
        scattered.triangles.push_back(Tri{3 * i, 3 * i + 1, 3 * i + 2});
    }
    const std::string topology_in_c = describe_topology(compute_topology(scattered));
    REQUIRE(topology_in_c.find("1234 components") != std::string::npos);
    const std::string text_in_c = check_report_to_text(report);
    REQUIRE(text_in_c.find("12345 problems") != std::string::npos);

    const test_support::CommaLocale comma;
    CHECK(check_report_to_text(report) == text_in_c);
    CHECK(describe_topology(compute_topology(scattered)) == topology_in_c);
}
