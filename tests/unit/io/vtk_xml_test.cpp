// The VTK XML reader (.vtp, .vtu): every data encoding VTK writes (ascii, inline base64,
// appended raw and base64, zlib-compressed or not, UInt32/UInt64 headers, either byte
// order) reads the same surface, point data and patches exactly; strips, polygons, cell
// types and pieces; malformed files fail with the line of what is wrong. The files are
// written here by a small encoder that follows VTK's layout (headers base64-encoded
// separately from compressed data, as vtkXMLWriter does).
#include <catch2/catch.hpp>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "bpm/errors.h"
#include "bpm/refine.h"
#include "bpm/surface_io.h"
#include "bpm/write_vtu.h"
#include "test_bytes.h"
#include "test_support.h"

using namespace bpm;
namespace fs = std::filesystem;

namespace {

std::string base64(const std::string& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t v = static_cast<uint32_t>(static_cast<unsigned char>(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= static_cast<uint32_t>(static_cast<unsigned char>(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 2]);
        out += table[(v >> 18) & 63];
        out += table[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? table[v & 63] : '=';
    }
    return out;
}

struct Encoding {
    std::string format = "ascii";  // ascii, binary, appended
    bool raw = false;              // appended: encoding="raw" (else base64)
    bool zlib = false;
    bool header64 = false;
    bool big_endian = false;
    size_t block_size = 32768;  // uncompressed bytes per zlib block
};

std::string describe(const Encoding& e) {
    return e.format + (e.format == "appended" ? (e.raw ? " raw" : " base64") : "") + (e.zlib ? " zlib" : "") +
           (e.header64 ? " UInt64" : " UInt32") + (e.big_endian ? " big-endian" : "");
}

// Writes DataArrays in one encoding; appended data is collected and put at the end.
class VtkWriter {
public:
    explicit VtkWriter(Encoding e) : e_(e) {}

    template <class T>
    void put(std::string& out, T value) const {
        test_bytes::put(out, value, e_.big_endian);
    }
    void put_header(std::string& out, uint64_t v) const {
        if (e_.header64) put<uint64_t>(out, v);
        else put<uint32_t>(out, static_cast<uint32_t>(v));
    }

    std::string array(const std::string& type, const std::string& name, int components, const std::vector<double>& v) {
        std::string data;
        for (double x : v) {
            if (type == "Float64") put<double>(data, x);
            else if (type == "Float32") put<float>(data, static_cast<float>(x));
            else if (type == "Int32") put<int32_t>(data, static_cast<int32_t>(x));
            else if (type == "Int64") put<int64_t>(data, static_cast<int64_t>(x));
            else if (type == "UInt8") put<uint8_t>(data, static_cast<uint8_t>(x));
            else if (type == "UInt64") put<uint64_t>(data, static_cast<uint64_t>(x));
            else FAIL("unknown type " << type);
        }
        std::string out = "<DataArray type=\"" + type + "\"" + (name.empty() ? "" : " Name=\"" + name + "\"") +
                          " NumberOfComponents=\"" + std::to_string(components) + "\" format=\"" + e_.format + "\"";
        if (e_.format == "ascii") {
            out += ">\n";
            for (double x : v) {
                char buf[40];
                std::snprintf(buf, sizeof buf, "%.17g ", x);
                out += buf;
            }
            return out + "\n</DataArray>\n";
        }
        // Header and data as VTK writes them: [n] data, or [blocks, size, last, csizes] blocks.
        std::string header, body;
        if (!e_.zlib) {
            put_header(header, data.size());
            body = data;
        } else {
            std::vector<std::string> blocks;
            for (size_t at = 0; at < data.size(); at += e_.block_size) {
                const std::string chunk = data.substr(at, e_.block_size);
                uLongf n = compressBound(chunk.size());
                std::string c(n, '\0');
                REQUIRE(compress(reinterpret_cast<Bytef*>(&c[0]), &n, reinterpret_cast<const Bytef*>(chunk.data()),
                                 chunk.size()) == Z_OK);
                c.resize(n);
                blocks.push_back(c);
            }
            put_header(header, blocks.size());
            put_header(header, e_.block_size);
            put_header(header, data.size() % e_.block_size);
            for (const std::string& b : blocks) {
                put_header(header, b.size());
                body += b;
            }
        }
        if (e_.format == "binary") {
            // Uncompressed: one base64 run for all; compressed: the header on its own.
            const std::string text = e_.zlib ? base64(header) + base64(body) : base64(header + body);
            return out + ">\n" + text + "\n</DataArray>\n";
        }
        const size_t offset = appended_.size();
        appended_ += e_.raw ? header + body : base64(header) + base64(body);
        return out + " offset=\"" + std::to_string(offset) + "\"/>\n";
    }

    std::string file(const std::string& type, const std::string& pieces) const {
        std::string out = "<?xml version=\"1.0\"?>\n<VTKFile type=\"" + type + "\" version=\"1.0\" byte_order=\"" +
                          (e_.big_endian ? "BigEndian" : "LittleEndian") + "\" header_type=\"" +
                          (e_.header64 ? "UInt64" : "UInt32") + "\"" +
                          (e_.zlib ? " compressor=\"vtkZLibDataCompressor\"" : "") + ">\n<" + type + ">\n" + pieces +
                          "</" + type + ">\n";
        if (e_.format == "appended") {
            out += std::string("<AppendedData encoding=\"") + (e_.raw ? "raw" : "base64") + "\">\n   _" + appended_ +
                   "\n</AppendedData>\n";
        }
        return out + "</VTKFile>\n";
    }

private:
    Encoding e_;
    std::string appended_;
};

// A tetrahedron with awkward coordinates, patches and two point arrays.
struct Fixture {
    std::vector<double> points = {0.1, -1e-300, 1.0 / 3, 12345.678901234567, 0, -0.0, 1.0000000000000002, 2.0 / 3, 7e22,
                                  -5.5, 1e-7, 3.0000000000000004};
    std::vector<double> connectivity = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    std::vector<double> offsets = {3, 6, 9, 12};
    std::vector<double> material = {7, 2, 7, 0};
    std::vector<double> temperature = {0.5, -1.25, 1e-10, 300};
    std::vector<double> velocity = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
};

// Appended arrays go in the order of the statements below: the operands of + may be
// evaluated in any order, so appended files are never built by chains of w.array() + w.array().
std::string tet_piece(VtkWriter& w, const Fixture& f) {
    std::string p = "<Piece NumberOfPoints=\"4\" NumberOfPolys=\"4\">\n<PointData Scalars=\"temperature\">\n";
    p += w.array("Float64", "temperature", 1, f.temperature);
    p += w.array("Float32", "velocity", 3, f.velocity);
    p += "</PointData>\n<CellData>\n";
    p += w.array("Float64", "area", 1, {1, 2, 3, 4});
    p += w.array("Int32", "material", 1, f.material);
    p += "</CellData>\n<Points>\n";
    p += w.array("Float64", "Points", 3, f.points);
    p += "</Points>\n<Polys>\n";
    p += w.array("Int64", "connectivity", 1, f.connectivity);
    p += w.array("Int64", "offsets", 1, f.offsets);
    return p + "</Polys>\n</Piece>\n";
}

std::string tet_vtu_piece(VtkWriter& w, const Fixture& f) {
    std::string p = "<Piece NumberOfPoints=\"4\" NumberOfCells=\"4\">\n<PointData>\n";
    p += w.array("Float64", "temperature", 1, f.temperature);
    p += "</PointData>\n<CellData>\n";
    p += w.array("Int32", "CellEntityIds", 1, f.material);
    p += "</CellData>\n<Points>\n";
    p += w.array("Float64", "Points", 3, f.points);
    p += "</Points>\n<Cells>\n";
    p += w.array("Int32", "connectivity", 1, f.connectivity);
    p += w.array("Int32", "offsets", 1, f.offsets);
    p += w.array("UInt8", "types", 1, {5, 5, 5, 5});
    return p + "</Cells>\n</Piece>\n";
}

Surface read_vtk(const std::string& bytes, SurfaceFormat format = SurfaceFormat::Vtp, const SurfaceReadOptions& o = {},
                 SurfaceReadReport* report = nullptr) {
    return read_surface_from_memory(bytes, format, "test.vtp", o, report);
}

std::string vtk_error(const std::string& bytes, SurfaceFormat format = SurfaceFormat::Vtp,
                      const SurfaceReadOptions& o = {}) {
    try {
        (void)read_vtk(bytes, format, o);
    } catch (const InputError& e) {
        CHECK(e.where() == "test.vtp");
        return e.what();
    }
    return "";
}

const VertexArray* find_array(const Surface& s, const std::string& name) {
    for (const VertexArray& a : s.vertex_data)
        if (a.name == name) return &a;
    return nullptr;
}

bool has_note(const SurfaceReadReport& r, const std::string& text) {
    for (const std::string& n : r.notes)
        if (n.find(text) != std::string::npos) return true;
    return false;
}

std::vector<Encoding> all_encodings() {
    std::vector<Encoding> out;
    for (const char* format : {"ascii", "binary", "appended"}) {
        for (int raw = 0; raw < (std::string(format) == "appended" ? 2 : 1); ++raw) {
            for (int zlib = 0; zlib < (std::string(format) == "ascii" ? 1 : 2); ++zlib) {
                for (int h64 = 0; h64 < 2; ++h64) {
                    for (int big = 0; big < 2; ++big) {
                        Encoding e;
                        e.format = format;
                        e.raw = raw;
                        e.zlib = zlib;
                        e.header64 = h64;
                        e.big_endian = big;
                        e.block_size = 40;  // several blocks and a partial last one
                        out.push_back(e);
                    }
                }
            }
        }
    }
    return out;
}

}  // namespace

TEST_CASE("vtk xml: every encoding reads the same surface, point data and patches", "[surface_io][vtk_xml]") {
    const Fixture f;
    for (const Encoding& e : all_encodings()) {
        INFO(describe(e));
        VtkWriter w(e);
        const std::string pieces = tet_piece(w, f);
        const std::string bytes = w.file("PolyData", pieces);
        SurfaceReadReport report;
        const Surface s = read_vtk(bytes, SurfaceFormat::Vtp, {}, &report);
        REQUIRE(s.num_vertices() == 4);
        for (int v = 0; v < 4; ++v)
            for (int k = 0; k < 3; ++k) CHECK(s.vertices[v][k] == f.points[v * 3 + k]);
        CHECK(s.triangles == std::vector<Tri>{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}});
        CHECK(s.patches == std::vector<int32_t>{7, 2, 7, 0});
        REQUIRE(s.vertex_data.size() == 2);
        CHECK(s.vertex_data[0].name == "temperature");
        CHECK(s.vertex_data[0].components == 1);
        CHECK(s.vertex_data[0].values == f.temperature);
        CHECK(s.vertex_data[1].name == "velocity");
        CHECK(s.vertex_data[1].components == 3);
        CHECK(s.vertex_data[1].values == f.velocity);  // small integers: exact in Float32
        CHECK(has_note(report, "'material'"));
        CHECK(has_note(report, "cell data arrays ignored"));
        CHECK(has_note(report, "'area'"));

        VtkWriter wu(e);
        const std::string upieces = tet_vtu_piece(wu, f);
        const Surface u = read_vtk(wu.file("UnstructuredGrid", upieces), SurfaceFormat::Vtu);
        CHECK(u.vertices == s.vertices);
        CHECK(u.triangles == s.triangles);
        CHECK(u.patches == s.patches);
        REQUIRE(u.vertex_data.size() == 1);
        CHECK(u.vertex_data[0].values == f.temperature);
    }
}

TEST_CASE("vtk xml: formats, names and write refusal", "[surface_io][vtk_xml]") {
    CHECK(surface_format_from_name("VTP") == SurfaceFormat::Vtp);
    CHECK(surface_format_from_name("vtu") == SurfaceFormat::Vtu);
    CHECK(surface_format_from_path("a/b/mesh.vtp") == SurfaceFormat::Vtp);
    CHECK(surface_format_from_path("mesh.VTU") == SurfaceFormat::Vtu);
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    s.triangles = {{0, 1, 2}};
    s.patches = {0};
    const test_support::ScratchDir scratch("vtk_xml_test");
    const fs::path& dir = scratch.path;
    CHECK_THROWS_AS(write_surface((dir / "x.vtp").string(), s), OutputError);
    CHECK_THROWS_AS(write_surface((dir / "x.off").string(), s, SurfaceFormat::Vtu), OutputError);
    CHECK(!fs::exists(dir / "x.vtp"));
}

TEST_CASE("vtk xml: files VTK wrote (ascii with InformationKey, zlib binary)", "[surface_io][vtk_xml]") {
    // vtkSphereSource (theta 4, phi 3) through vtkXMLPolyDataWriter of VTK 9.1, cut down:
    // the Normals with their <InformationKey> before and after the data.
    const std::string ascii = R"(<?xml version="1.0"?>
<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian" header_type="UInt32">
  <PolyData>
    <Piece NumberOfPoints="4" NumberOfVerts="0" NumberOfLines="0" NumberOfStrips="0" NumberOfPolys="4">
      <PointData Normals="Normals">
        <DataArray type="Float32" Name="Normals" NumberOfComponents="3" format="ascii" RangeMin="1" RangeMax="1">
          <InformationKey name="L2_NORM_RANGE" location="vtkDataArray" length="2">
            <Value index="0">
              1
            </Value>
          </InformationKey>
          0 0 1 0 0 -1
          1 0 0 0 1 0
          <!-- a comment -->
        </DataArray>
      </PointData>
      <CellData>
      </CellData>
      <Points>
        <DataArray type="Float32" Name="Points" NumberOfComponents="3" format="ascii" RangeMin="0.5" RangeMax="0.5">
          0 0 0 1 0 0 0 1 0 0 0 1
        </DataArray>
      </Points>
      <Verts>
        <DataArray type="Int64" Name="connectivity" format="ascii" RangeMin="1e+299" RangeMax="-1e+299">
        </DataArray>
        <DataArray type="Int64" Name="offsets" format="ascii" RangeMin="1e+299" RangeMax="-1e+299">
        </DataArray>
      </Verts>
      <Polys>
        <DataArray type="Int64" Name="connectivity" format="ascii">
          0 2 1 0 1 3 0 3 2 1 2 3
        </DataArray>
        <DataArray type="Int64" Name="offsets" format="ascii">
          3 6 9 12
        </DataArray>
      </Polys>
    </Piece>
  </PolyData>
</VTKFile>
)";
    const Surface s = read_vtk(ascii);
    CHECK(s.num_triangles() == 4);
    CHECK(s.patches == std::vector<int32_t>{0, 0, 0, 0});
    REQUIRE(s.vertex_data.size() == 1);
    CHECK(s.vertex_data[0].name == "Normals");
    CHECK(s.vertex_data[0].values == std::vector<double>{0, 0, 1, 0, 0, -1, 1, 0, 0, 0, 1, 0});

