// The Amira HyperSurface reader (libbpm/src/io/read_surf.cpp) through read_surface_from_memory
// and read_surface: two materials (two tetrahedra sharing a face: patches Exterior|A,
// Exterior|B, A|B) written ASCII and BINARY give the same surface, patches and notes;
// Parameters with nested braces and quoted strings, the sections that are parsed and not
// used, unknown keys; the format from the head of a file without the extension; errors
// with their line (ASCII) or byte offset (BINARY).
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
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

namespace fs = std::filesystem;
using namespace bpm;

namespace {

using test_bytes::put;
using test_bytes::text;

// Writes a HyperSurface file: keyword lines as text, the values after a count line as
// text lines or, in BINARY files, as big-endian (or little-endian) 4-byte values followed
// by a line end, as Amira does.
struct SurfWriter {
    bool binary = false;
    bool big_endian = true;
    std::string out;

    explicit SurfWriter(bool binary_, bool little_endian = false) : binary(binary_), big_endian(!little_endian) {
        out = std::string("# HyperSurface 0.1 ") +
              (!binary         ? "ASCII"
               : little_endian ? "BINARY-LITTLE-ENDIAN"
                               : "BINARY") +
              "\n\n";
    }
    void line(const std::string& s) { out += s + "\n"; }
    // "KEY n" and the values, `per` to a line; returns the offset of the first value (binary).
    size_t ints(const std::string& key, const std::vector<int32_t>& v, size_t per = 1) {
        line(key + " " + std::to_string(v.size() / per));
        const size_t at = out.size();
        for (size_t i = 0; i < v.size(); ++i) {
            if (binary)
                put<int32_t>(out, v[i], big_endian);
            else
                out += (i % per == 0 ? "\t" : " ") + std::to_string(v[i]) + (i % per == per - 1 ? "\n" : "");
        }
        if (binary) out += "\n";
        return at;
    }
    size_t vertices(const std::vector<Vec3>& v) {
        line("Vertices " + std::to_string(v.size()));
        const size_t at = out.size();
        for (const Vec3& p : v) {
            if (binary) {
                for (double x : p) put<float>(out, static_cast<float>(x), big_endian);
            } else {
                out += "\t" + text(p[0]) + " " + text(p[1]) + " " + text(p[2]) + "\n";
            }
        }
        if (binary) out += "\n";
        return at;
    }
    // One Patches entry; returns the offset of its first triangle value.
    size_t patch(const std::string& inner, const std::string& outer, const std::vector<int32_t>& triangles,
                 const std::string& extra = "") {
        line("{");
        line("InnerRegion " + inner);
        line("OuterRegion " + outer);
        line("BoundaryID 0");
        line("BranchingPoints 0");
        out += extra;
        line("");
        const size_t at = ints("Triangles", triangles, 3);
        line("}");
        return at;
    }
};

// Floats exactly, so that ASCII and BINARY give the same doubles.
const std::vector<Vec3> kVertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.25, 0.25, -1}};

// Tetrahedron A (vertices 1 2 3 4) above tetrahedron B (1 2 3 5), sharing the face 1 2 3;
// one-based as in the file. A fourth, empty patch for material C.
struct TwoMaterials {
    std::string bytes;
    size_t vertex_data = 0;    // offset of the first coordinate (binary)
    size_t triangle_data = 0;  // offset of the first index of patch 0 (binary)
};

TwoMaterials two_materials(bool binary, bool little_endian = false) {
    SurfWriter w(binary, little_endian);
    w.line("Parameters {");
    w.line("    Materials {");
    w.line("        Exterior {");
    w.line("            Id 0");
    w.line("        }");
    w.line("        A { Color 0.8 0.2 0.2, Id 1 }");
    w.line("        B {");
    w.line("            Color 0.2 0.2 0.8,");
    w.line("            Id 2");
    w.line("        }");
    w.line("    }");
    w.line("    BoundaryIds { Name \"BoundaryConditions\" }");
    w.line("    Note \"a } brace, a { brace and a # in a string\"  # and a comment with a }");
    w.line("    Units { Coordinates \"mm\" }");
    w.line("}");
    w.line("");
    TwoMaterials t;
    t.vertex_data = w.vertices(kVertices);
    w.line("NBranchingPoints 0");
    w.line("NVerticesOnCurves 0");
    w.line("BoundaryCurves 0");
    w.line("Patches 4");
    t.triangle_data = w.patch("A", "Exterior", {1, 2, 4, 2, 3, 4, 3, 1, 4});
    w.patch("B", "Exterior", {1, 5, 2, 2, 5, 3, 3, 5, 1});
    w.patch("A", "B", {1, 3, 2});
    w.patch("C", "Exterior", {});
    t.bytes = w.out;
    return t;
}

