// The legacy VTK reader (libbpm/src/io/read_vtk.cpp) through read_surface_from_memory: the
// same surface written ASCII and BINARY, in the old and the 5.1 cell layout, gives the same
// triangles, patches and point data; strips, polygons and non-surface cells; errors with
// their line or byte offset.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "bpm/errors.h"
#include "bpm/surface_io.h"
#include "test_bytes.h"
#include "test_support.h"

using namespace bpm;

namespace {

template <class T>
void put_be(std::string& out, T value) {
    test_bytes::put(out, value, true);
}
using test_bytes::text;

// Writes a legacy VTK file in either encoding: keyword lines as text, values as text or
// big-endian binary (followed by a line end, as vtkDataWriter does).
struct VtkWriter {
    bool binary = false;
    bool new_layout = false;  // 5.1: OFFSETS / CONNECTIVITY
    std::string out;

    explicit VtkWriter(bool binary_, bool new_layout_ = false) : binary(binary_), new_layout(new_layout_) {
        out = std::string("# vtk DataFile Version ") + (new_layout ? "5.1" : "4.2") + "\ntest data\n" +
              (binary ? "BINARY" : "ASCII") + "\n";
    }
    void line(const std::string& s) { out += s + "\n"; }
    template <class T>
    void values(const std::vector<T>& v) {
        if (binary) {
            for (T x : v) put_be<T>(out, x);
            out += "\n";
            return;
        }
        for (size_t i = 0; i < v.size(); ++i) out += (i ? " " : "") + text(static_cast<double>(v[i]));
        out += "\n";
    }
    void cells(const std::string& keyword, const std::vector<std::vector<int>>& cells) {
        size_t total = 0;
        for (const auto& c : cells) total += c.size();
        if (new_layout) {
            line(keyword + " " + std::to_string(cells.size() + 1) + " " + std::to_string(total));
            std::vector<int64_t> offsets{0}, connectivity;
            for (const auto& c : cells) {
                offsets.push_back(offsets.back() + static_cast<int64_t>(c.size()));
                connectivity.insert(connectivity.end(), c.begin(), c.end());
            }
            line("OFFSETS vtktypeint64");
            values(offsets);
            line("CONNECTIVITY vtktypeint64");
            values(connectivity);
            return;
        }
        line(keyword + " " + std::to_string(cells.size()) + " " + std::to_string(total + cells.size()));
        std::vector<int32_t> flat;
        for (const auto& c : cells) {
            flat.push_back(static_cast<int32_t>(c.size()));
            flat.insert(flat.end(), c.begin(), c.end());
        }
        values(flat);
    }
};

const std::vector<float> kPoints = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0, 1, 2, 0.5f};