    // The Normals of the same sphere (6 points), written by VTK with SetDataModeToBinary
    // and zlib: the header "AQAAAACAAABIAAAAKwAAAA==" (1 block of 72 bytes, 43 compressed)
    // base64-encoded on its own, then the block.
    std::string vtk_bytes = ascii;
    const std::string from = R"(<DataArray type="Float32" Name="Normals" NumberOfComponents="3" format="ascii" RangeMin="1" RangeMax="1">)";
    const size_t a = vtk_bytes.find(from);
    const size_t b = vtk_bytes.find("</DataArray>", a);
    vtk_bytes.replace(a, b - a, R"(<DataArray type="Float32" Name="Normals" NumberOfComponents="3" format="binary">
          AQAAAACAAABIAAAAKwAAAA==eF5jYICBBnsGBHs/jG9k2KsCwiA+lN5vZMirCmKfOhm8FMLvVQEAaLIOfw==
        )");
    vtk_bytes.replace(vtk_bytes.find("header_type=\"UInt32\""), 20, "header_type=\"UInt32\" compressor=\"vtkZLibDataCompressor\"");
    // 18 normals for 4 points: the size check sees it.
    CHECK_THAT(vtk_error(vtk_bytes), Catch::Contains("72 bytes, 48 expected"));
}

