// Surface readers and writers: each format reads a known surface, patch ids come through,
// writes read back exactly, and malformed input of every kind is refused with an
// InputError that says where and what (never a crash, a hang or a huge allocation).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "bpm/errors.h"
#include "bpm/surface_io.h"
#include "test_bytes.h"
#include "test_support.h"

using namespace bpm;
namespace fs = std::filesystem;

namespace {

Surface tetrahedron() {
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    s.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    s.patches = {0, 0, 1, 1};
    return s;
}

// Coordinates that are not short decimals, and patches out of order: round trips must be exact.
Surface awkward_tetrahedron() {
    Surface s = tetrahedron();
    s.vertices = {{0.1, -1e-300, 1.0 / 3}, {12345.678901234567, 0, -0.0}, {std::nextafter(1.0, 2.0), 2.0 / 3, 7e22},
                  {-5.5, 1e-7, 3.0000000000000004}};
    s.patches = {7, 2, 7, 0};
    return s;
}

std::string file_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

Surface read_bytes(const std::string& bytes, SurfaceFormat format, const SurfaceReadOptions& options = {},
                   SurfaceReadReport* report = nullptr) {
    return read_surface_from_memory(bytes, format, "test-input", options, report);
}

// The message of the InputError that reading `bytes` throws ("" if none is thrown).
std::string read_error(const std::string& bytes, SurfaceFormat format, const SurfaceReadOptions& options = {}) {
    try {
        (void)read_bytes(bytes, format, options);
    } catch (const InputError& e) {
        CHECK(e.where() == "test-input");
        CHECK(std::string(e.what()) != "");
        return e.what();
    }
    return "";
}

// The real meshes (scripts/setup.sh unpacks them); a test without them warns and passes.
bool have_mesh_dir(const fs::path& dir) {
    if (fs::is_directory(dir)) return true;
    WARN("no mesh directory " << dir.string() << "; skipped");
    return false;
}

#define CHECK_READ_ERROR(bytes, format, text)                               \
    do {                                                                    \
        const std::string message_ = read_error((bytes), (format));        \
        INFO("message: " << message_);                                      \
        CHECK(!message_.empty());                                           \
        CHECK(message_.find(text) != std::string::npos);                    \
    } while (0)

// ---- byte builders for the binary formats ----
template <class T>
void put(std::string& out, T value, bool big_endian = false) {
    test_bytes::put(out, value, big_endian);
}

std::string binary_stl(const Surface& s, const std::string& header) {
    std::string out = header;
    out.resize(80, ' ');
    put<uint32_t>(out, static_cast<uint32_t>(s.triangles.size()));
    for (const Tri& t : s.triangles) {
        for (int k = 0; k < 3; ++k) put<float>(out, 0.f);
        for (int32_t v : t) {
            for (double x : s.vertices[v]) put<float>(out, static_cast<float>(x));
        }
        put<uint16_t>(out, 0);
    }
    return out;
}

std::string msh22_binary(const Surface& s, bool big_endian, const std::vector<int>& node_tags) {
    std::string out = "$MeshFormat\n2.2 1 8\n";
    put<int32_t>(out, 1, big_endian);
    out += "\n$EndMeshFormat\n$Nodes\n" + std::to_string(s.vertices.size()) + "\n";
    for (size_t i = 0; i < s.vertices.size(); ++i) {
        put<int32_t>(out, node_tags[i], big_endian);
        for (double x : s.vertices[i]) put<double>(out, x, big_endian);
    }
    out += "\n$EndNodes\n$Elements\n" + std::to_string(s.triangles.size() + 1) + "\n";
    // one point element (type 15: 1 node, 2 tags) to be skipped
    put<int32_t>(out, 15, big_endian), put<int32_t>(out, 1, big_endian), put<int32_t>(out, 2, big_endian);
    put<int32_t>(out, 1, big_endian), put<int32_t>(out, 9, big_endian), put<int32_t>(out, 9, big_endian);
    put<int32_t>(out, node_tags[0], big_endian);
    put<int32_t>(out, 2, big_endian), put<int32_t>(out, static_cast<int32_t>(s.triangles.size()), big_endian);
    put<int32_t>(out, 2, big_endian);
    for (size_t t = 0; t < s.triangles.size(); ++t) {
        put<int32_t>(out, static_cast<int32_t>(t + 2), big_endian);
        put<int32_t>(out, s.patches[t], big_endian);
        put<int32_t>(out, 1, big_endian);
        for (int32_t v : s.triangles[t]) put<int32_t>(out, node_tags[v], big_endian);
    }
    out += "\n$EndElements\n";
    return out;
}

void check_same(const Surface& a, const Surface& b) {
    REQUIRE(a.vertices.size() == b.vertices.size());
    REQUIRE(a.triangles.size() == b.triangles.size());
    for (size_t i = 0; i < a.vertices.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            INFO("vertex " << i << " coordinate " << k);
            // Bitwise: -0 must stay -0, and the last bit of every double must survive.
            CHECK(std::memcmp(&a.vertices[i][k], &b.vertices[i][k], sizeof(double)) == 0);
        }
    }
    CHECK(a.triangles == b.triangles);
    CHECK(a.patches == b.patches);
}

}  // namespace

// ============================================================================ formats

TEST_CASE("format from name and extension", "[surface_io]") {
    CHECK(surface_format_from_name("OFF") == SurfaceFormat::Off);
    CHECK(surface_format_from_name("msh") == SurfaceFormat::Msh);
    CHECK(surface_format_from_name("vtk") == SurfaceFormat::Vtk);
    CHECK(surface_format_from_name("vtu") == SurfaceFormat::Vtu);  // VTK XML, read only
    CHECK_FALSE(surface_format_from_name("vti").has_value());        // image data: no surface
    CHECK(surface_format_from_path("a/b.c/mesh.PLY") == SurfaceFormat::Ply);
    CHECK(surface_format_from_path("x.stl") == SurfaceFormat::Stl);
    CHECK(surface_format_from_path("x.obj") == SurfaceFormat::Obj);
    CHECK_FALSE(surface_format_from_path("a.dir/mesh").has_value());
    CHECK_FALSE(surface_format_from_path("-").has_value());
}

TEST_CASE("OFF: reads a tetrahedron with comments, colours and counts on the keyword line", "[surface_io]") {
    const std::string text =
        "COFF 4 4 6 # counts on the keyword line\n"
        "# a comment line\n"
        "0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n\n0 1 0 0 0 255 255\n0 0 1 1 1 1 1\n"
        "3 0 2 1\n3 0 1 3 255 0 0\n3 0 3 2\n3 1 2 3 # last\n";
    const Surface s = read_bytes(text, SurfaceFormat::Off);
    CHECK(s.vertices == tetrahedron().vertices);
    CHECK(s.triangles == tetrahedron().triangles);
    CHECK(s.patches == std::vector<int32_t>{0, 0, 0, 0});
}

TEST_CASE("OBJ: groups and materials become patch ids in order of first use", "[surface_io]") {
    const std::string text =
        "mtllib x.mtl\n"
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1 1.0\nvt 0 0\nvn 0 0 1\n"
        "f 1 3 2\n"                      // no group yet: patch 0
        "g wing\nusemtl steel\n"
        "f 1/1 2/1 4/1\n"                // (wing, steel): 1
        "g body\n"
        "f -4//1 -1//1 -2//1\n"          // (body, steel): 2, relative indices
        "g wing\n"
        "f 2/1/1 3/1/1 4/1/1\n";         // (wing, steel) again: 1
    SurfaceReadReport report;
    const Surface s = read_bytes(text, SurfaceFormat::Obj, {}, &report);
    CHECK(s.vertices == tetrahedron().vertices);
    CHECK(s.triangles == tetrahedron().triangles);
    CHECK(s.patches == std::vector<int32_t>{0, 1, 2, 1});
    CHECK(report.format == SurfaceFormat::Obj);
}