// The surface of most tests: a vertex cell, a line, two polygons (triangles) and a strip
// of four points, written strips first (VTK numbers polydata cells vertices, lines,
// polygons, strips whatever the order in the file); cell data "material"; point data of
// every kind.
std::string full_polydata(bool binary, bool new_layout) {
    VtkWriter w(binary, new_layout);
    w.line("DATASET POLYDATA");
    w.line("FIELD FieldData 1");
    w.line("TimeValue 1 1 double");
    w.values(std::vector<double>{2.5});
    w.line("POINTS 6 float");
    w.values(kPoints);
    w.cells("VERTICES", {{4}});
    w.cells("LINES", {{0, 5}});
    w.cells("TRIANGLE_STRIPS", {{0, 1, 2, 3}});
    w.cells("POLYGONS", {{2, 3, 4}, {3, 5, 4}});
    w.line("CELL_DATA 5");
    w.line("SCALARS material int 1");
    w.line("LOOKUP_TABLE default");
    w.values(std::vector<int32_t>{9, 8, 1, 2, 3});
    w.line("FIELD FieldData 1");
    w.line("other 1 5 float");
    w.values(std::vector<float>{0.5f, 1, 2, 3, 4});
    w.line("POINT_DATA 6");
    w.line("SCALARS temp float");
    w.line("LOOKUP_TABLE default");
    w.values(std::vector<float>{0, 0.5f, 1, 1.5f, 2, 2.5f});
    w.line("SCALARS two double 2");
    w.line("LOOKUP_TABLE my_table");
    w.values(std::vector<double>{0, -0.0, 1, -1, 2, -2, 3, -3, 4, -4, 5, -5.125});
    w.line("LOOKUP_TABLE my_table 2");
    if (binary)
        w.values(std::vector<uint8_t>{1, 2, 3, 4, 5, 6, 7, 8});
    else
        w.values(std::vector<float>{0, 0.25f, 0.5f, 1, 1, 1, 1, 1});
    w.line("VECTORS vel double");
    w.values(std::vector<double>{0, 0.25, 0.5, 1, 1.25, 1.5, 2, 2.25, 2.5, 3, 3.25, 3.5, 4, 4.25, 4.5, 5, 5.25, 5.5});
    w.line("METADATA");
    w.line("INFORMATION 1");
    w.line("NAME L2_NORM_RANGE LOCATION vtkDataArray");
    w.line("DATA 2 0 7.5 ");
    w.line("");
    w.line("NORMALS nrm float");
    w.values(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, -1, 0, 0, -1, 0, 1, 0});
    w.line("TEXTURE_COORDINATES uv 2 float");
    w.values(std::vector<float>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11});
    std::vector<double> tensor;
    for (int i = 0; i < 54; ++i) tensor.push_back(i * 0.5);
    w.line("TENSORS stress double");
    w.values(tensor);
    w.line("COLOR_SCALARS rgb 3");
    std::vector<uint8_t> colour;
    for (int i = 0; i < 18; ++i) colour.push_back(static_cast<uint8_t>(i * 15));
    if (binary) {
        w.values(colour);
    } else {
        std::vector<double> as_float;
        for (uint8_t c : colour) as_float.push_back(c / 255.0);
        w.values(as_float);
    }
    w.line("FIELD FieldData 3");
    w.line("ids 1 6 vtkIdType");
    w.values(std::vector<int32_t>{10, 11, 12, 13, 14, -15});
    w.line("a%2Fb%20c 2 6 unsigned_short");
    w.values(std::vector<uint16_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 65535});
    w.line("METADATA");
    w.line("COMPONENT_NAMES");
    w.line("first");
    w.line("second");
    w.line("");
    w.line("temp 1 6 vtktypeint64");
    w.values(std::vector<int64_t>{-1, 0, 1, 2, 3, int64_t(1) << 40});
    return w.out;
}

const VertexArray* find_array(const Surface& s, const std::string& name) {
    for (const VertexArray& a : s.vertex_data)
        if (a.name == name) return &a;
    return nullptr;
}

void check_array(const Surface& s, const std::string& name, int components, const std::vector<double>& values) {
    INFO("array " << name);
    const VertexArray* a = find_array(s, name);
    REQUIRE(a != nullptr);
    CHECK(a->components == components);
    REQUIRE(a->values.size() == values.size());
    for (size_t i = 0; i < values.size(); ++i) {
        INFO("value " << i);
        CHECK(std::memcmp(&a->values[i], &values[i], sizeof(double)) == 0);
    }
}

bool has_note(const SurfaceReadReport& r, const std::string& text) {
    for (const std::string& n : r.notes)
        if (n.find(text) != std::string::npos) return true;
    return false;
}

std::string vtk_error(const std::string& bytes, const SurfaceReadOptions& options = {}) {
    try {
        (void)read_surface_from_memory(bytes, SurfaceFormat::Vtk, "test.vtk", options);
    } catch (const InputError& e) {
        CHECK(e.where() == "test.vtk");
        return e.what();
    }
    return "";
}

using test_support::line_of;

#define CHECK_VTK_ERROR(bytes, text)                     \
    do {                                                 \
        const std::string message_ = vtk_error(bytes);   \
        INFO("message: " << message_);                   \
        CHECK(message_.find(text) != std::string::npos); \
    } while (0)

}  // namespace