TEST_CASE("vtk xml: several pieces are concatenated", "[surface_io][vtk_xml]") {
    const Fixture f;
    for (const char* format : {"ascii", "appended"}) {
        Encoding e;
        e.format = format;
        e.raw = true;
        VtkWriter w(e);
        Fixture g = f;
        for (double& x : g.points) x = 2 * x + 100;  // no duplicate vertices
        const std::string pieces = tet_piece(w, f) + tet_piece(w, g);
        const Surface s = read_vtk(w.file("PolyData", pieces));
        REQUIRE(s.num_vertices() == 8);
        REQUIRE(s.num_triangles() == 8);
        CHECK(s.triangles[4] == Tri{4, 6, 5});
        CHECK(s.triangles[7] == Tri{5, 6, 7});
        CHECK(s.vertices[4][2] == g.points[2]);
        CHECK(s.patches == std::vector<int32_t>{7, 2, 7, 0, 7, 2, 7, 0});
        REQUIRE(s.vertex_data.size() == 2);
        CHECK(s.vertex_data[0].values.size() == 8);
        CHECK(s.vertex_data[1].values.size() == 24);
        CHECK(s.vertex_data[0].values[5] == f.temperature[1]);
    }
}

TEST_CASE("vtk xml: strips, polygons and cell types", "[surface_io][vtk_xml]") {
    Encoding e;
    VtkWriter w(e);
    // A strip over a 2 x 3 grid of points 0 1 2 / 3 4 5: 0 3 1 4 2 5.
    const std::vector<double> grid = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0};
    const std::string strip = "<Piece NumberOfPoints=\"6\" NumberOfStrips=\"1\">\n<Points>\n" +
                              w.array("Float64", "", 3, grid) + "</Points>\n<Strips>\n" +
                              w.array("Int32", "connectivity", 1, {0, 3, 1, 4, 2, 5}) +
                              w.array("Int32", "offsets", 1, {6}) + "</Strips>\n</Piece>\n";
    SurfaceReadReport report;
    const Surface s = read_vtk(w.file("PolyData", strip), SurfaceFormat::Vtp, {}, &report);
    // Alternating orientation: every triangle turns the same way as the first.
    CHECK(s.triangles == std::vector<Tri>{{0, 3, 1}, {1, 3, 4}, {1, 4, 2}, {2, 4, 5}});
    for (const Tri& t : s.triangles) {
        const Vec3 n = triangle_normal(s.vertices[t[0]], s.vertices[t[1]], s.vertices[t[2]]);
        CHECK(n[2] < 0);  // like the first, (0, 3, 1)
    }
    CHECK(has_note(report, "split 1 triangle strips"));

    // A quad among the polygons: refused, naming the repair; read with it.
    VtkWriter w2(e);
    const std::string quad = "<Piece NumberOfPoints=\"6\" NumberOfPolys=\"2\">\n<CellData>" +
                             w2.array("Int32", "Region", 1, {4, 9}) + "</CellData>\n<Points>\n" +
                             w2.array("Float64", "", 3, grid) + "</Points>\n<Polys>\n" +
                             w2.array("Int32", "connectivity", 1, {0, 1, 4, 3, 1, 2, 4}) +
                             w2.array("Int32", "offsets", 1, {4, 7}) + "</Polys>\n</Piece>\n";
    const std::string quad_file = w2.file("PolyData", quad);
    CHECK_THAT(vtk_error(quad_file), Catch::Contains("line 14: face 0 has 4 corners") &&
                                         Catch::Contains("the repairs it needs, all together: triangulate polygons, drop unreferenced vertices"));
    SurfaceReadOptions repair;
    repair.triangulate_polygons = true;
    repair.drop_unreferenced_vertices = true;  // point 5 is in no triangle
    const Surface q = read_vtk(quad_file, SurfaceFormat::Vtp, repair, &report);
    CHECK(q.num_triangles() == 3);
    CHECK(q.patches == std::vector<int32_t>{4, 4, 9});
    CHECK(has_note(report, "triangulated 1 polygon face"));

    // UnstructuredGrid: a triangle, a quad, a tetrahedron and a line; the last two skipped.
    VtkWriter w3(e);
    const std::string mixed = "<Piece NumberOfPoints=\"6\" NumberOfCells=\"4\">\n<Points>\n" +
                              w3.array("Float64", "", 3, grid) + "</Points>\n<Cells>\n" +
                              w3.array("Int64", "connectivity", 1, {1, 2, 4, 0, 1, 4, 3, 0, 1, 3, 5, 2, 5}) +
                              w3.array("Int64", "offsets", 1, {3, 7, 11, 13}) +
                              w3.array("UInt8", "types", 1, {5, 9, 10, 3}) + "</Cells>\n</Piece>\n";
    const Surface m = read_vtk(w3.file("UnstructuredGrid", mixed), SurfaceFormat::Vtu, repair, &report);
    CHECK(m.num_triangles() == 3);
    CHECK(has_note(report, "skipped 0 vertex and 1 line cells"));
    CHECK(has_note(report, "skipped 1 volume or higher-order cells (1 of type 10)"));

    // Only volume cells: refused.
    VtkWriter w4(e);
    const std::string tets = "<Piece NumberOfPoints=\"6\" NumberOfCells=\"1\">\n<Points>\n" +
                             w4.array("Float64", "", 3, grid) + "</Points>\n<Cells>\n" +
                             w4.array("Int64", "connectivity", 1, {0, 1, 3, 5}) + w4.array("Int64", "offsets", 1, {4}) +
                             w4.array("UInt8", "types", 1, {10}) + "</Cells>\n</Piece>\n";
    CHECK_THAT(vtk_error(w4.file("UnstructuredGrid", tets), SurfaceFormat::Vtu),
               Catch::Contains("line 10: no surface cells") && Catch::Contains("extract the boundary first"));
}