TEST_CASE("OBJ: groups named patch_N keep N as the patch id", "[surface_io]") {
    const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\ng patch_5\nf 1 3 2\nf 1 2 4\ng patch_3\nf 1 4 3\ng patch_5\nf 2 3 4\n";
    CHECK(read_bytes(text, SurfaceFormat::Obj).patches == std::vector<int32_t>{5, 5, 3, 5});
    // One other name and the numbering is by first use again.
    const std::string mixed = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\ng patch_5\nf 1 3 2\nf 1 2 4\ng top\nf 1 4 3\nf 2 3 4\n";
    CHECK(read_bytes(mixed, SurfaceFormat::Obj).patches == std::vector<int32_t>{0, 0, 1, 1});
}

TEST_CASE("OBJ: groups named A|B or pair_A_B give their patches materials, other names none", "[surface_io]") {
    const std::string head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
    SurfaceReadReport report;
    (void)read_bytes(head + "g bone | muscle\nf 1 3 2\nf 1 2 4\ng pair_muscle_exterior\nf 1 4 3\ng lid\nf 2 3 4\n",
                     SurfaceFormat::Obj, {}, &report);
    REQUIRE(report.patch_info.size() == 3);
    CHECK(report.patch_info[0] == PatchInfo{0, "bone | muscle", "bone", "muscle", false});
    CHECK(report.patch_info[1] == PatchInfo{1, "pair_muscle_exterior", "muscle", "exterior", false});
    CHECK(report.patch_info[2] == PatchInfo{2, "lid", "", "", true});  // named, no materials
    // Groups that are just names say nothing about materials: the file's own material
    // applies (read from a path, apply_file_material), as for a file without groups, but
    // the names are kept (they were dropped: every patch was "<file>|exterior"). From
    // memory (no file name, no material) the names alone.
    (void)read_bytes(head + "g Cube\nf 1 3 2\nf 1 2 4\ng Lid\nf 1 4 3\nf 2 3 4\n", SurfaceFormat::Obj, {}, &report);
    CHECK(report.patch_info == std::vector<PatchInfo>{{0, "Cube", "", "", true}, {1, "Lid", "", "", true}});
    const test_support::ScratchDir scratch("surface_io_obj_names");
    std::ofstream(scratch.path / "part.obj") << head << "g inlet\nf 1 3 2\ng wall\nusemtl steel\nf 1 2 4\nf 1 4 3\n"
                                             << "g\nusemtl paint\nf 2 3 4\n";
    (void)read_surface((scratch.path / "part.obj").string(), {}, &report);
    CHECK(report.patch_info == std::vector<PatchInfo>{{0, "inlet", "exterior", "part", true},
                                                      {1, "wall (steel)", "exterior", "part", true},
                                                      {2, "paint", "exterior", "part", true}});
}