TEST_CASE("VTK: format name, extension, hint", "[surface_io][vtk]") {
    CHECK(surface_format_from_name("VTK") == SurfaceFormat::Vtk);
    CHECK(surface_format_from_path("dir/mesh.vtk") == SurfaceFormat::Vtk);
    const std::string message = [] {
        try {
            (void)read_surface_from_memory(full_polydata(false, false), SurfaceFormat::Off, "x.off");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    }();
    CHECK(message.find("looks like VTK") != std::string::npos);
}

TEST_CASE("VTK: ASCII and BINARY polydata, old and 5.1 cell layouts, give the same surface and data",
          "[surface_io][vtk]") {
    for (const bool binary : {false, true}) {
        for (const bool new_layout : {false, true}) {
            INFO((binary ? "BINARY" : "ASCII") << (new_layout ? " 5.1" : " 4.2"));
            SurfaceReadReport report;
            const Surface s =
                read_surface_from_memory(full_polydata(binary, new_layout), SurfaceFormat::Vtk, "t.vtk", {}, &report);
            REQUIRE(s.vertices.size() == 6);
            CHECK(s.vertices[5] == Vec3{1, 2, 0.5});
            // Polygons, then the strip split with the second triangle flipped: (0 1 2), (2 1 3).
            const std::vector<Tri> triangles = {{2, 3, 4}, {3, 5, 4}, {0, 1, 2}, {2, 1, 3}};
            CHECK(s.triangles == triangles);
            CHECK(s.patches == std::vector<int32_t>{1, 2, 3, 3});
            CHECK(report.skipped_elements == 2);
            CHECK(has_note(report, "1 vertex cells skipped"));
            CHECK(has_note(report, "1 line cells skipped"));
            CHECK(has_note(report, "patch ids from the cell data array 'material'"));
            CHECK(has_note(report, "cell data ignored: 'other'"));
            CHECK(has_note(report, "point data array 'a/b c' stored as 'a_b c'"));
            CHECK(has_note(report, "point data array 'temp' stored as 'temp_2'"));

            REQUIRE(s.vertex_data.size() == 10);
            check_array(s, "temp", 1, {0, 0.5, 1, 1.5, 2, 2.5});
            check_array(s, "two", 2, {0, -0.0, 1, -1, 2, -2, 3, -3, 4, -4, 5, -5.125});
            check_array(s, "vel", 3,
                        {0, 0.25, 0.5, 1, 1.25, 1.5, 2, 2.25, 2.5, 3, 3.25, 3.5, 4, 4.25, 4.5, 5, 5.25, 5.5});
            check_array(s, "nrm", 3, {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, -1, 0, 0, -1, 0, 1, 0});
            check_array(s, "uv", 2, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11});
            std::vector<double> tensor, colour;
            for (int i = 0; i < 54; ++i) tensor.push_back(i * 0.5);
            for (int i = 0; i < 18; ++i) colour.push_back(i * 15 / 255.0);
            check_array(s, "stress", 9, tensor);
            check_array(s, "rgb", 3, colour);
            check_array(s, "ids", 1, {10, 11, 12, 13, 14, -15});
            check_array(s, "a_b c", 2, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 65535});
            check_array(s, "temp_2", 1, {-1, 0, 1, 2, 3, std::ldexp(1.0, 40)});
            // In file order.
            CHECK(s.vertex_data[0].name == "temp");
            CHECK(s.vertex_data[9].name == "temp_2");
        }
    }
}

TEST_CASE("VTK: keywords are case-insensitive, CRLF line ends pass", "[surface_io][vtk]") {
    std::string bytes =
        "# vtk DataFile Version 3.0\r\ntitle\r\nascii\r\ndataset polydata\r\npoints 3 double\r\n0 0 0 1 0 0 0 1 0\r\n"
        "polygons 1 4\r\n3 0 1 2\r\n";
    const Surface s = read_surface_from_memory(bytes, SurfaceFormat::Vtk, "t.vtk");
    CHECK(s.triangles == std::vector<Tri>{{0, 1, 2}});
    CHECK(s.patches == std::vector<int32_t>{0});
}