TEST_CASE("vtk xml: point data names and values", "[surface_io][vtk_xml]") {
    const Fixture f;
    Encoding e;
    e.format = "binary";
    VtkWriter w(e);
    std::vector<double> with_nan = f.temperature;
    with_nan[2] = std::nan("");
    const std::string piece = "<Piece NumberOfPoints=\"4\" NumberOfPolys=\"4\">\n<PointData>\n" +
                              w.array("Float64", "a/b", 1, f.temperature) + w.array("Float64", "a_b", 1, f.temperature) +
                              w.array("Float64", "a_b", 1, f.temperature) + w.array("Float64", "bad", 1, with_nan) +
                              w.array("UInt64", "", 1, {1, 2, 3, 18446744073709549568.0}) +
                              "<DataArray type=\"String\" Name=\"words\" format=\"ascii\">97 0</DataArray>\n" +
                              "</PointData>\n<Points>\n" + w.array("Float64", "Points", 3, f.points) +
                              "</Points>\n<Polys>\n" + w.array("Int64", "connectivity", 1, f.connectivity) +
                              w.array("Int64", "offsets", 1, f.offsets) + "</Polys>\n</Piece>\n";
    SurfaceReadReport report;
    const Surface s = read_vtk(w.file("PolyData", piece), SurfaceFormat::Vtp, {}, &report);
    REQUIRE(s.vertex_data.size() == 4);
    CHECK(s.vertex_data[0].name == "a_b");
    CHECK(s.vertex_data[1].name == "a_b_2");
    CHECK(s.vertex_data[2].name == "a_b_3");
    CHECK(s.vertex_data[3].name == "point_data_3");
    CHECK(s.vertex_data[3].values[3] == 18446744073709549568.0);
    CHECK(find_array(s, "bad") == nullptr);
    CHECK(has_note(report, "vertex data 'bad' left out: vertex 2"));
    CHECK(has_note(report, "'words' left out"));
    CHECK(has_note(report, "stored as 'a_b_2'"));
}