TEST_CASE("one file of a closed surface per label: each label encloses a material of its own", "[surface_io]") {
    // Two tetrahedra on either side of the triangle (1, 2, 3), each a closed surface facing
    // outward, told apart by their groups (labels 1 and 2), the shared face in both.
    const test_support::ScratchDir scratch("surface_io_labels");
    const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 1 1 1\n"
                             "g patch_1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
                             "g patch_2\nf 2 4 3\nf 2 5 4\nf 3 4 5\nf 2 3 5\n";
    const fs::path path = scratch.path / "cells.obj";
    std::ofstream(path) << text;
    SurfaceReadOptions options;
    options.merge_duplicate_triangles = true;
    SurfaceReadReport report;
    const Surface s = read_surface(path.string(), options, &report);
    CHECK(s.num_triangles() == 7);
    REQUIRE(report.patch_info.size() == 3);
    CHECK(report.patch_info[0] == PatchInfo{1, "cells_1|exterior", "exterior", "cells_1", true});
    CHECK(report.patch_info[1] == PatchInfo{2, "cells_2|exterior", "exterior", "cells_2", true});
    const PatchInfo& fused = report.patch_info[2];
    CHECK(((fused.front == "cells_2" && fused.back == "cells_1") || (fused.front == "cells_1" && fused.back == "cells_2")));
    // A file of one material: the files' material, as before.
    std::ofstream(scratch.path / "a.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    (void)read_surface((scratch.path / "a.obj").string(), options, &report);
    REQUIRE(report.patch_info.size() == 1);
    CHECK(report.patch_info[0].back == "a");
    // One closed surface in two patches (faces of a part) with one triangle in both: no
    // patch is closed alone, so this is no surface per label, and the material stays the
    // file's.
    std::ofstream(scratch.path / "part.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                                "g patch_1\nf 1 3 2\nf 1 2 4\ng patch_2\nf 1 4 3\nf 2 3 4\nf 1 2 3\n";
    (void)read_surface((scratch.path / "part.obj").string(), options, &report);
    REQUIRE(report.patch_info.size() >= 2);
    for (const PatchInfo& info : report.patch_info) CHECK(info.back.rfind("part_", 0) == std::string::npos);
}

TEST_CASE("STL: ASCII with two solids gives two patches and shared vertices, normals are ignored", "[surface_io]") {
    const Surface t = tetrahedron();
    std::string text;
    for (int solid = 0; solid < 2; ++solid) {
        text += "solid part " + std::to_string(solid) + "\n";
        for (int f = 2 * solid; f < 2 * solid + 2; ++f) {
            text += f == 1 ? "  facet normal nan -nan +1e999\n    outer loop\n" : "  facet normal 0 0 0\n    outer loop\n";
            for (int32_t v : t.triangles[f]) {
                text += "      vertex " + std::to_string(t.vertices[v][0]) + " " + std::to_string(t.vertices[v][1]) +
                        " " + std::to_string(t.vertices[v][2]) + "\n";
            }
            text += "    endloop\n  endfacet\n";
        }
        text += "endsolid part\n";
    }
    const Surface s = read_bytes(text, SurfaceFormat::Stl);
    CHECK(s.num_vertices() == 4);
    CHECK(s.num_triangles() == 4);
    CHECK(s.patches == std::vector<int32_t>{0, 0, 1, 1});
    CHECK(s.triangles[0] == Tri{0, 1, 2});  // vertices numbered in order of first appearance
}

TEST_CASE("STL: a binary file whose header starts with 'solid' is read as binary", "[surface_io]") {
    const Surface t = tetrahedron();
    const Surface s = read_bytes(binary_stl(t, "solid exported by some CAD tool"), SurfaceFormat::Stl);
    REQUIRE(s.num_triangles() == 4);
    CHECK(s.num_vertices() == 4);
    for (int f = 0; f < 4; ++f) {
        for (int k = 0; k < 3; ++k) CHECK(s.vertices[s.triangles[f][k]] == t.vertices[t.triangles[f][k]]);
    }
}

TEST_CASE("STL: -0 and +0 are one position when corners are merged", "[surface_io]") {
    Surface t = tetrahedron();
    std::string bytes = binary_stl(t, "x");
    // Make the first corner of the second triangle (vertex 0 = (0,0,0)) read as (-0, 0, 0).
    const size_t at = 84 + 50 + 12;
    const float minus_zero = -0.0f;
    std::memcpy(&bytes[at], &minus_zero, 4);
    CHECK(read_bytes(bytes, SurfaceFormat::Stl).num_vertices() == 4);
}

TEST_CASE("PLY: ASCII with extra properties, elements and a face label", "[surface_io]") {
    const std::string text =
        "ply\nformat ascii 1.0\ncomment extra stuff everywhere\n"
        "element vertex 4\nproperty double x\nproperty double y\nproperty double z\nproperty float nx\n"
        "property list uchar float texture\nproperty uchar red\n"
        "element face 4\nproperty list uchar int vertex_indices\nproperty uchar red\nproperty int label\n"
        "property int region\n"
        "element edge 2\nproperty int vertex1\nproperty int vertex2\nproperty float confidence\n"
        "end_header\n"
        "0 0 0 nan 2 0.5 0.5 255\n1 0 0 0 0 7\n0 1 0 0 1 9 0\n0 0 1 0 0 1\n"
        "3 0 2 1 255 4 99\n3 0 1 3 0 -1 99\n3 0 3 2 0 4 99\n3 1 2 3 0 2 99\n"
        "0 1 0.5\n1 2 inf\n";
    const Surface s = read_bytes(text, SurfaceFormat::Ply);
    CHECK(s.vertices == tetrahedron().vertices);
    CHECK(s.triangles == tetrahedron().triangles);
    CHECK(s.patches == std::vector<int32_t>{4, -1, 4, 2});  // `label` comes before `region`
}

TEST_CASE("PLY: binary little and big endian with every property type", "[surface_io]") {
    const Surface t = awkward_tetrahedron();
    for (const bool big : {false, true}) {
        std::string out = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                          " 1.0\nelement material 2\nproperty list ushort char name\n"
                          "element vertex 4\nproperty char a\nproperty double x\nproperty uchar b\nproperty double y\n"
                          "property short c\nproperty ushort d\nproperty double z\nproperty uint e\nproperty float f\n"
                          "element face 4\nproperty list uint uint16 vertex_index\nproperty uchar physical\n"
                          "end_header\n";
        for (int m = 0; m < 2; ++m) {
            put<uint16_t>(out, 3, big);
            out += "abc";
        }
        for (const Vec3& p : t.vertices) {
            put<int8_t>(out, -1, big), put<double>(out, p[0], big), put<uint8_t>(out, 200, big);
            put<double>(out, p[1], big), put<int16_t>(out, -300, big), put<uint16_t>(out, 60000, big);
            put<double>(out, p[2], big), put<uint32_t>(out, 4000000000u, big), put<float>(out, 1.5f, big);
        }
        for (size_t f = 0; f < 4; ++f) {
            put<uint32_t>(out, 3, big);
            for (int32_t v : t.triangles[f]) put<uint16_t>(out, static_cast<uint16_t>(v), big);
            put<uint8_t>(out, static_cast<uint8_t>(t.patches[f]), big);
        }
        INFO((big ? "big endian" : "little endian"));
        check_same(read_bytes(out, SurfaceFormat::Ply), t);
    }
}

TEST_CASE("MSH 2.2 ASCII: physical tags, sparse node tags, skipped elements", "[surface_io]") {
    const std::string text =
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
        "$PhysicalNames\n2\n2 10 \"skin\"\n2 20 \"bone\"\n$EndPhysicalNames\n"
        "$Nodes\n5\n100 0 0 0\n7 1 0 0\n55 0 1 0\n3 0 0 1\n9 0.2 0.2 0.2\n$EndNodes\n"
        "$Elements\n7\n"
        "1 15 2 0 1 100\n"           // point: skipped
        "2 2 2 10 1 100 55 7\n"
        "3 1 2 0 1 100 7\n"          // line: skipped
        "4 2 2 10 1 100 7 3\n"
        "5 2 2 20 2 100 3 55\n"
        "6 2 0 7 55 3\n"             // no tags: patch 0
        "7 4 2 0 1 100 7 55 9\n"     // tetrahedron: skipped, node 9 unreferenced
        "$EndElements\n"
        "$Comments\nanything $Nodes here\n$EndComments\n";
    SurfaceReadReport report;
    CHECK_THROWS_AS(read_bytes(text, SurfaceFormat::Msh), InputError);  // node 9 is unreferenced
    SurfaceReadOptions options;
    options.drop_unreferenced_vertices = true;
    const Surface s = read_bytes(text, SurfaceFormat::Msh, options, &report);
    CHECK(s.vertices == tetrahedron().vertices);
    CHECK(s.triangles == tetrahedron().triangles);
    CHECK(s.patches == std::vector<int32_t>{10, 10, 20, 0});
    CHECK(report.skipped_elements == 3);
    CHECK(report.dropped_vertices == 1);
}

TEST_CASE("MSH 2.2 binary: little and big endian", "[surface_io]") {
    const Surface t = awkward_tetrahedron();
    for (const bool big : {false, true}) {
        SurfaceReadReport report;
        INFO((big ? "big endian" : "little endian"));
        check_same(read_bytes(msh22_binary(t, big, {40, 3, 1000000, 12}), SurfaceFormat::Msh, {}, &report), t);
        CHECK(report.skipped_elements == 1);
    }
}

TEST_CASE("MSH 4.1 ASCII: physical tags of entities, multiple blocks, parametric nodes", "[surface_io]") {
    const std::string text =
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
        "$Entities\n1 0 3 0\n"
        "1 0 0 0 0\n"                                  // point 1, no physical tag
        "1 0 0 0 1 1 1 2 31 32 0\n"                    // surface 1: physical 31 (first of two)
        "2 0 0 0 1 1 1 0 0\n"                          // surface 2: no physical tag -> patch 0
        "3 0 0 0 1 1 1 1 -4 2 1 2\n"                   // surface 3: physical -4, two bounding curves
        "$EndEntities\n"
        "$Nodes\n3 4 3 80\n"
        "0 1 0 1\n80\n0 0 0\n"
        "2 1 1 2\n3\n20\n1 0 0 0.5 0.5\n0 1 0 0.1 0.2\n"  // parametric: u v follow
        "2 3 0 1\n4\n0 0 1\n"
        "$EndNodes\n"
        "$Elements\n4 5 1 6\n"
        "0 1 15 1\n1 80\n"
        "2 1 2 2\n2 80 20 3\n3 80 3 4\n"
        "2 2 2 1\n4 80 4 20\n"
        "2 3 2 1\n5 3 20 4\n"
        "$EndElements\n";
    SurfaceReadReport report;
    const Surface s = read_bytes(text, SurfaceFormat::Msh, {}, &report);
    CHECK(s.vertices == tetrahedron().vertices);
    CHECK(s.triangles == tetrahedron().triangles);
    CHECK(s.patches == std::vector<int32_t>{31, 31, 0, -4});
    CHECK(report.skipped_elements == 1);
}

TEST_CASE("MSH 4.1: physical volumes give the materials on the sides of the physical surfaces they bound",
          "[surface_io]") {
    // Volume 1 (physical 5, "bone") is bounded by surfaces 1, 2 and 3, volume 2 (physical 6,
    // no name) by surface 2. They were read and ignored: the patches had no materials, and
    // bpm-mesh named the regions region_1, region_2.
    const std::string head =
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
        "$PhysicalNames\n3\n2 31 \"skin\"\n2 33 \"pair_a_b\"\n3 5 \"bone\"\n$EndPhysicalNames\n"
        "$Entities\n0 0 3 2\n"
        "1 0 0 0 1 1 1 1 31 0\n"
        "2 0 0 0 1 1 1 1 32 0\n"
        "3 0 0 0 1 1 1 1 33 0\n";
    const std::string mesh =
        "$EndEntities\n"
        "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n"
        "$Elements\n3 4 1 4\n2 1 2 2\n1 1 3 2\n2 1 2 4\n2 2 2 1\n3 1 4 3\n2 3 2 1\n4 2 3 4\n$EndElements\n";
    SurfaceReadReport report;
    const Surface s = read_bytes(head + "1 0 0 0 1 1 1 1 5 3 1 -2 3\n2 0 0 0 1 1 1 1 6 1 2\n" + mesh,
                                 SurfaceFormat::Msh, {}, &report);
    CHECK(s.patches == std::vector<int32_t>{31, 31, 32, 33});
    CHECK(report.patch_info == std::vector<PatchInfo>{{31, "skin", "bone", "exterior", false},
                                                      {32, "", "bone", "volume_6", false},
                                                      {33, "pair_a_b", "a", "b", false}});  // the name wins
    for (const std::string& note : report.notes) CHECK(note.find("physical volumes") == std::string::npos);

    SECTION("a physical surface whose parts bound different volumes gets none, and a note says which") {
        // Surface 3 joins physical 31 and bounds volume 2 only.
        std::string split = head;
        split.replace(split.find("3 0 0 0 1 1 1 1 33 0"), 20, "3 0 0 0 1 1 1 1 31 0");
        SurfaceReadReport r;
        (void)read_bytes(split + "1 0 0 0 1 1 1 1 5 2 1 -2\n2 0 0 0 1 1 1 1 6 2 2 3\n" + mesh, SurfaceFormat::Msh,
                         {}, &r);
        CHECK(r.patch_info == std::vector<PatchInfo>{{31, "skin", "", "", true},
                                                     {32, "", "bone", "volume_6", false},
                                                     {33, "pair_a_b", "a", "b", false}});  // named, unused
        REQUIRE(r.notes.size() == 1);
        CHECK(r.notes[0].find("physical surfaces 31: no materials from the physical volumes") == 0);
    }
    SECTION("volumes that list no bounding surfaces: a note says the physical volumes were ignored") {
        SurfaceReadReport r;
        (void)read_bytes(head + "1 0 0 0 1 1 1 1 5 0\n2 0 0 0 1 1 1 1 6 0\n" + mesh, SurfaceFormat::Msh, {}, &r);
        CHECK(r.patch_info == std::vector<PatchInfo>{{31, "skin", "", "", true}, {33, "pair_a_b", "a", "b", false}});
        REQUIRE(r.notes.size() == 1);
        CHECK(r.notes[0].find("physical volumes 'bone' ignored: no physical surface lies between the same") == 0);
    }
}

TEST_CASE("MSH 2.2: physical volumes are reported as ignored (the format does not say what bounds them)",
          "[surface_io]") {
    const std::string text =
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
        "$PhysicalNames\n2\n2 10 \"skin\"\n3 7 \"bone\"\n$EndPhysicalNames\n"
        "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
        "$Elements\n4\n1 2 2 10 1 1 3 2\n2 2 2 10 1 1 2 4\n3 2 2 10 1 1 4 3\n4 2 2 10 1 2 3 4\n$EndElements\n";
    SurfaceReadReport report;
    (void)read_bytes(text, SurfaceFormat::Msh, {}, &report);
    CHECK(report.patch_info == std::vector<PatchInfo>{{10, "skin", "", "", true}});
    REQUIRE(report.notes.size() == 1);
    CHECK(report.notes[0] == "physical volumes 'bone' ignored: MSH 2.2 does not say which surfaces bound a volume "
                             "(write MSH 4.1, gmsh -format msh41, or name the physical surfaces 'A|B' after the "
                             "materials on their two sides)");
}

TEST_CASE("MSH 4.1 binary: entities, nodes and elements", "[surface_io]") {
    const Surface t = awkward_tetrahedron();
    auto q = [](std::string& o, uint64_t v) { put<uint64_t>(o, v); };
    auto i = [](std::string& o, int32_t v) { put<int32_t>(o, v); };
    std::string out = "$MeshFormat\n4.1 1 8\n";
    i(out, 1);
    out += "\n$EndMeshFormat\n$Entities\n";
    q(out, 0), q(out, 0), q(out, 3), q(out, 0);
    const int32_t physical[3] = {7, 2, 0};  // entity 3 has no physical tag: patch 0
    for (int e = 1; e <= 3; ++e) {
        i(out, e);
        for (int k = 0; k < 6; ++k) put<double>(out, 0.0);
        if (e < 3) {
            q(out, 1), i(out, physical[e - 1]);
        } else {
            q(out, 0);
        }
        q(out, 0);
    }
    out += "\n$EndEntities\n$Nodes\n";
    q(out, 1), q(out, 4), q(out, 5), q(out, 8);
    i(out, 2), i(out, 1), i(out, 0), q(out, 4);
    for (uint64_t tag : {8, 5, 6, 7}) q(out, tag);
    for (const Vec3& p : t.vertices) {
        for (double x : p) put<double>(out, x);
    }
    out += "\n$EndNodes\n$Elements\n";
    q(out, 5), q(out, 5), q(out, 1), q(out, 9);
    const uint64_t tag_of[4] = {8, 5, 6, 7};
    const int entity_of_patch[8] = {3, 0, 2, 0, 0, 0, 0, 1};
    for (size_t f = 0; f < 4; ++f) {
        i(out, 2), i(out, entity_of_patch[t.patches[f]]), i(out, 2), q(out, 1);
        q(out, f + 1);
        for (int32_t v : t.triangles[f]) q(out, tag_of[v]);
    }
    i(out, 1), i(out, 1), i(out, 1), q(out, 1);  // a 2-node line: skipped
    q(out, 9), q(out, 8), q(out, 5);
    out += "\n$EndElements\n";
    SurfaceReadReport report;
    check_same(read_bytes(out, SurfaceFormat::Msh, {}, &report), t);
    CHECK(report.skipped_elements == 1);
}

TEST_CASE("CRLF line ends and a UTF-8 byte order mark are accepted", "[surface_io]") {
    auto crlf = [](std::string text) {
        std::string out;
        for (char c : text) {
            if (c == '\n') out += '\r';
            out += c;
        }
        return out;
    };
    const Surface t = tetrahedron();
    const std::string off = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    CHECK(read_bytes(crlf(off), SurfaceFormat::Off).triangles == t.triangles);
    CHECK(read_bytes("\xEF\xBB\xBF" + off, SurfaceFormat::Off).triangles == t.triangles);
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    CHECK(read_bytes(crlf(obj), SurfaceFormat::Obj).triangles == t.triangles);
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                            "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"
                            "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    CHECK(read_bytes(crlf(ply), SurfaceFormat::Ply).triangles == t.triangles);
    const std::string msh = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
                            "$EndNodes\n$Elements\n4\n1 2 0 1 3 2\n2 2 0 1 2 4\n3 2 0 1 4 3\n4 2 0 2 3 4\n$EndElements\n";
    CHECK(read_bytes(crlf(msh), SurfaceFormat::Msh).triangles == t.triangles);
    // A binary PLY whose header lines end in CRLF.
    std::string binary = crlf("ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty double x\n"
                              "property double y\nproperty double z\nelement face 4\n"
                              "property list uchar int vertex_indices\nend_header\n");
    for (const Vec3& p : t.vertices) {
        for (double x : p) put<double>(binary, x);
    }
    for (const Tri& f : t.triangles) {
        put<uint8_t>(binary, 3);
        for (int32_t v : f) put<int32_t>(binary, v);
    }
    CHECK(read_bytes(binary, SurfaceFormat::Ply).triangles == t.triangles);
}

TEST_CASE("standard input needs an explicit format", "[surface_io]") {
    CHECK_THROWS_WITH(read_surface("-"), Catch::Contains("standard input"));
    CHECK_THROWS_AS(write_surface("-", tetrahedron()), OutputError);
}

// ============================================================================ round trips

TEST_CASE("write then read gives back the same surface bit for bit", "[surface_io]") {
    const test_support::ScratchDir scratch("surface_io_test");
    const fs::path& dir = scratch.path;
    const Surface t = awkward_tetrahedron();
    for (const char* ext : {"off", "obj", "ply", "msh"}) {
        INFO(ext);
        const fs::path path = dir / (std::string("round.") + ext);
        write_surface(path.string(), t);
        Surface back = read_surface(path.string());
        if (std::string(ext) == "off") {
            CHECK(back.patches == std::vector<int32_t>(4, 0));  // OFF has no patches
            back.patches = t.patches;
        }
        check_same(back, t);
        // Deterministic: writing again gives the same bytes.
        const std::string first = file_bytes(path);
        write_surface(path.string(), back);
        CHECK(file_bytes(path) == first);
    }
}

TEST_CASE("STL round trip is exact for float coordinates", "[surface_io]") {
    const test_support::ScratchDir scratch("surface_io_test");
    const fs::path& dir = scratch.path;
    Surface t = tetrahedron();
    t.vertices[1] = {0.25f, -3.5f, 1e-3f};  // representable as float
    t.patches.assign(4, 0);                 // STL has no patches
    // STL numbers vertices in order of first use, so use them in index order.
    t.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    const fs::path path = dir / "round.stl";
    write_surface(path.string(), t);
    CHECK(file_bytes(path).size() == 84 + 50 * 4);
    CHECK(file_bytes(path).rfind("solid", 0) != 0);  // the header must not look like ASCII STL
    check_same(read_surface(path.string()), t);
}

TEST_CASE("writer refuses inconsistent surfaces and unknown formats", "[surface_io]") {
    const test_support::ScratchDir scratch("surface_io_test");
    const fs::path& dir = scratch.path;
    Surface t = tetrahedron();
    t.patches.pop_back();
    CHECK_THROWS_AS(write_surface((dir / "x.off").string(), t), OutputError);
    CHECK_THROWS_AS(write_surface((dir / "x.vtk").string(), tetrahedron()), OutputError);
    CHECK_THROWS_AS(write_surface((dir / "missing" / "x.off").string(), tetrahedron()), OutputError);
    CHECK_FALSE(fs::exists(dir / "x.off"));
    Surface huge = tetrahedron();
    huge.vertices[3][2] = 1e300;
    CHECK_THROWS_AS(write_surface((dir / "x.stl").string(), huge), OutputError);
    huge.vertices[3][2] = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_AS(write_surface((dir / "x.obj").string(), huge), OutputError);
}

// ============================================================================ malformed input, by kind

TEST_CASE("reject: empty file", "[surface_io]") {
    for (SurfaceFormat f : {SurfaceFormat::Off, SurfaceFormat::Obj, SurfaceFormat::Stl, SurfaceFormat::Ply,
                            SurfaceFormat::Msh, SurfaceFormat::Vtk}) {
        CHECK_READ_ERROR("", f, "empty");
    }
}

TEST_CASE("reject: directory, missing file, unknown extension", "[surface_io]") {
    const test_support::ScratchDir scratch("surface_io_test");
    const fs::path& dir = scratch.path;
    fs::create_directories(dir / "looks_like.off");
    try {
        (void)read_surface((dir / "looks_like.off").string());
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK(e.where() == (dir / "looks_like.off").string());
        CHECK(std::string(e.what()).find("directory") != std::string::npos);
    }
    CHECK_THROWS_AS(read_surface((dir / "missing.off").string()), InputError);
    std::ofstream(dir / "mesh.txt") << "OFF\n";
    CHECK_THROWS_WITH(read_surface((dir / "mesh.txt").string()), Catch::Contains("format"));
}

TEST_CASE("reject: truncated files", "[surface_io]") {
    CHECK_READ_ERROR("OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1", SurfaceFormat::Off, "line 2: 4 vertices and 4 faces announced, but the rest of the file is only");
    CHECK_READ_ERROR("OFF\n4 4 0\n# padding so that the size check passes\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2", SurfaceFormat::Off, "line 11: expected a vertex index of face 3, found the end of the file");
    CHECK_READ_ERROR("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2", SurfaceFormat::Obj, "line 4");
    CHECK_READ_ERROR(binary_stl(tetrahedron(), "x").substr(0, 200), SurfaceFormat::Stl, "byte offset 80");
    CHECK_READ_ERROR("solid x\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\n", SurfaceFormat::Stl, "line 5");
    CHECK_READ_ERROR(msh22_binary(tetrahedron(), false, {1, 2, 3, 4}).substr(0, 150), SurfaceFormat::Msh,
                     "byte offset 46: 4 nodes announced, but the 101 bytes left in the file cannot hold that many");
    CHECK_READ_ERROR(msh22_binary(tetrahedron(), false, {1, 2, 3, 4}).substr(0, 60), SurfaceFormat::Msh,
                     "byte offset 46: 4 nodes announced, but the 11 bytes left");
}

TEST_CASE("reject: billions of elements claimed, before allocating", "[surface_io]") {
    CHECK_READ_ERROR("OFF\n4000000000 1 0\n", SurfaceFormat::Off, "bpm supports at most");
    CHECK_READ_ERROR("OFF\n2000000000 0 0\n0 0 0\n", SurfaceFormat::Off, "cannot hold that many");
    std::string stl(80, ' ');
    put<uint32_t>(stl, 0xFFFFFFFFu);
    CHECK_READ_ERROR(stl, SurfaceFormat::Stl, "4294967295 triangles");
    CHECK_READ_ERROR("ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\nproperty double x\n"
                     "property double y\nproperty double z\nend_header\n",
                     SurfaceFormat::Ply, "cannot hold that many");
    std::string ply = "ply\nformat binary_big_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n";
    put<uint32_t>(ply, 4000000000u, true);
    CHECK_READ_ERROR(ply, SurfaceFormat::Ply, "list 'vertex_indices' of 4000000000 entries runs past the end");
    CHECK_READ_ERROR("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 3000000000 1 3000000000\n",
                     SurfaceFormat::Msh, "bpm supports at most");
    std::string msh = "$MeshFormat\n4.1 1 8\n";
    put<int32_t>(msh, 1);
    msh += "\n$EndMeshFormat\n$Nodes\n";
    for (uint64_t v : {1ull, 1ull << 40, 1ull, 1ull << 40}) put<uint64_t>(msh, v);
    CHECK_READ_ERROR(msh, SurfaceFormat::Msh, "bpm supports at most");
}

TEST_CASE("reject: NaN and infinite coordinates", "[surface_io]") {
    CHECK_READ_ERROR("OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", SurfaceFormat::Off, "line 4: coordinate of vertex 1 'nan' is not a finite number");
    CHECK_READ_ERROR("v 0 0 0\nv 1 0 0\nv 0 -inf 0\nf 1 2 3\n", SurfaceFormat::Obj, "line 3");
    CHECK_READ_ERROR("v 0 0 0\nv 1 0 0\nv 0 1e400 0\nf 1 2 3\n", SurfaceFormat::Obj, "not a finite number");
    Surface t = tetrahedron();
    t.vertices[2][1] = std::numeric_limits<double>::quiet_NaN();
    CHECK_READ_ERROR(binary_stl(t, "x"), SurfaceFormat::Stl, "coordinate is NaN");
    CHECK_READ_ERROR(msh22_binary(t, false, {1, 2, 3, 4}), SurfaceFormat::Msh, "is NaN");
    CHECK_READ_ERROR("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                     "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 Infinity\n0 1 0\n3 0 1 2\n",
                     SurfaceFormat::Ply, "line 11");
    // A tiny number that underflows is not an error.
    CHECK(read_bytes("OFF\n3 1 0\n0 0 0\n1 1e-400 0\n0 1 0\n3 0 1 2\n", SurfaceFormat::Off).vertices[1][1] == 0.0);
}

TEST_CASE("reject: negative and out-of-range indices", "[surface_io]") {
    const std::string off_head = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
    CHECK_READ_ERROR(off_head + "3 0 -1 2\n", SurfaceFormat::Off, "line 6: face 0: vertex index -1 is out of range");
    CHECK_READ_ERROR(off_head + "3 0 1 3\n", SurfaceFormat::Off, "vertex index 3 is out of range");
    CHECK_READ_ERROR("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", SurfaceFormat::Obj, "line 4");
    CHECK_READ_ERROR("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", SurfaceFormat::Obj, "before the first vertex");
    CHECK_READ_ERROR("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n"
                     "$Elements\n1\n1 2 0 1 2 -3\n$EndElements\n",
                     SurfaceFormat::Msh, "node tag -3 is not in $Nodes");
}

TEST_CASE("reject: garbage tokens, with the line", "[surface_io]") {
    CHECK_READ_ERROR("OFF\n3 1 0\n0 0 0\n1 0x 0\n0 1 0\n3 0 1 2\n", SurfaceFormat::Off, "line 4: expected coordinate of vertex 1 (a number), found '0x'");
    CHECK_READ_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2.0\n", SurfaceFormat::Off, "line 6");
    CHECK_READ_ERROR("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n\x01\x02\n", SurfaceFormat::Obj, "\\x01");
}

TEST_CASE("reject: polygons with more than three corners", "[surface_io]") {
    CHECK_READ_ERROR("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n", SurfaceFormat::Off, "only triangles");
    CHECK_READ_ERROR("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", SurfaceFormat::Obj, "line 5: face 0 has 4 corners");
    CHECK_READ_ERROR("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                     "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n",
                     SurfaceFormat::Ply, "face 0 has 4 corners");
}

// Sum of the triangles' vector areas: for a triangulation of a planar polygon with the
// polygon's orientation this is the polygon's vector area (no triangle flipped).
Vec3 vector_area(const Surface& s) {
    Vec3 sum{0, 0, 0};
    for (const Tri& t : s.triangles)
        sum = sum + 0.5 * cross(s.vertices[t[1]] - s.vertices[t[0]], s.vertices[t[2]] - s.vertices[t[0]]);
    return sum;
}

TEST_CASE("triangulate-polygons repair: polygons become triangles in place, orientation and patches kept",
          "[surface_io]") {
    SurfaceReadOptions repair;
    repair.triangulate_polygons = true;
    SECTION("OFF: a unit square and a triangle; the polygon's triangles stay where the face was") {
        SurfaceReadReport report;
        const Surface s = read_bytes("OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 1\n4 0 1 2 3\n3 0 4 1\n",
                                     SurfaceFormat::Off, repair, &report);
        REQUIRE(s.num_triangles() == 3);
        CHECK(s.triangles[2] == Tri{0, 4, 1});
        const Vec3 a = vector_area(Surface{s.vertices, {s.triangles[0], s.triangles[1]}, {0, 0}});
        CHECK(a[0] == 0.0);
        CHECK(a[1] == 0.0);
        CHECK(a[2] == Approx(1.0));  // counter-clockwise seen from +z, as the face
        REQUIRE(report.notes.size() == 1);
        CHECK(report.notes[0] == "triangulated 1 polygon face (up to 4 corners)");
    }
    SECTION("a non-convex hexagon (an L) in a tilted plane: no flipped or overlapping triangle") {
        // The L in the plane z = x + y, listed clockwise seen from +z (normal points down).
        const double L[6][2] = {{0, 0}, {0, 2}, {1, 2}, {1, 1}, {2, 1}, {2, 0}};
        std::string off = "OFF\n6 1 0\n";
        for (auto& p : L) off += std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[0] + p[1]) + "\n";
        off += "6 0 1 2 3 4 5\n";
        const Surface s = read_bytes(off, SurfaceFormat::Off, repair);
        REQUIRE(s.num_triangles() == 4);
        // Area of the L is 3; its normal direction is (1, 1, -1) / sqrt(3) flipped (clockwise from +z).
        const Vec3 a = vector_area(s);
        CHECK(norm(a) == Approx(3.0 * std::sqrt(3.0)));
        CHECK(a[2] == Approx(-3.0));
        for (const Tri& t : s.triangles) {
            const Vec3 n = cross(s.vertices[t[1]] - s.vertices[t[0]], s.vertices[t[2]] - s.vertices[t[0]]);
            CHECK(dot(n, a) > 0);  // every triangle oriented as the polygon
        }
    }
    SECTION("OBJ: quads in two groups keep their groups' patches") {
        const Surface s = read_bytes("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\n"
                                     "g a\nf 1 2 3 4\ng b\nf 1 5 6 2\n",
                                     SurfaceFormat::Obj, repair);
        REQUIRE(s.num_triangles() == 4);
        CHECK(s.patches == std::vector<int32_t>{0, 0, 1, 1});
    }
    SECTION("PLY: a pentagon with its patch property, between two triangles") {
        const Surface s = read_bytes(
            "ply\nformat ascii 1.0\nelement vertex 6\nproperty double x\nproperty double y\nproperty double z\n"
            "element face 3\nproperty list uchar int vertex_indices\nproperty int patch\nend_header\n"
            "0 0 0\n2 0 0\n3 1 0\n1 2 0\n-1 1 0\n1 1 1\n3 0 1 5 4\n5 0 1 2 3 4 7\n3 1 2 5 9\n",
            SurfaceFormat::Ply, repair);
        REQUIRE(s.num_triangles() == 5);
        CHECK(s.patches == std::vector<int32_t>{4, 7, 7, 7, 9});
        CHECK(s.triangles[0] == Tri{0, 1, 5});
        CHECK(s.triangles[4] == Tri{1, 2, 5});
    }
    SECTION("refused: a self-crossing quad (a bow tie), with the face and its line") {
        // Lobes of different size, so that the polygon still has a net area.
        const std::string bow = "OFF\n4 1 0\n0 0 0\n3 2 0\n3 0 0\n0 1 0\n4 0 1 2 3\n";
        const std::string message = read_error(bow, SurfaceFormat::Off, repair);
        CHECK_THAT(message, Catch::Contains("line 7: face 0 (4 corners) cannot be triangulated: the polygon is not simple"));
    }
    SECTION("refused: a corner twice, collinear corners, and a count larger than the file") {
        CHECK_THAT(read_error("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 1\n", SurfaceFormat::Off, repair),
                   Catch::Contains("vertex 1 is a corner of the polygon twice"));
        CHECK_THAT(read_error("OFF\n4 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 0\n4 0 1 2 3\n", SurfaceFormat::Off, repair),
                   Catch::Contains("no area"));
        CHECK_THAT(read_error("OFF\n4 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 0\n2000000000 0 1 2 3\n", SurfaceFormat::Off,
                              repair),
                   Catch::Contains("more than the rest of the file holds"));
    }
    SECTION("without the repair the message names it") {
        CHECK_THAT(read_error("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n", SurfaceFormat::Off),
                   Catch::Contains("line 7: face 0 has 4 corners; only triangles are accepted; the repair it needs: "
                                   "triangulate polygons"));
    }
    SECTION("without the repair, every repair the input needs is named at once") {
        // Two quads (a square split in two along x = 1) whose shared corners are given
        // twice: the duplicates only show once the polygons are read.
        const std::string twice = "OFF\n8 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n1 0 0\n2 0 0\n2 1 0\n1 1 0\n"
                                  "4 0 1 2 3\n4 4 5 6 7\n";
        try {
            read_surface_from_memory(twice, SurfaceFormat::Off, "twice.off");
            FAIL("read without the repairs");
        } catch (const InputNeedsRepair& e) {
            CHECK_THAT(e.what(), Catch::Contains("line 11: face 0 has 4 corners (and 1 more polygon faces)"));
            CHECK_THAT(e.what(), Catch::Contains("the repairs it needs, all together: triangulate polygons, merge "
                                                 "duplicate vertices"));
            CHECK(e.repairs() ==
                  std::vector<SurfaceRepair>{SurfaceRepair::TriangulatePolygons, SurfaceRepair::MergeDuplicateVertices});
        }
        SurfaceReadOptions both;
        both.triangulate_polygons = true;
        both.merge_duplicate_vertices = true;
        const Surface s = read_surface_from_memory(twice, SurfaceFormat::Off, "twice.off", both);
        CHECK(s.num_triangles() == 4);
        CHECK(s.num_vertices() == 6);
    }
}

TEST_CASE("reject: wrong counts in the header", "[surface_io]") {
    const std::string body = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    CHECK_READ_ERROR("OFF\n4 3 0\n" + body, SurfaceFormat::Off, "after the last of the 3 announced faces");
    CHECK_READ_ERROR("OFF\n3 4 0\n" + body, SurfaceFormat::Off, "line 6: face 0 has 0 corners");
    CHECK_READ_ERROR("OFF\n5 4 0\n" + body, SurfaceFormat::Off, "truncated, or wrong counts?");
    CHECK_READ_ERROR("OFF\n5 4 0\n" + body + "#####################################\n", SurfaceFormat::Off,
                     "ends after 3 of the 4 announced faces");
    std::string stl = binary_stl(tetrahedron(), "x");
    stl[80] = 3;
    CHECK_READ_ERROR(stl, SurfaceFormat::Stl, "announces 3 triangles");
}

TEST_CASE("reject: zero-area and duplicate triangles, named by index", "[surface_io]") {
    const std::string head = "OFF\n5 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.5 0.5 0\n";
    const std::string faces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    CHECK_READ_ERROR(head + faces + "3 1 4 2\n", SurfaceFormat::Off, "triangle 4 (vertices 1, 4, 2): zero area");
    CHECK_READ_ERROR(head + faces + "3 2 1 3\n", SurfaceFormat::Off, "same three vertices as triangle 3");
    CHECK_READ_ERROR(head + faces + "3 2 1 2\n", SurfaceFormat::Off, "triangle 4 (vertices 2, 1, 2): corners 0 and 2 are the same vertex");
}

TEST_CASE("unreferenced vertices: an error unless the repair is requested", "[surface_io]") {
    const std::string text = "OFF\n5 4 0\n0 0 0\n9 9 9\n1 0 0\n0 1 0\n0 0 1\n3 0 3 2\n3 0 2 4\n3 0 4 3\n3 2 3 4\n";
    CHECK_READ_ERROR(text, SurfaceFormat::Off, "vertex 1: not used by any triangle");
    // The repair is named once, at the end (it was also repeated after the problem).
    const std::string message = read_error(text, SurfaceFormat::Off);
    INFO(message);
    CHECK(message.find("drop unreferenced vertices") == message.rfind("drop unreferenced vertices"));
    CHECK(message.find("the repair it needs: drop unreferenced vertices") != std::string::npos);
    SurfaceReadOptions options;
    options.drop_unreferenced_vertices = true;
    SurfaceReadReport report;
    const Surface s = read_bytes(text, SurfaceFormat::Off, options, &report);
    CHECK(report.dropped_vertices == 1);
    CHECK(s.vertices == tetrahedron().vertices);
    CHECK(s.triangles == tetrahedron().triangles);
}

TEST_CASE("duplicate vertices: merged only when requested", "[surface_io]") {
    // Vertex 4 sits where vertex 1 is; triangle 3 uses it.
    const std::string text = "OFF\n5 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 4 2 3\n";
    CHECK_READ_ERROR(text, SurfaceFormat::Off, "vertex 4: same position (1, 0, 0) as vertex 1");
    SurfaceReadOptions options;
    options.merge_duplicate_vertices = true;
    SurfaceReadReport report;
    const Surface s = read_bytes(text, SurfaceFormat::Off, options, &report);
    CHECK(report.merged_vertices == 1);
    CHECK(s.vertices == tetrahedron().vertices);
    CHECK(s.triangles == tetrahedron().triangles);
}

TEST_CASE("reject: binary garbage in every format", "[surface_io]") {
    uint32_t state = 12345;
    for (int round = 0; round < 50; ++round) {
        std::string bytes(static_cast<size_t>(round * 37 % 700), '\0');
        for (char& c : bytes) {
            state = state * 1664525u + 1013904223u;
            c = static_cast<char>(state >> 24);
        }
        for (SurfaceFormat f : {SurfaceFormat::Off, SurfaceFormat::Obj, SurfaceFormat::Stl, SurfaceFormat::Ply,
                                SurfaceFormat::Msh, SurfaceFormat::Vtk}) {
            CHECK_THROWS_AS(read_bytes(bytes, f), InputError);
        }
    }
}

TEST_CASE("reject: wrong endianness claims", "[surface_io]") {
    // PLY: big-endian data declared little-endian makes absurd indices.
    const Surface t = tetrahedron();
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
                      "property double z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
    for (const Vec3& p : t.vertices) {
        for (double x : p) put<double>(ply, x, true);
    }
    for (const Tri& f : t.triangles) {
        put<uint8_t>(ply, 3);
        for (int32_t v : f) put<int32_t>(ply, v, true);
    }
    CHECK_READ_ERROR(ply, SurfaceFormat::Ply, "is out of range");
    // MSH: the one-integer marker that is neither 1 nor a byte-swapped 1.
    std::string msh = msh22_binary(t, false, {1, 2, 3, 4});
    msh[20] = 7;
    CHECK_READ_ERROR(msh, SurfaceFormat::Msh, "endianness marker is 7");
}

TEST_CASE("a file of another format gets a hint", "[surface_io]") {
    CHECK_READ_ERROR("ply\nformat ascii 1.0\nend_header\n", SurfaceFormat::Off, "looks like PLY");
}

// ============================================================================ the corpus

TEST_CASE("every file of the malformed corpus is refused with a clear InputError", "[surface_io]") {
    const fs::path dir = fs::path(BPM_SOURCE_DIR) / "tests" / "data" / "bad";
    REQUIRE(fs::is_directory(dir));
    std::map<std::string, std::string> expected;
    {
        std::ifstream in(dir / "EXPECTED.tsv");
        std::string line;
        while (std::getline(in, line)) {
            if (line.empty() || line[0] == '#') continue;
            const size_t tab = line.find('\t');
            expected[line.substr(0, tab)] = line.substr(tab + 1);
        }
    }
    int files = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        if (!surface_format_from_path(name)) continue;
        ++files;
        INFO(name);
        std::string message;
        try {
            (void)read_surface(entry.path().string());
        } catch (const InputError& e) {
            message = e.what();
            CHECK(e.where() == entry.path().string());
        }
        INFO("message: " << message);
        CHECK(!message.empty());
        REQUIRE(expected.count(name) == 1);
        if (expected[name] != "*") CHECK(message.find(expected[name]) != std::string::npos);
    }
    CHECK(files >= 40);
    CHECK(files == static_cast<int>(expected.size()));
}