const std::vector<Tri> kTriangles = {{0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {0, 4, 1}, {1, 4, 2}, {2, 4, 0}, {0, 2, 1}};
const std::vector<int32_t> kPatches = {0, 0, 0, 1, 1, 1, 2};

bool has_note(const SurfaceReadReport& r, const std::string& text) {
    for (const std::string& n : r.notes)
        if (n.find(text) != std::string::npos) return true;
    return false;
}

std::string surf_error(const std::string& bytes) {
    try {
        (void)read_surface_from_memory(bytes, SurfaceFormat::Surf, "test.surf");
    } catch (const InputError& e) {
        CHECK(e.where() == "test.surf");
        return e.what();
    }
    return "";
}

using test_support::line_of;
std::string line(const std::string& bytes, const std::string& marker) {
    return "line " + std::to_string(line_of(bytes, marker)) + ": ";
}

std::string replaced(std::string bytes, const std::string& from, const std::string& to) {
    const size_t at = bytes.find(from);
    REQUIRE(at != std::string::npos);
    return bytes.replace(at, from.size(), to);
}

#define CHECK_SURF_ERROR(bytes, text)                   \
    do {                                                \
        const std::string message_ = surf_error(bytes); \
        INFO("message: " << message_);                  \
        CHECK(message_.find(text) == 0);                \
    } while (0)

#define CHECK_SURF_ERROR_CONTAINS(bytes, text)           \
    do {                                                 \
        const std::string message_ = surf_error(bytes);  \
        INFO("message: " << message_);                   \
        CHECK(message_.find(text) != std::string::npos); \
    } while (0)

}  // namespace