TEST_CASE("vtk xml: reads back what bpm-refine's write_surface_vtu writes", "[surface_io][vtk_xml]") {
    Surface s;
    s.vertices = {{0.1, 0, 0}, {1, 1.0 / 3, 0}, {0, 1, 2.0 / 3}, {0, 0, 1e-300}};
    s.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    s.patches = {3, -1, 3, 8};
    const test_support::ScratchDir scratch("vtk_xml_test_vtu");
    const fs::path& dir = scratch.path;
    const std::string path = (dir / "refined.vtu").string();
    write_surface_vtu(path, s, {{"temperature", 1, {1.5, 2.5, -3, 1e-20}}, {"bary", 3, std::vector<double>(12, 0.25)}},
              {{"level", 1, {0, 1, 2, 3}}});
    SurfaceReadReport report;
    const Surface r = read_surface(path, {}, &report);
    CHECK(report.format == SurfaceFormat::Vtu);
    CHECK(r.vertices == s.vertices);
    CHECK(r.triangles == s.triangles);
    CHECK(r.patches == s.patches);
    REQUIRE(r.vertex_data.size() == 2);
    CHECK(r.vertex_data[0].values == std::vector<double>{1.5, 2.5, -3, 1e-20});
    CHECK(r.vertex_data[1].components == 3);
}