TEST_CASE("VTK: a quad is refused without the repair and split with it, keeping its patch", "[surface_io][vtk]") {
    for (const bool binary : {false, true}) {
        for (const bool new_layout : {false, true}) {
            INFO((binary ? "BINARY" : "ASCII") << (new_layout ? " 5.1" : " 4.2"));
            VtkWriter w(binary, new_layout);
            w.line("DATASET POLYDATA");
            w.line("POINTS 5 double");
            w.values(std::vector<double>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, -1, 0});
            w.cells("POLYGONS", {{0, 4, 1}, {0, 1, 2, 3}});
            w.line("CELL_DATA 2");
            w.line("FIELD FieldData 1");
            w.line("Region 1 2 double");
            w.values(std::vector<double>{4, -7});
            const std::string message = vtk_error(w.out);
            INFO(message);
            CHECK(message.find("face 1 has 4 corners; only triangles are accepted; the repair it needs: "
                               "triangulate polygons") != std::string::npos);
            CHECK(message.find(binary ? "byte offset " : "line ") == 0);

            SurfaceReadOptions options;
            options.triangulate_polygons = true;
            SurfaceReadReport report;
            const Surface s = read_surface_from_memory(w.out, SurfaceFormat::Vtk, "t.vtk", options, &report);
            REQUIRE(s.triangles.size() == 3);
            CHECK(s.triangles[0] == Tri{0, 4, 1});
            CHECK(s.patches == std::vector<int32_t>{4, -7, -7});
            CHECK(has_note(report, "triangulated 1 polygon face"));
            CHECK(has_note(report, "'Region'"));
        }
    }
}

TEST_CASE("VTK: unstructured grid with triangles, a quad, a pixel, a strip and skipped vertex / line cells",
          "[surface_io][vtk]") {
    for (const bool binary : {false, true}) {
        for (const bool new_layout : {false, true}) {
            INFO((binary ? "BINARY" : "ASCII") << (new_layout ? " 5.1" : " 4.2"));
            VtkWriter w(binary, new_layout);
            w.line("DATASET UNSTRUCTURED_GRID");
            w.line("POINTS 8 float");
            w.values(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 2, 0, 0, 2, 1, 0, 3, 0, 0, 3, 1, 0});
            // 0: triangle, 1: line, 2: polyline, 3: vertex, 4: pixel 1 4 3 5 (order of a grid cell),
            // 5: quad 4 6 7 5, 6: strip 0 1 2 3 (overlaps the triangle: fine for the reader).
            w.cells("CELLS", {{0, 1, 2}, {0, 3}, {0, 1, 3}, {7}, {1, 4, 3, 5}, {4, 6, 7, 5}, {2, 1, 3}});
            w.line("CELL_TYPES 7");
            w.values(std::vector<int32_t>{5, 3, 4, 1, 8, 9, 6});
            w.line("CELL_DATA 7");
            w.line("SCALARS gmsh:physical int");
            w.line("LOOKUP_TABLE default");
            w.values(std::vector<int32_t>{1, 2, 3, 4, 5, 6, 7});
            w.line("POINT_DATA 8");
            w.line("SCALARS u double");
            w.line("LOOKUP_TABLE default");
            w.values(std::vector<double>{0, 1, 2, 3, 4, 5, 6, 7});
            SurfaceReadOptions options;
            options.triangulate_polygons = true;
            SurfaceReadReport report;
            const Surface s = read_surface_from_memory(w.out, SurfaceFormat::Vtk, "t.vtk", options, &report);
            REQUIRE(s.triangles.size() == 6);
            CHECK(s.triangles[0] == Tri{0, 1, 2});
            CHECK(s.triangles[5] == Tri{2, 1, 3});
            CHECK(s.patches == std::vector<int32_t>{1, 5, 5, 6, 6, 7});
            CHECK(report.skipped_elements == 3);
            CHECK(has_note(report, "1 vertex cells skipped"));
            CHECK(has_note(report, "2 line cells skipped"));
            check_array(s, "u", 1, {0, 1, 2, 3, 4, 5, 6, 7});
            // The pixel's corners go round the polygon as 1 4 5 3: every triangle of it uses
            // three of those four corners and none is flipped (normal +z).
            for (int t = 1; t <= 2; ++t) {
                const Vec3& a = s.vertices[s.triangles[t][0]];
                const Vec3& b = s.vertices[s.triangles[t][1]];
                const Vec3& c = s.vertices[s.triangles[t][2]];
                CHECK((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0);
            }
        }
    }
}