// ============================================================================ real meshes

namespace {
// Counts from the header of an OFF or PLY file (the readers must agree with them).
std::pair<int64_t, int64_t> header_counts(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::string word;
    if (path.extension() == ".off") {
        int64_t v = 0, f = 0;
        in >> word >> v >> f;
        return {v, f};
    }
    int64_t v = -1, f = 0;
    std::string line;
    while (std::getline(in, line) && line.rfind("end_header", 0) != 0) {
        std::istringstream ls(line);
        std::string a, b;
        int64_t n = 0;
        ls >> a >> b >> n;
        if (a == "element" && b == "vertex") v = n;
        if (a == "element" && b == "face") f = n;
    }
    return {v, f};
}
}  // namespace

TEST_CASE("real meshes read with the counts of their headers", "[surface_io][real]") {
    const fs::path dir = BPM_MESH_DIR;
    if (!have_mesh_dir(dir)) return;
    for (const char* name : {"femur.off", "fandisk.off", "elephant.off", "armadillo.off", "mech-holes-shark.off",
                             "sphere.ply"}) {
        const fs::path path = dir / name;
        if (!fs::exists(path)) {
            WARN(name << " missing; skipped");
            continue;
        }
        INFO(name);
        const auto [nv, nf] = header_counts(path);
        const Surface s = read_surface(path.string());
        CHECK(s.num_vertices() == nv);
        CHECK(s.num_triangles() == nf);
        CHECK(s.patches.size() == s.triangles.size());
    }
}