TEST_CASE("vtk xml: malformed files fail with their line", "[surface_io][vtk_xml]") {
    const Fixture f;
    auto good = [&](const Encoding& e) {
        VtkWriter w(e);
        const std::string pieces = tet_piece(w, f);
        return w.file("PolyData", pieces);
    };
    Encoding ascii, binary, raw, b64, zlib;
    binary.format = "binary";
    raw.format = "appended";
    raw.raw = true;
    b64.format = "appended";
    zlib.format = "binary";
    zlib.zlib = true;
    for (const Encoding& e : {ascii, binary, raw, b64, zlib}) CHECK(vtk_error(good(e)).empty());

    auto replaced = [](std::string s, const std::string& from, const std::string& to) {
        const size_t at = s.find(from);
        REQUIRE(at != std::string::npos);
        return s.replace(at, from.size(), to);
    };
    // Bad base64: a character outside the alphabet, on the line of the Points data.
    {
        const std::string s = good(binary);
        const size_t points = s.find("Name=\"Points\"");
        const size_t data = s.find('\n', points) + 1;
        std::string bad = s;
        bad[data + 5] = '*';
        CHECK_THAT(vtk_error(bad), Catch::Contains("line 23: invalid base64 character '*'"));
    }
    // Truncated appended data (raw and base64).
    for (const Encoding& e : {raw, b64}) {
        const std::string s = good(e);
        const size_t end = s.find("\n</AppendedData>");
        CHECK_THAT(vtk_error(s.substr(0, end - 20)), Catch::Contains("line 18: DataArray 'offsets' of <Polys>") &&
                                                         (Catch::Contains("truncated") || Catch::Contains("ends")));
    }
    // Offsets that decrease; an index out of range; a cell with fewer than three corners.
    CHECK_THAT(vtk_error(replaced(good(ascii), "3 6 9 12", "3 9 6 12")),
               Catch::Contains("line 30: DataArray 'offsets' of <Polys>: entry 2") && Catch::Contains("must not decrease"));
    CHECK_THAT(vtk_error(replaced(good(ascii), "0 2 1 0 1 3", "0 2 1 0 1 4")),
               Catch::Contains("line 27: DataArray 'connectivity' of <Polys>: entry 5 (4) is out of range"));
    CHECK_THAT(vtk_error(replaced(good(ascii), "3 6 9 12", "2 6 9 12")),
               Catch::Contains("polygon 0 of <Polys> has 2 corners"));
    CHECK_THAT(vtk_error(replaced(good(ascii), "3 6 9 12", "3 6 9 13")),
               Catch::Contains("connectivity' of <Polys> holds 12 values, 13 expected"));
    // Garbage numbers, NaN coordinates, wrong counts.
    CHECK_THAT(vtk_error(replaced(good(ascii), "0 2 1 0 1 3", "0 2 x 0 1 3")),
               Catch::Contains("line 28: DataArray 'connectivity' of <Polys>: expected an integer, found 'x'"));
    CHECK_THAT(vtk_error(replaced(good(ascii), "12345.678901234567", "nan")), Catch::Contains("line 23:") &&
                                                                                Catch::Contains("'nan' is not a finite number"));
    CHECK_THAT(vtk_error(replaced(good(ascii), "NumberOfPoints=\"4\"", "NumberOfPoints=\"5\"")),
               Catch::Contains("line 22: DataArray 'Points' of <Points> holds 12 values, 15 expected"));
    // Decompressed size absurd: one block claiming 4 GB from a few bytes; never allocated.
    {
        Encoding z = zlib;
        z.format = "appended";
        z.raw = true;
        z.header64 = true;
        std::string s = good(z);
        // The first array (temperature): blocks=1, block size 32768, last 32, csize.
        const size_t at = s.find('_', s.find("<AppendedData")) + 1;
        const uint64_t huge = 4000000000ull;
        std::memcpy(&s[at + 8], &huge, 8);
        std::memset(&s[at + 16], 0, 8);  // last block full: 4 GB
        CHECK_THAT(vtk_error(s), Catch::Contains("line 6: DataArray 'temperature' of <PointData>") &&
                                     Catch::Contains("absurd decompressed size"));
        // Corrupt zlib data.
        std::string c = good(z);
        c[at + 32 + 4] ^= 0x55;
        CHECK_THAT(vtk_error(c), Catch::Contains("cannot be decompressed"));
    }
    // An appended header announcing more than there is.
    {
        std::string s = good(raw);
        const size_t at = s.find('_', s.find("<AppendedData")) + 1;
        s[at + 3] = 0x70;
        CHECK_THAT(vtk_error(s), Catch::Contains("line 6: DataArray 'temperature' of <PointData>: the header announces") &&
                                     Catch::Contains("(truncated?)"));
    }
    // Unknown elements, broken markup, unsupported file types and compressors.
    CHECK_THAT(vtk_error(replaced(good(ascii), "<CellData>", "<Bogus/>\n<CellData>")),
               Catch::Contains("line 13: unknown element <Bogus> in <Piece>"));
    CHECK_THAT(vtk_error(replaced(good(ascii), "</Points>", "")), Catch::Contains("</Piece> does not close <Points>"));
    CHECK_THAT(vtk_error(good(ascii).substr(0, 300)), Catch::Contains("is never closed"));
    CHECK_THAT(vtk_error(replaced(good(ascii), "type=\"PolyData\"", "type=\"ImageData\"")),
               Catch::Contains("line 2: VTKFile type 'ImageData' is not supported"));
    CHECK_THAT(vtk_error(replaced(good(binary), "header_type=\"UInt32\"", "compressor=\"vtkLZ4DataCompressor\"")),
               Catch::Contains("compressor 'vtkLZ4DataCompressor' is not supported"));
    CHECK_THAT(vtk_error(replaced(good(ascii), "format=\"ascii\"", "format=\"hex\"")),
               Catch::Contains("line 6: DataArray 'temperature' of <PointData>: unknown format 'hex'"));
    CHECK_THAT(vtk_error("solid x\nendsolid x\n"), Catch::Contains("line 1: not an XML file"));
    CHECK_THAT(vtk_error("<?xml version=\"1.0\"?>\n<html></html>\n"), Catch::Contains("line 2: the root element is <html>"));
    CHECK_THAT(vtk_error(""), Catch::Contains("empty"));
    // A file that is plainly VTK XML read as PLY says so.
    try {
        (void)read_surface_from_memory(good(ascii), SurfaceFormat::Ply, "test.ply");
        FAIL("read as PLY");
    } catch (const InputError& e) {
        CHECK_THAT(std::string(e.what()), Catch::Contains("looks like VTP"));
    }
}