TEST_CASE("VTK: volume cells are skipped next to triangles and refused alone", "[surface_io][vtk]") {
    auto grid = [](const std::vector<int32_t>& types) {
        VtkWriter w(false);
        w.line("DATASET UNSTRUCTURED_GRID");
        w.line("POINTS 4 double");
        w.values(std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1});
        std::vector<std::vector<int>> cells;
        for (int32_t t : types) cells.push_back(t == 10 ? std::vector<int>{0, 1, 2, 3} : std::vector<int>{0, 2, 1});
        w.cells("CELLS", cells);
        w.line("CELL_TYPES " + std::to_string(types.size()));
        w.values(types);
        return w.out;
    };
    SurfaceReadReport report;
    SurfaceReadOptions drop;  // point 3 is used by the tetrahedron only
    drop.drop_unreferenced_vertices = true;
    const Surface s = read_surface_from_memory(grid({10, 5}), SurfaceFormat::Vtk, "t.vtk", drop, &report);
    CHECK(s.triangles == std::vector<Tri>{{0, 2, 1}});
    CHECK(has_note(report, "1 volume cells skipped"));
    const std::string message = vtk_error(grid({10, 10}));
    CHECK(message ==
          "line 10: cell 0 is a tetrahedron (VTK type 10): bpm reads surfaces; extract the boundary first "
          "(e.g. vtkGeometryFilter, ParaView's Extract Surface)");
    CHECK_VTK_ERROR(grid({22}), "cell 0 is a quadratic triangle (VTK type 22)");
}

TEST_CASE("VTK: point data with NaN is dropped with a note, a patch array must hold whole numbers",
          "[surface_io][vtk]") {
    const std::string head =
        "# vtk DataFile Version 4.2\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 "
        "1 2\n";
    SurfaceReadReport report;
    Surface s = read_surface_from_memory(head +
                                             "POINT_DATA 3\nSCALARS u float\nLOOKUP_TABLE default\n1 nan 2\n"
                                             "SCALARS w float\nLOOKUP_TABLE default\n1 2 3\n",
                                         SurfaceFormat::Vtk, "t.vtk", {}, &report);
    REQUIRE(s.vertex_data.size() == 1);
    CHECK(s.vertex_data[0].name == "w");
    CHECK(has_note(report, "'u' (NaN or infinite values)"));
    s = read_surface_from_memory(head + "CELL_DATA 1\nSCALARS label float\nLOOKUP_TABLE default\n1.5\n",
                                 SurfaceFormat::Vtk, "t.vtk", {}, &report);
    CHECK(s.patches == std::vector<int32_t>{0});
    CHECK(has_note(report, "cell data ignored: 'label'"));
}

TEST_CASE("VTK: array names: %-decoded, '/' and empty replaced, repeats numbered, control characters kept encoded",
          "[surface_io][vtk]") {
    std::string bytes =
        "# vtk DataFile Version 4.2\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 2\n"
        "POINT_DATA 3\nFIELD f 4\nx%00y 1 3 int\n1 2 3\n. 1 3 int\n1 2 3\nx_2 1 3 int\n1 2 3\nNULL_ARRAY\n";
    // 300 arrays of one name: numbered _2 ... _300, except x_2, which is taken.
    for (int i = 0; i < 300; ++i) bytes += "SCALARS x float\nLOOKUP_TABLE default\n1 2 3\n";
    SurfaceReadReport report;
    const Surface s = read_surface_from_memory(bytes, SurfaceFormat::Vtk, "t.vtk", {}, &report);
    REQUIRE(s.vertex_data.size() == 303);
    CHECK(s.vertex_data[0].name == "x%00y");
    CHECK(s.vertex_data[1].name == "_");
    CHECK(s.vertex_data[2].name == "x_2");
    CHECK(s.vertex_data[3].name == "x");
    CHECK(s.vertex_data[4].name == "x_3");
    CHECK(s.vertex_data[302].name == "x_301");
    CHECK(has_note(report, "point data array '.' stored as '_'"));
    CHECK(vertex_data_problems(s).empty());
}