TEST_CASE("real meshes with problems are refused with a clear message", "[surface_io][real]") {
    const fs::path dir = BPM_MESH_DIR;
    if (!have_mesh_dir(dir)) return;
    // b9.ply is a point cloud: 22300 vertices, no faces.
    if (fs::exists(dir / "b9.ply")) {
        CHECK_THROWS_WITH(read_surface((dir / "b9.ply").string()), Catch::Contains("no triangles") && Catch::Contains("22300 vertices"));
        SurfaceReadOptions options;
        options.drop_unreferenced_vertices = true;
        CHECK_THROWS_WITH(read_surface((dir / "b9.ply").string(), options), Catch::Contains("point cloud"));
    }
    // colored_tetra.ply: normals, colours, an edge element, a `label` face property.
    if (fs::exists(dir / "colored_tetra.ply")) {
        const Surface s = read_surface((dir / "colored_tetra.ply").string());
        CHECK(s.num_vertices() == 4);
        CHECK(s.num_triangles() == 4);
        CHECK(s.patches[0] == -1);
    }
}

TEST_CASE("real meshes with duplicate or unused vertices, flat triangles or polygons", "[surface_io][real]") {
    const fs::path dir = BPM_MESH_DIR;
    if (!have_mesh_dir(dir)) return;
    struct Case {
        const char* name;
        const char* error;       // part of the message without repairs
        bool merge, drop;        // repairs that make it readable (neither: never readable)
        int64_t repaired;        // vertices merged or dropped
    };
    const Case cases[] = {
        {"cow.off", "vertex 2903: same position", true, false, 1},
        {"boeing.off", "vertex 8: same position", true, false, 1477},
        {"cube-ouvert.off", "vertex 8: not used by any triangle", false, true, 1},
        {"degtri_sliding.off", "triangle 2 (vertices 3, 2, 4): zero area", false, false, 0},
        {"3torus.off", "line 22: face 0 has 4 corners (and 22 more polygon faces); only triangles are accepted", false,
         false, 0},
    };
    for (const Case& c : cases) {
        const fs::path path = dir / c.name;
        if (!fs::exists(path)) continue;
        INFO(c.name);
        CHECK_THROWS_WITH(read_surface(path.string()), Catch::Contains(c.error));
        if (!c.merge && !c.drop) continue;
        SurfaceReadOptions options;
        options.merge_duplicate_vertices = c.merge;
        options.drop_unreferenced_vertices = c.drop;
        SurfaceReadReport report;
        const Surface s = read_surface(path.string(), options, &report);
        CHECK((c.merge ? report.merged_vertices : report.dropped_vertices) == c.repaired);
        CHECK(s.num_triangles() > 0);
    }
}