TEST_CASE("HyperSurface: format name and extension, writing refused, a hint for the wrong format",
          "[surface_io][surf]") {
    CHECK(surface_format_from_name("surf") == SurfaceFormat::Surf);
    CHECK(surface_format_from_name("SURF") == SurfaceFormat::Surf);
    CHECK(surface_format_from_path("segmentation/labels.surf") == SurfaceFormat::Surf);
    const std::string bytes = two_materials(false).bytes;
    const std::string message = [&] {
        try {
            (void)read_surface_from_memory(bytes, SurfaceFormat::Off, "x.off");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    }();
    CHECK(message.find("looks like HyperSurface, not OFF") != std::string::npos);

    const test_support::ScratchDir scratch("read_surf_test");
    const fs::path& dir = scratch.path;
    const Surface s = read_surface_from_memory(bytes, SurfaceFormat::Surf, "t.surf");
    CHECK_THROWS_WITH(write_surface((dir / "out.surf").string(), s),
                      Catch::Contains("cannot write Amira HyperSurface"));
    CHECK_THROWS_AS(write_surface((dir / "out.off").string(), s, SurfaceFormat::Surf), OutputError);
    CHECK_FALSE(fs::exists(dir / "out.surf"));
    CHECK_FALSE(fs::exists(dir / "out.off"));
}

TEST_CASE("HyperSurface: two materials, ASCII, BINARY and BINARY-LITTLE-ENDIAN, give the same surface and notes",
          "[surface_io][surf]") {
    for (const int encoding : {0, 1, 2}) {
        INFO((encoding == 0 ? "ASCII" : encoding == 1 ? "BINARY" : "BINARY-LITTLE-ENDIAN"));
        SurfaceReadReport report;
        const Surface s = read_surface_from_memory(two_materials(encoding > 0, encoding == 2).bytes,
                                                   SurfaceFormat::Surf, "t.surf", {}, &report);
        CHECK(report.format == SurfaceFormat::Surf);
        CHECK(s.vertices == kVertices);
        CHECK(s.triangles == kTriangles);
        CHECK(s.patches == kPatches);
        REQUIRE(report.notes.size() == 4);
        CHECK(report.notes[0] == "patch 0 = InnerRegion A / OuterRegion Exterior (3 triangles)");
        CHECK(report.notes[1] == "patch 1 = InnerRegion B / OuterRegion Exterior (3 triangles)");
        CHECK(report.notes[2] == "patch 2 = InnerRegion A / OuterRegion B (1 triangle)");
        CHECK(report.notes[3] == "patch 3 = InnerRegion C / OuterRegion Exterior (0 triangles)");
        CHECK(report.skipped_elements == 0);
    }
}

TEST_CASE("HyperSurface: branching points, boundary curves, surfaces, case, CRLF, unknown keys (ASCII)",
          "[surface_io][surf]") {
    for (const bool binary : {false, true}) {
        INFO((binary ? "BINARY" : "ASCII"));
        SurfWriter w(binary);
        w.line("# CreationDate: Thu Jan  1 00:00:00 2026");
        w.line("Parameters {");
        w.line("    Materials { Exterior { Id 0 } \"odd name\" { Id 3 } }");
        w.line("    Filename \"C:\\\\data\\\\{x}.surf\"");
        w.line("}");
        w.vertices(kVertices);
        // Counts only: the first vertices are branching points / on curves.
        w.line("NBranchingPoints 1");
        w.line("NVerticesOnCurves 2");
        w.line("BoundaryCurves 2");
        w.line("{");
        w.ints("Vertices", {1, 2, 3, 1});
        w.line("} {");
        w.ints("Vertices", {});
        w.line("}");
        w.line("Patches 3");
        w.patch("Bone marrow", "Exterior", {1, 2, 4, 2, 3, 4, 3, 1, 4});
        // Keys in other capitalization, branching points and curves with values.
        w.line("{");
        w.line("innerregion B");
        w.line("OUTERREGION Exterior");
        w.line("BoundaryId 7");
        w.ints("BranchingPoints", {1});
        w.ints("BoundaryCurves", {1, -2});
        w.ints("triangles", {1, 5, 2, 2, 5, 3, 3, 5, 1}, 3);
        w.line("}");
        w.line("{ InnerRegion A");  // a brace on the line of a key
        w.line("OuterRegion B");
        w.ints("Triangles", {1, 3, 2}, 3);
        w.line("}");
        w.line("Surfaces 3");
        w.line("{");
        w.line("Region A");
        w.ints("Patches", {1, 3});
        w.line("}");
        w.line("{");
        w.line("Region B");
        w.ints("Patches", {2, -3});
        w.line("}");
        w.line("{ Region C }");  // a brace on the line of a name
        SurfaceReadReport report;
        const Surface s = read_surface_from_memory(w.out, SurfaceFormat::Surf, "t.surf", {}, &report);
        CHECK(s.triangles == kTriangles);
        CHECK(s.patches == kPatches);
        CHECK(has_note(report, "patch 0 = InnerRegion Bone marrow / OuterRegion Exterior (3 triangles)"));
        CHECK(has_note(report, "patch 1 = InnerRegion B / OuterRegion Exterior, BoundaryID 7 (3 triangles)"));
        CHECK(has_note(report, "patch 2 = InnerRegion A / OuterRegion B (1 triangle)"));

        if (binary) continue;
        // CRLF line ends.
        std::string crlf;
        for (char c : w.out) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
        CHECK(read_surface_from_memory(crlf, SurfaceFormat::Surf, "t.surf").triangles == kTriangles);

        // Unknown keys: a block at the top level, a key with a line of values and one with
        // numbers on the following lines inside a patch, skipped with a note.
        std::string unknown = replaced(w.out, "Patches 3\n", "Extra { a { \"}\" } }\nPatches 3\n");
        unknown = replaced(unknown, "InnerRegion Bone marrow\n",
                           "InnerRegion Bone marrow\nColour 1 0 0\nWeights 2\n 0.5\n -0.25\n");
        unknown = replaced(unknown, "innerregion B\n", "innerregion B\nColour 0 1 0\n");
        SurfaceReadReport skipped;
        const Surface u = read_surface_from_memory(unknown, SurfaceFormat::Surf, "t.surf", {}, &skipped);
        CHECK(u.triangles == kTriangles);
        CHECK(u.patches == kPatches);
        CHECK(has_note(skipped, "skipped the unknown HyperSurface key 'Extra' at the top level"));
        CHECK(has_note(skipped, "skipped the unknown HyperSurface key 'Colour' in patch 0 (and 1 more times)"));
        CHECK(has_note(skipped, "skipped the unknown HyperSurface key 'Weights' in patch 0"));
    }
}

TEST_CASE("HyperSurface: many patches are summed up in one note", "[surface_io][surf]") {
    // A fan of 29 triangles around vertex 1, one patch each.
    SurfWriter w(false);
    std::vector<Vec3> fan = {{0, 0, 0}};
    for (int i = 0; i < 30; ++i) fan.push_back({std::cos(i * 0.2), std::sin(i * 0.2), 0});
    w.vertices(fan);
    w.line("Patches 29");
    for (int i = 0; i < 29; ++i) w.patch("M" + std::to_string(i), "Exterior", {1, i + 2, i + 3});
    SurfaceReadReport report;
    const Surface s = read_surface_from_memory(w.out, SurfaceFormat::Surf, "t.surf", {}, &report);
    REQUIRE(s.patches.size() == 29);
    CHECK(s.patches[28] == 28);
    CHECK(report.notes.size() == 21);
    CHECK(has_note(report, "patch 19 = InnerRegion M19 / OuterRegion Exterior (1 triangle)"));
    CHECK_FALSE(has_note(report, "patch 20 ="));
    CHECK(has_note(report, "patches 20 to 28 = 9 more HyperSurface patches (9 triangles)"));
}

TEST_CASE("HyperSurface: a file without the extension is read by its first line", "[surface_io][surf]") {
    const test_support::ScratchDir scratch("read_surf_test");
    const fs::path& dir = scratch.path;
    for (const bool binary : {false, true}) {
        for (const char* name : {"labels", "labels.dat", "labels.surf"}) {
            INFO(name << (binary ? " BINARY" : " ASCII"));
            const fs::path path = dir / name;
            std::ofstream(path, std::ios::binary) << two_materials(binary).bytes;
            SurfaceReadReport report;
            const Surface s = read_surface(path.string(), {}, &report);
            CHECK(report.format == SurfaceFormat::Surf);
            CHECK(s.triangles == kTriangles);
            CHECK(s.patches == kPatches);
        }
    }
    // Only the HyperSurface head chooses a format; other files still need their extension.
    std::ofstream(dir / "mesh.dat") << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    CHECK_THROWS_WITH(read_surface((dir / "mesh.dat").string()), Catch::Contains("cannot tell the surface format"));
}

TEST_CASE("HyperSurface: ASCII errors name the line", "[surface_io][surf]") {
    const std::string ok = two_materials(false).bytes;
    REQUIRE(surf_error(ok).empty());

    SECTION("first line") {
        CHECK(surf_error("") == "the file is empty");
        CHECK_SURF_ERROR("# HyperSurface 0.2 ASCII\n",
                         "line 1: HyperSurface version '0.2' is not supported (only 0.1)");
        CHECK_SURF_ERROR("# HyperSurface 0.1 TEXT\n", "line 1: unknown HyperSurface encoding 'TEXT'");
        CHECK_SURF_ERROR("# AmiraMesh BINARY-LITTLE-ENDIAN 2.1\n", "line 1: an AmiraMesh file, not a HyperSurface");
        CHECK_SURF_ERROR("OFF\n3 1 0\n", "line 1: not a HyperSurface file: the first line must be");
    }
    SECTION("structure") {
        // Unbalanced braces and an unclosed string in Parameters, at the opening brace / quote.
        CHECK_SURF_ERROR(replaced(ok, "    Units { Coordinates \"mm\" }\n}\n", "    Units { Coordinates \"mm\" }\n"),
                         "line 3: the '{' of the Parameters block is never closed (unbalanced braces");
        CHECK_SURF_ERROR(replaced(ok, "\"mm\"", "\"mm"),
                         line(ok, "Units") + "a quoted string in the Parameters block is not closed");
        CHECK_SURF_ERROR(replaced(ok, "Parameters {", "Parameters"),
                         line(ok, "Materials") + "expected '{' after 'Parameters', found 'Materials'");
        // A patch without its closing brace (at its '{'), one patch fewer than announced.
        CHECK_SURF_ERROR(ok.substr(0, ok.size() - 2), "line " + std::to_string(line_of(ok, "InnerRegion C") - 1) +
                                                          ": the '{' of patch 3 is never closed (truncated file?)");
        CHECK_SURF_ERROR_CONTAINS(replaced(ok, "Patches 4", "Patches 5"),
                                  "expected '{' opening patch 4, found the end of the file");
        CHECK_SURF_ERROR(replaced(ok, "Patches 4\n{", "Patches 4\nInnerRegion A"),
                         "line " + std::to_string(line_of(ok, "Patches 4") + 1) +
                             ": expected '{' opening patch 0, found 'InnerRegion'");
        // Patches before Vertices; a patch without Triangles.
        CHECK_SURF_ERROR("# HyperSurface 0.1 ASCII\nPatches 1\n{ Triangles 0 }\n", "line 2: Patches before Vertices");
        CHECK_SURF_ERROR(replaced(ok, "Triangles 0\n", "\n"),
                         "line " + std::to_string(line_of(ok, "InnerRegion C") - 1) + ": patch 3 has no 'Triangles'");
        CHECK_SURF_ERROR("# HyperSurface 0.1 ASCII\nVertices 0\n", "no Patches section");
        CHECK_SURF_ERROR("# HyperSurface 0.1 ASCII\nVertices 0\nPatches\n",
                         "line 3: expected a count after 'Patches', found the end of the line");
    }
    SECTION("counts and values") {
        // The count of triangles missing, negative, too large for the file.
        CHECK_SURF_ERROR(replaced(ok, "Triangles 1\n", "Triangles\n"),
                         line(ok, "Triangles 1") + "expected a count after 'Triangles', found the end of the line");
        CHECK_SURF_ERROR(replaced(ok, "Triangles 1\n", "Triangles -1\n"),
                         line(ok, "Triangles 1") + "negative count -1 after 'Triangles'");
        CHECK_SURF_ERROR(replaced(ok, "Vertices 5", "Vertices 5000000"),
                         line(ok, "Vertices 5") + "5000000 vertices announced, but the");
        CHECK_SURF_ERROR(replaced(ok, "Vertices 5", "Vertices 4000000000"),
                         line(ok, "Vertices 5") + "4000000000 vertices announced; bpm supports at most 2147483647");
        // Fewer vertices than lines: the fifth vertex is where a keyword belongs.
        CHECK_SURF_ERROR(replaced(ok, "Vertices 5", "Vertices 4"),
                         line(ok, "\t0.25 0.25 -1") +
                             "expected a section keyword such as Vertices or Patches, found '0.25' "
                             "(more values than a count announced?)");
        // One-based indices: 0 and 6 are out of range.
        CHECK_SURF_ERROR(replaced(ok, "\t1 2 4\n", "\t0 2 4\n"),
                         line(ok, "\t1 2 4") +
                             "patch 0, triangle 0: vertex index 0 is out of range (the file has 5 "
                             "vertices, numbered from 1)");
        CHECK_SURF_ERROR(replaced(ok, "\t1 5 2\n", "\t1 5 6\n"),
                         line(ok, "\t1 5 2") + "patch 1, triangle 0: vertex index 6 is out of range");
        CHECK_SURF_ERROR(
            replaced(ok, "\t1 5 2\n", "\t1 5 2.5\n"),
            line(ok, "\t1 5 2") + "expected a vertex index of triangle 0 of patch 1 (an integer), found '2.5'");
        // Too few indices: the closing brace comes instead.
        CHECK_SURF_ERROR(replaced(ok, "\t1 3 2\n", "\t1 3\n"),
                         "line " + std::to_string(line_of(ok, "\t1 3 2") + 1) +
                             ": expected a vertex index of triangle 0 of patch 2 (an integer), found '}'");
        // Coordinates: NaN, infinity, not a number.
        CHECK_SURF_ERROR(replaced(ok, "\t1 0 0\n", "\tnan 0 0\n"),
                         line(ok, "\t1 0 0") + "a coordinate of vertex 2 'nan' is not a finite number");
        CHECK_SURF_ERROR(replaced(ok, "\t1 0 0\n", "\t1 -inf 0\n"),
                         line(ok, "\t1 0 0") + "a coordinate of vertex 2 '-inf' is not a finite number");
        CHECK_SURF_ERROR(replaced(ok, "\t1 0 0\n", "\t1 zero 0\n"),
                         line(ok, "\t1 0 0") + "expected a coordinate of vertex 2 (a number), found 'zero'");
        // A name missing; a second Triangles in one patch.
        CHECK_SURF_ERROR(replaced(ok, "InnerRegion B\n", "InnerRegion\n"),
                         line(ok, "InnerRegion B") + "expected a name after 'InnerRegion', found the end of the line");
        const std::string twice = replaced(ok, "BranchingPoints 0\n\nTriangles 1\n", "Triangles 0\nTriangles 1\n");
        CHECK_SURF_ERROR(twice, line(twice, "Triangles 1") + "a second 'Triangles' in patch 2");
    }
}

TEST_CASE("HyperSurface: BINARY errors name the byte offset", "[surface_io][surf]") {
    const TwoMaterials t = two_materials(true);
    const std::string& ok = t.bytes;
    REQUIRE(surf_error(ok).empty());
    auto offset = [](size_t at) { return "byte offset " + std::to_string(at) + ": "; };
    auto with_int = [&](size_t at, int32_t value) {
        std::string bad = ok;
        std::string raw;
        put<int32_t>(raw, value, true);
        return bad.replace(at, 4, raw);
    };
    auto with_float_bits = [&](size_t at, uint32_t bits) {
        std::string bad = ok;
        std::string raw;
        put<uint32_t>(raw, bits, true);
        return bad.replace(at, 4, raw);
    };

    // Indices out of range, at the offset of the index.
    CHECK_SURF_ERROR(with_int(t.triangle_data, 0),
                     offset(t.triangle_data) +
                         "patch 0, triangle 0: vertex index 0 is out of range (the file has 5 "
                         "vertices, numbered from 1)");
    CHECK_SURF_ERROR(with_int(t.triangle_data + 16, 99),
                     offset(t.triangle_data + 16) + "patch 0, triangle 1: vertex index 99 is out of range");
    CHECK_SURF_ERROR(with_int(t.triangle_data + 4, -3),
                     offset(t.triangle_data + 4) + "patch 0, triangle 0: vertex index -3");
    // NaN and infinite coordinates: y of vertex 2, z of vertex 5.
    CHECK_SURF_ERROR(with_float_bits(t.vertex_data + 16, 0x7fc00000u),
                     offset(t.vertex_data + 16) + "vertex 2: coordinate y is NaN");
    CHECK_SURF_ERROR(with_float_bits(t.vertex_data + 56, 0xff800000u),
                     offset(t.vertex_data + 56) + "vertex 5: coordinate z is infinite");
    // Truncated: inside the vertices, inside the triangles (refused at the count), and
    // after the last values (the patch is never closed).
    const size_t vertices_count = ok.find("Vertices 5") + 9;
    CHECK_SURF_ERROR(ok.substr(0, t.vertex_data + 30),
                     offset(vertices_count) +
                         "5 vertices announced, but the 31 bytes left in the file cannot hold that "
                         "many (truncated, or wrong counts?)");
    const size_t triangles_count = ok.find("Triangles 3") + 10;
    CHECK_SURF_ERROR(ok.substr(0, t.triangle_data + 20),
                     offset(triangles_count) + "3 triangles in patch 0 announced, but the 21 bytes left");
    const size_t last_open = ok.rfind("{\nInnerRegion C");
    CHECK_SURF_ERROR(ok.substr(0, ok.size() - 2), offset(last_open) + "the '{' of patch 3 is never closed");
    // Text after a count where the binary values belong; a count too large.
    CHECK_SURF_ERROR(replaced(ok, "Vertices 5\n", "Vertices 5 x\n"),
                     offset(vertices_count + 2) +
                         "unexpected 'x' after the count '5' of vertices (the binary values "
                         "start on the next line)");
    CHECK_SURF_ERROR(replaced(ok, "Triangles 3\n", "Triangles 30\n"),
                     offset(triangles_count) + "30 triangles in patch 0 announced");
    // Unknown keys cannot be skipped in binary files.
    const std::string unknown = replaced(ok, "InnerRegion B\n", "InnerRegion B\nColour 1 0 0\n");
    CHECK_SURF_ERROR(unknown, offset(unknown.find("Colour")) +
                                  "unknown key 'Colour' in patch 1: in a BINARY file its "
                                  "values cannot be skipped safely");
    // A missing Triangles count, as text in a binary file.
    CHECK_SURF_ERROR(
        replaced(ok, "Triangles 1\n", "Triangles\n"),
        offset(ok.find("Triangles 1") + 9) + "expected a count after 'Triangles', found the end of the line");
    CHECK_SURF_ERROR(
        replaced(ok, "Triangles 1\n", "Triangles one\n"),
        offset(ok.find("Triangles 1") + 10) + "expected a count after 'Triangles' (an integer), found 'one'");
}