TEST_CASE("VTK: errors name the line (ASCII) or byte offset (BINARY) and what was expected", "[surface_io][vtk]") {
    const std::string ok = full_polydata(false, false);
    CHECK(vtk_error(ok).empty());

    SECTION("header and dataset") {
        CHECK(vtk_error("") == "the file is empty");
        CHECK_VTK_ERROR("# vtk DataFile Version 9.0\nt\nASCII\n", "line 1: unsupported VTK file version '9.0'");
        CHECK_VTK_ERROR("OFF\n3 1 0\n", "line 1: not a legacy VTK file");
        CHECK_VTK_ERROR("# vtk DataFile Version 2.0\nt\nTEXT\n",
                        "line 3: expected ASCII or BINARY on the third line, found 'TEXT'");
        CHECK_VTK_ERROR("# vtk DataFile Version 2.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\n",
                        "line 4: DATASET STRUCTURED_POINTS is a grid, not a surface");
        CHECK_VTK_ERROR(
            "# vtk DataFile Version 2.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
            "POLYGON 1 4\n3 0 1 2\n",
            "line 7: unknown keyword 'POLYGON'");
        CHECK_VTK_ERROR("# vtk DataFile Version 2.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 real\n",
                        "line 5: unknown VTK data type 'real'");
    }
    SECTION("ASCII values") {
        std::string bad = ok;
        bad.replace(bad.find("3 2 3 4"), 7, "3 2 3 7");
        CHECK_VTK_ERROR(bad, "line " + std::to_string(line_of(ok, "3 2 3 4")) +
                                 ": POLYGONS cell 0: point index 7 is out of range (the file has 6 points)");
        bad = ok;
        bad.replace(bad.find("\n0 0 0 1 0 0") + 1, 1, "nan");
        const std::string points_line = "line " + std::to_string(line_of(ok, "POINTS 6"));
        CHECK_VTK_ERROR(bad, "line " + std::to_string(line_of(ok, "POINTS 6") + 1) +
                                 ": point 0: coordinate x 'nan' is not a finite number");
        bad = ok;
        bad.replace(bad.find("POINTS 6"), 8, "POINTS 2000000000");
        CHECK_VTK_ERROR(bad, points_line + ": 6000000000 point coordinates announced, but the");
        bad = ok;
        bad.replace(bad.find("POINTS 6"), 8, "POINTS 4000000000");
        CHECK_VTK_ERROR(bad, points_line + ": 4000000000 points announced; bpm supports at most 2147483647");
        bad = ok;
        bad.replace(bad.find("POINT_DATA 6"), 12, "POINT_DATA 7");
        CHECK_VTK_ERROR(bad, "POINT_DATA 7, but the file has 6 points");
        bad = ok;
        bad.replace(bad.find("TRIANGLE_STRIPS 1 5"), 19, "TRIANGLE_STRIPS 1 9");
        CHECK_VTK_ERROR(bad, "TRIANGLE_STRIPS: 1 cells use 5 integers, but 9 were announced");
        bad = ok;
        bad.replace(bad.find("TRIANGLE_STRIPS 1 5"), 19, "TRIANGLE_STRIPS 1 3");
        CHECK_VTK_ERROR(bad,
                        "line " + std::to_string(line_of(ok, "TRIANGLE_STRIPS") + 1) +
                            ": TRIANGLE_STRIPS cell 0 has 4 points, but only 2 of the 3 announced entries are left");
        CHECK_VTK_ERROR(ok.substr(0, ok.find("3 5 4") + 3),
                        "line " + std::to_string(line_of(ok, "POLYGONS")) +
                            ": 8 cell list entries announced, but the 13 bytes left");
        bad = ok;
        bad.replace(bad.find("SCALARS two double 2\n"), 20, "SCALARS two double 2 extra");
        CHECK_VTK_ERROR(bad, "line " + std::to_string(line_of(ok, "SCALARS two")) + ": unexpected 'extra'");
        bad = ok;
        bad.replace(bad.find("LOOKUP_TABLE my_table\n"), 21, "LOOKUP my_table");
        CHECK_VTK_ERROR(bad, "expected LOOKUP_TABLE after SCALARS 'two', found 'LOOKUP'");
    }
    SECTION("5.1 layout") {
        const std::string v51 = full_polydata(false, true);
        std::string bad = v51;
        bad.replace(bad.find("OFFSETS vtktypeint64\n0 3 6"), 26, "OFFSETS vtktypeint64\n0 3 5");
        CHECK_VTK_ERROR(bad, "POLYGONS: the last offset is 5, but the connectivity has 6 entries");
        bad = v51;
        bad.replace(bad.find("OFFSETS vtktypeint64\n0 3 6"), 26, "OFFSETS vtktypeint64\n0 7 6");
        CHECK_VTK_ERROR(bad, "POLYGONS offset 1 is 7; expected a value from 0 to 6");
        bad = v51;
        bad.replace(bad.find("CONNECTIVITY vtktypeint64\n2 3 4"), 31, "CONNECTIVITY vtktypeint64\n2 3 -4");
        CHECK_VTK_ERROR(bad, "POLYGONS cell 0: point index -4 is out of range");
    }
    SECTION("BINARY") {
        const std::string bin = full_polydata(true, false);
        // A truncated point block: refused at the POINTS line before anything is read.
        CHECK_VTK_ERROR(
            bin.substr(0, bin.find("POINTS 6 float\n") + 30),
            "line 8: 18 point coordinates announced, but the 15 bytes left in the file cannot hold that many");
        // Truncated inside the cells: the POLYGONS data ends early.
        const size_t polygons = bin.find("POLYGONS 2 8\n") + 13;
        CHECK_VTK_ERROR(bin.substr(0, polygons + 20), "8 cell list entries announced, but the 20 bytes left");
        // An index out of range, at its byte offset: the third entry of the first polygon.
        std::string bad = bin;
        const size_t index_at = polygons + 4 * 3;
        bad[index_at + 3] = 99;
        CHECK_VTK_ERROR(bad, "byte offset " + std::to_string(index_at) +
                                 ": POLYGONS cell 0: point index 99 is out of range (the file has 6 points)");
        // A NaN coordinate.
        bad = bin;
        const size_t y1 = bin.find("POINTS 6 float\n") + 15 + 4 * 4;
        bad.replace(y1, 4, std::string("\x7f\xc0\x00\x00", 4));
        CHECK_VTK_ERROR(bad, "byte offset " + std::to_string(y1) + ": point 1: coordinate y is NaN");
    }
}