TEST_CASE("real meshes with polygon faces read with the triangulate-polygons repair", "[surface_io][real]") {
    const fs::path dir = BPM_MESH_DIR;
    if (!have_mesh_dir(dir)) return;
    int files = 0;
    for (const char* name : {"3torus.off", "cube_quad.off", "torus_quad.off", "double-torus-example.off", "P.off"}) {
        const fs::path path = dir / name;
        if (!fs::exists(path)) continue;
        ++files;
        INFO(name);
        // Expected triangles: sum over faces of (corners - 2), from the file itself.
        std::ifstream in(path);
        std::string keyword;
        int64_t nv = 0, nf = 0, ne = 0;
        in >> keyword >> nv >> nf >> ne;
        std::string line;
        for (int64_t i = 0; i < nv; ++i) std::getline(in >> std::ws, line);
        int64_t expected = 0;
        for (int64_t f = 0; f < nf; ++f) {
            std::getline(in >> std::ws, line);
            expected += std::stoll(line) - 2;
        }
        SurfaceReadOptions repair;
        repair.triangulate_polygons = true;
        SurfaceReadReport report;
        const Surface s = read_surface(path.string(), repair, &report);
        CHECK(s.num_triangles() == expected);
        CHECK(s.num_vertices() == nv);
    }
    if (files == 0) WARN("none of the polygon meshes in " << dir.string());
}

TEST_CASE("real STL meshes read, the vertex count comes from merging corners", "[surface_io][real]") {
    const fs::path dir = BPM_MESH_DIR;
    if (!have_mesh_dir(dir)) return;
    int files = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (entry.path().extension() != ".stl" && entry.path().extension() != ".obj") continue;
        ++files;
        INFO(entry.path().filename().string());
        const Surface s = read_surface(entry.path().string());
        CHECK(s.num_triangles() > 0);
        CHECK(s.num_vertices() < 3 * s.num_triangles());  // corners were shared
        const std::string bytes = file_bytes(entry.path());
        if (entry.path().extension() == ".stl" && bytes.size() >= 84) {
            uint32_t n;
            std::memcpy(&n, bytes.data() + 80, 4);
            if (bytes.size() == 84 + 50 * size_t(n)) CHECK(s.num_triangles() == int64_t(n));  // binary
        }
    }
    if (files == 0) WARN("no .stl or .obj meshes in " << dir.string());
}