TEST_CASE("vtk xml: the files VTK 9.1 wrote in tests/data/vtk_xml", "[surface_io][vtk_xml]") {
    // make_vtk_xml_fixtures.py: a sphere of 6 points and 8 triangles, temperature =
    // x + 2y + 3z + 1 (from the Float32 points, stored as Float64), material 1 2 3 1 ...
    const fs::path dir = fs::path(BPM_SOURCE_DIR) / "tests" / "data" / "vtk_xml";
    int files = 0;
    Surface first;
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string ext = entry.path().extension().string();
        if (ext != ".vtp" && ext != ".vtu") continue;
        INFO(entry.path().filename().string());
        SurfaceReadReport report;
        const Surface s = read_surface(entry.path().string(), {}, &report);
        CHECK(report.format == (ext == ".vtp" ? SurfaceFormat::Vtp : SurfaceFormat::Vtu));
        REQUIRE(s.num_vertices() == 6);
        REQUIRE(s.num_triangles() == 8);
        CHECK(s.patches == std::vector<int32_t>{1, 2, 3, 1, 2, 3, 1, 2});
        const VertexArray* t = find_array(s, "temperature");
        REQUIRE(t != nullptr);
        for (int v = 0; v < 6; ++v) {
            const Vec3& p = s.vertices[v];
            CHECK(t->values[v] == p[0] + 2 * p[1] + 3 * p[2] + 1.0);
        }
        const VertexArray* n = find_array(s, "Normals");
        REQUIRE(n != nullptr);
        CHECK(n->components == 3);
        if (files == 0) first = s;
        CHECK(s.vertices == first.vertices);
        CHECK(s.triangles == first.triangles);
        ++files;
    }
    CHECK(files == 8);
}

TEST_CASE("vtk xml: arrays sharing appended data are refused", "[surface_io][vtk_xml]") {
    // Many arrays at the same offset would decode the same bytes again and again: a small
    // file could allocate without bound. Legitimate files never share data.
    const Fixture f;
    Encoding e;
    e.format = "appended";
    e.raw = true;
    VtkWriter w(e);
    std::string piece = tet_piece(w, f);
    const std::string big = w.array("Float64", "big", 1000, std::vector<double>(4000, 0.5));  // 32 KB
    const size_t at = big.find("offset=\"") + 8;
    const std::string offset = big.substr(at, big.find('"', at) - at);
    std::string shared = big;
    for (int i = 0; i < 3; ++i) {
        shared += "<DataArray type=\"Float64\" Name=\"copy\" NumberOfComponents=\"1000\" format=\"appended\" offset=\"" +
                  offset + "\"/>\n";
    }
    piece.replace(piece.find("</PointData>"), 0, shared);
    const std::string bytes = w.file("PolyData", piece);
    REQUIRE(bytes.size() < 2 * 32000);
    CHECK_THAT(vtk_error(bytes), Catch::Contains("line 9: DataArray 'copy' of <PointData>") &&
                                     Catch::Contains("arrays overlapping in the appended data"));
}