TEST_CASE("VTK: point data written by VTK itself (every array type, ASCII and binary, 4.2 and 5.1) reads exactly",
          "[surface_io][vtk]") {
    using test_support::run_command;
    std::string out;
    if (run_command("/usr/bin/python3 -c 'import vtk' 2>/dev/null", out) != 0) {
        WARN("SKIPPED: python3-vtk9 is not installed; VTK-written files not read");
        return;
    }
    const test_support::ScratchDir scratch("read_vtk_test");
    const std::string dir = scratch.file("vtk");
    // Two triangles as a strip; arrays of each VTK type, component names (METADATA), a
    // string array (skipped), a bit array, and the dataset's own field data.
    const std::string script = R"PY(
import sys, os, vtk
d = sys.argv[1]
os.makedirs(d, exist_ok=True)
pd = vtk.vtkPolyData()
pts = vtk.vtkPoints(); pts.SetDataTypeToDouble()
for p in [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0.125)]: pts.InsertNextPoint(p)
pd.SetPoints(pts)
strip = vtk.vtkCellArray(); strip.InsertNextCell(4, [0, 1, 2, 3]); pd.SetStrips(strip)
line = vtk.vtkCellArray(); line.InsertNextCell(2, [0, 3]); pd.SetLines(line)
def arr(cls, name, nc, vals):
    a = cls(); a.SetName(name); a.SetNumberOfComponents(nc)
    for v in vals:
        if nc == 1: a.InsertNextTuple1(v)
        else: a.InsertNextValue(v)
    return a
