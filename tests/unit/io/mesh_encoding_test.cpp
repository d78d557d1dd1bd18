// Binary and MSH 2.2 output (bpm/mesh_encoding.h): what the writers write in every
// encoding reads back through bpm's own readers as the same surface, bit for bit; the
// encodings a format does not have are refused, not ignored.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "bpm/errors.h"
#include "bpm/mesh_encoding.h"
#include "bpm/surface_io.h"
#include "bpm/write_vtu.h"
#include "test_support.h"

using namespace bpm;
using bpm::test_support::ScratchDir;

namespace {

std::string file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Coordinates that are not short decimals and patches out of order, so that a round trip
// that loses a bit or reorders anything shows.
Surface awkward_tetrahedron() {
    Surface s;
    s.vertices = {{0.1, -1e-300, 1.0 / 3}, {12345.678901234567, 0, -0.0}, {std::nextafter(1.0, 2.0), 2.0 / 3, 7e22},
                  {-5.5, 1e-7, 3.0000000000000004}};
    s.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    s.patches = {7, 2, 7, 0};
    return s;
}

// A closed surface big enough that every array of its VTU spans several 32 KiB zlib
// blocks: a triangulated torus of n x n quads.
Surface torus(int n) {
    Surface s;
    const double pi = std::acos(-1.0);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double u = 2 * pi * i / n, v = 2 * pi * j / n;
            s.vertices.push_back({(3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v)});
        }
    auto at = [n](int i, int j) { return int32_t(((i + n) % n) * n + (j + n) % n); };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            s.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            s.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
            s.patches.push_back(i % 3);
            s.patches.push_back(i % 3);
        }
    return s;
}

void check_bitwise_same(const Surface& a, const Surface& b) {
    REQUIRE(a.vertices.size() == b.vertices.size());
    CHECK(std::memcmp(a.vertices.data(), b.vertices.data(), a.vertices.size() * sizeof(Vec3)) == 0);
    CHECK(a.triangles == b.triangles);
    CHECK(a.patches == b.patches);
}

}  // namespace

TEST_CASE("binary MSH 4.1 and MSH 2.2 surfaces read back bit for bit", "[surface_io][encoding]") {
    const ScratchDir dir("mesh_encoding_msh");
    const Surface t = awkward_tetrahedron();
    const std::string binary = dir.file("binary.msh"), v22 = dir.file("v22.msh");
    write_surface(binary, t, SurfaceFormat::Msh, MeshEncoding::Binary);
    write_surface(v22, t, SurfaceFormat::Msh22);
    SurfaceReadReport report;
    check_bitwise_same(read_surface(binary, {}, &report), t);
    REQUIRE(report.patch_info.size() == 3);
    CHECK(report.patch_info[2].name == "patch_7");
    check_bitwise_same(read_surface(v22, {}, &report), t);
    REQUIRE(report.patch_info.size() == 3);
    CHECK(report.patch_info[0].name == "patch_0");

    const std::string b = file_bytes(binary), a = file_bytes(v22);
    CHECK(b.rfind("$MeshFormat\n4.1 1 8\n", 0) == 0);
    // MSH 2.2 for DUNE 2.9's GmshReader: $Nodes right after $MeshFormat, the names after $Elements.
    CHECK(a.rfind("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n", 0) == 0);
    CHECK(a.find("$EndElements\n$PhysicalNames\n3\n2 1 \"patch_0\"\n") != std::string::npos);
    CHECK(a.find("\n1 2 2 8 3 1 3 2\n") != std::string::npos);  // triangle 1: physical tag 7 + 1, entity 3
    // Deterministic.
    write_surface(binary, t, SurfaceFormat::Msh, MeshEncoding::Binary);
    CHECK(file_bytes(binary) == b);
    // "msh22" names the format; the extension .msh stays MSH 4.1.
    CHECK(surface_format_from_name("MSH22") == SurfaceFormat::Msh22);
    CHECK(surface_format_from_path("a.msh") == SurfaceFormat::Msh);
}

TEST_CASE("binary and zlib VTU surfaces read back bit for bit, data arrays too", "[surface_io][encoding]") {
    const ScratchDir dir("mesh_encoding_vtu");
    const Surface t = torus(60);  // 3,600 vertices: 86 KB of coordinates, three zlib blocks
    std::vector<double> heat, bary;
    for (size_t v = 0; v < t.vertices.size(); ++v) {
        heat.push_back(std::sqrt(double(v)) / 7);
        bary.insert(bary.end(), {1.0 / 3, 0.5, 1.0 / 6});
    }
    std::vector<double> level(t.triangles.size(), 2);
    const std::string ascii = dir.file("ascii.vtu");
    write_surface_vtu(ascii, t, {{"heat", 1, heat}, {"bary", 3, bary}}, {{"level", 1, level}});
    const size_t ascii_size = file_bytes(ascii).size();
    for (MeshEncoding e : {MeshEncoding::Binary, MeshEncoding::BinaryZlib}) {
        const bool zlib = e == MeshEncoding::BinaryZlib;
        INFO((zlib ? "zlib" : "binary"));
        const std::string path = dir.file(zlib ? "zlib.vtu" : "binary.vtu");
        write_surface_vtu(path, t, {{"heat", 1, heat}, {"bary", 3, bary}}, {{"level", 1, level}}, e);
        const std::string bytes = file_bytes(path);
        CHECK(bytes.find("<AppendedData encoding=\"raw\">") != std::string::npos);
        CHECK((bytes.find("compressor=\"vtkZLibDataCompressor\"") != std::string::npos) == zlib);
        CHECK(bytes.find("type=\"Int32\" Name=\"connectivity\"") != std::string::npos);  // narrowed from Int64
        CHECK(bytes.size() < ascii_size / 2);
        const Surface back = read_surface(path);
        check_bitwise_same(back, t);
        REQUIRE(back.vertex_data.size() == 2);
        CHECK(back.vertex_data[0].values == heat);
        CHECK(back.vertex_data[1].values == bary);
    }
}

TEST_CASE("an encoding the format lacks is refused, not ignored", "[surface_io][encoding]") {
    const ScratchDir dir("mesh_encoding_refused");
    const Surface t = awkward_tetrahedron();
    CHECK_THROWS_WITH(write_surface(dir.file("a.off"), t, std::nullopt, MeshEncoding::Binary),
                      Catch::Contains("cannot write OFF as binary"));
    CHECK_THROWS_WITH(write_surface(dir.file("a.msh"), t, SurfaceFormat::Msh22, MeshEncoding::Binary),
                      Catch::Contains("MSH 2.2 as binary"));
    CHECK_THROWS_WITH(write_surface(dir.file("a.msh"), t, std::nullopt, MeshEncoding::BinaryZlib),
                      Catch::Contains("compressed"));
    CHECK_FALSE(std::filesystem::exists(dir.file("a.msh")));
    // Binary formats take Binary (they are binary anyway).
    write_surface(dir.file("a.ply"), t, std::nullopt, MeshEncoding::Binary);
    check_bitwise_same(read_surface(dir.file("a.ply")), t);
}