namespace {

// An ascii .vtp of the given triangles over the given points.
std::string ascii_vtp(const std::vector<Vec3>& points, const std::vector<Tri>& triangles) {
    std::string s = "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                    "<PolyData><Piece NumberOfPoints=\"" + std::to_string(points.size()) +
                    "\" NumberOfPolys=\"" + std::to_string(triangles.size()) + "\">\n"
                    "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">";
    for (const Vec3& p : points) s += " " + test_bytes::text(p[0]) + " " + test_bytes::text(p[1]) + " " + test_bytes::text(p[2]);
    s += "</DataArray></Points>\n<Polys><DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">";
    for (const Tri& t : triangles) s += " " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]);
    s += "</DataArray><DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">";
    for (size_t i = 1; i <= triangles.size(); ++i) s += " " + std::to_string(3 * i);
    s += "</DataArray></Polys>\n</Piece></PolyData></VTKFile>\n";
    return s;
}

std::string pvtp(const std::vector<std::string>& sources, const std::string& ghost_level = "0") {
    std::string s = "<?xml version=\"1.0\"?>\n<VTKFile type=\"PPolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                    "<PPolyData GhostLevel=\"" + ghost_level + "\">\n"
                    "<PPoints><PDataArray type=\"Float64\" NumberOfComponents=\"3\"/></PPoints>\n";
    for (const std::string& source : sources) s += "<Piece Source=\"" + source + "\"/>\n";
    return s + "</PPolyData></VTKFile>\n";
}

void put_text_file(const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    REQUIRE(out.good());
}

}  // namespace

TEST_CASE("vtk xml: a parallel file (.pvtp) reads as the union of its pieces", "[surface_io][vtk_xml]") {
    const test_support::ScratchDir scratch("pvtp_test");
    const fs::path& dir = scratch.path;
    fs::create_directories(dir / "parts");
    // A tetrahedron in two pieces of two triangles; the pieces share all four points.
    const std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    put_text_file(dir / "parts" / "t_0.vtp", ascii_vtp(x, {{0, 2, 1}, {0, 1, 3}}));
    put_text_file(dir / "parts" / "t_1.vtp", ascii_vtp({x[0], x[3], x[2], x[1]}, {{0, 1, 2}, {3, 2, 1}}));
    put_text_file(dir / "t.pvtp", pvtp({"parts/t_0.vtp", "parts/t_1.vtp"}));
    CHECK(surface_format_from_path("t.pvtp") == SurfaceFormat::Vtp);
    CHECK(surface_format_from_path("t.pvtu") == SurfaceFormat::Vtu);
    SurfaceReadReport report;
    const Surface s = read_surface((dir / "t.pvtp").string(), {}, &report);
    CHECK(s.num_vertices() == 4);
    CHECK(s.num_triangles() == 4);
    CHECK(s.vertices == x);
    CHECK(s.triangles[2] == Tri{0, 3, 2});  // the second piece's points merged into the first's
    bool joined = false;
    for (const std::string& note : report.notes) joined |= note.find("2 pieces joined; 4 points that pieces share merged") != std::string::npos;
    CHECK(joined);

    auto error_of = [&](const std::string& wrapper) {
        put_text_file(dir / "bad.pvtp", wrapper);
        try {
            (void)read_surface((dir / "bad.pvtp").string());
        } catch (const InputError& e) {
            return std::string(e.where()) + ": " + e.what();
        }
        return std::string("no error");
    };
    CHECK_THAT(error_of(pvtp({"parts/t_0.vtp", "parts/missing.vtp"})),
               Catch::Contains("bad.pvtp: piece 1 (Source 'parts/missing.vtp')"));
    CHECK_THAT(error_of(pvtp({"parts/t_0.vtp"}, "1")), Catch::Contains("line 3: GhostLevel '1': pieces with ghost cells"));
    CHECK_THAT(error_of(pvtp({})), Catch::Contains("lists no <Piece Source=...>"));
    CHECK_THAT(error_of(pvtp({""})), Catch::Contains("<Piece> has no attribute Source"));
    CHECK_THAT(error_of(pvtp({"bad.pvtp"})), Catch::Contains("piece 0 (Source 'bad.pvtp') is a parallel file itself"));
    // An error inside a piece names the piece file and its line.
    put_text_file(dir / "parts" / "broken.vtp", "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\">\n<PolyData>\n");
    CHECK_THAT(error_of(pvtp({"parts/t_0.vtp", "parts/broken.vtp"})), Catch::Contains("broken.vtp: line"));
}