p = pd.GetPointData()
p.SetScalars(arr(vtk.vtkFloatArray, "temp", 1, [1.5, 2.5, -3.5, 4.25]))
p.SetVectors(arr(vtk.vtkDoubleArray, "vel", 3, [i / 3.0 for i in range(12)]))
p.SetNormals(arr(vtk.vtkFloatArray, "nrm", 3, [0, 0, 1] * 4))
p.SetTCoords(arr(vtk.vtkFloatArray, "uv", 2, range(8)))
p.SetTensors(arr(vtk.vtkDoubleArray, "stress", 9, range(36)))
p.AddArray(arr(vtk.vtkIdTypeArray, "ids", 1, [7, 8, 9, 10]))
p.AddArray(arr(vtk.vtkLongArray, "long", 1, [-1, 2, 3, 1 << 40]))
u = arr(vtk.vtkUnsignedShortArray, "a b/c", 2, range(8)); u.SetComponentName(0, "x y"); p.AddArray(u)
p.AddArray(arr(vtk.vtkBitArray, "bits", 1, [1, 0, 1, 1]))
p.AddArray(arr(vtk.vtkCharArray, "chars", 1, [-5, 0, 5, 100]))
p.AddArray(arr(vtk.vtkSignedCharArray, "schars", 1, [-128, 0, 5, 127]))
p.AddArray(arr(vtk.vtkUnsignedIntArray, "uints", 1, [0, 1, 4000000000, 5]))
p.AddArray(arr(vtk.vtkUnsignedCharArray, "rgb", 3, [255, 0, 0, 0, 255, 0, 0, 0, 255, 51, 102, 153]))
s = vtk.vtkStringArray(); s.SetName("names")
for v in ["a b", "x" * 70, "", "z"]: s.InsertNextValue(v)
p.AddArray(s)
c = pd.GetCellData()
c.AddArray(arr(vtk.vtkIntArray, "Material", 1, [5, 6]))
f = vtk.vtkStringArray(); f.SetName("note"); f.InsertNextValue("hello"); pd.GetFieldData().AddArray(f)
pd.GetFieldData().AddArray(arr(vtk.vtkDoubleArray, "TimeValue", 1, [0.5]))
for binary in (0, 1):
    for version in (42, 51):
        w = vtk.vtkPolyDataWriter(); w.SetInputData(pd)
        w.SetFileName(os.path.join(d, "%s_%d.vtk" % ("binary" if binary else "ascii", version)))
        w.SetFileType(2 if binary else 1); w.SetFileVersion(version); w.Write()
)PY";
    const std::string script_path = scratch.file("write_vtk.py");
    { std::ofstream(script_path) << script; }
    const int status = run_command("/usr/bin/python3 " + script_path + " " + dir + " 2>&1", out);
    INFO(out);
    REQUIRE(status == 0);
    for (const char* name : {"ascii_42.vtk", "ascii_51.vtk", "binary_42.vtk", "binary_51.vtk"}) {
        INFO(name);
        SurfaceReadReport report;
        const Surface s = read_surface(dir + "/" + name, {}, &report);
        CHECK(s.triangles == std::vector<Tri>{{0, 1, 2}, {2, 1, 3}});
        CHECK(s.patches == std::vector<int32_t>{6, 6});
        CHECK(report.skipped_elements == 1);
        const bool ascii = std::string(name).rfind("ascii", 0) == 0;
        std::vector<double> vel, stress;
        for (int i = 0; i < 12; ++i) vel.push_back(i / 3.0);
        for (int i = 0; i < 36; ++i) stress.push_back(i);
        check_array(s, "temp", 1, {1.5, 2.5, -3.5, 4.25});
        if (!ascii) check_array(s, "vel", 3, vel);  // ASCII: VTK writes 6 significant digits
        check_array(s, "nrm", 3, {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
        check_array(s, "uv", 2, {0, 1, 2, 3, 4, 5, 6, 7});
        check_array(s, "stress", 9, stress);
        check_array(s, "ids", 1, {7, 8, 9, 10});
        check_array(s, "long", 1, {-1, 2, 3, std::ldexp(1.0, 40)});
        check_array(s, "a b_c", 2, {0, 1, 2, 3, 4, 5, 6, 7});
        check_array(s, "bits", 1, {1, 0, 1, 1});
        check_array(s, "chars", 1, {-5, 0, 5, 100});
        check_array(s, "schars", 1, {-128, 0, 5, 127});
        check_array(s, "uints", 1, {0, 1, 4e9, 5});
        // Not the active scalars: a FIELD array of unsigned char, read as the bytes (only
        // COLOR_SCALARS are scaled to 0..1).
        check_array(s, "rgb", 3, {255, 0, 0, 0, 255, 0, 0, 0, 255, 51, 102, 153});
        CHECK(find_array(s, "names") == nullptr);
        CHECK(has_note(report, "'names' (strings)"));
        CHECK(has_note(report, "'a b/c' stored as 'a b_c'"));
    }
    std::filesystem::remove_all(dir);
    std::filesystem::remove(script_path);
}
