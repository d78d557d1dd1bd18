// bpm-fuzz-seeds OUTDIR: writes small valid files of every input format into
// OUTDIR/{off,obj,stl,ply,msh,vtk,surf,nifti,nrrd,metaimage,bpm}/, the seed corpora of the fuzz targets
// (scripts/fuzz.sh adds the malformed files of tests/data/bad/ and spec/examples/).
//
// Surfaces come from the library's writers (one encoding per format) and, for the
// encodings, features and formats the writers do not produce (ASCII PLY and STL,
// big-endian PLY, MSH 2.2, binary MSH, OBJ groups / materials / relative indices, OFF
// colours, legacy VTK, Amira HyperSurface), from the small builders below, so that the
// fuzzer starts inside every branch of every reader. .bpm seeds are the fixtures of tests/unit/fixtures_phi.h, a simplified
// octahedron with its record of steps, one with a tetrahedral mesh (if tetgen is
// installed) and one with a refined one.
// Exit codes: 0 ok, 2 usage, 4 output error.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>
#include <zlib.h>

#include "bpm/bpm_file.h"
#include "bpm/errors.h"
#include "bpm/simplify.h"
#include "bpm/surface_io.h"
#include "bpm/tet_refine.h"
#include "bpm/tetmesh.h"
#include "fixtures_phi.h"
#include "test_bytes.h"

namespace fs = std::filesystem;
using namespace bpm;

namespace {

fs::path g_out;

void put_file(const std::string& format, const std::string& name, const std::string& bytes) {
    std::ofstream out(g_out / format / name, std::ios::binary);
    out << bytes;
    if (!out) throw OutputError((g_out / format / name).string(), "cannot write");
}

template <class T>
void put(std::string& out, T value, bool big_endian = false) {
    test_bytes::put(out, value, big_endian);
}

std::string num(double x) { return test_bytes::text(x); }

Surface tetrahedron() {
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    s.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    s.patches = {0, 0, 1, 1};
    return s;
}

std::string off_colours(const Surface& s) {
    std::string o = "# coloured OFF\nCOFF " + std::to_string(s.vertices.size()) + " " +
                    std::to_string(s.triangles.size()) + " 0\n";
    for (const Vec3& p : s.vertices) o += num(p[0]) + " " + num(p[1]) + " " + num(p[2]) + " 255 0 0 255\n";
    for (const Tri& t : s.triangles)
        o += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + " 0.5 0.5 0.5\n";
    return o;
}

std::string obj_features(const Surface& s) {
    std::string o = "mtllib x.mtl\no thing\n";
    for (const Vec3& p : s.vertices) o += "v " + num(p[0]) + " " + num(p[1]) + " \\\n " + num(p[2]) + "\n";
    o += "vt 0 0\nvn 0 0 1\ns 1\n";
    const int nv = static_cast<int>(s.vertices.size());
    for (size_t t = 0; t < s.triangles.size(); ++t) {
        if (t == 0 || s.patches[t] != s.patches[t - 1])
            o += "g part" + std::to_string(s.patches[t]) + "\nusemtl m" + std::to_string(t % 2) + "\n";
        const Tri& f = s.triangles[t];
        // absolute v/vt/vn, relative v//vn, plain v
        o += "f " + std::to_string(f[0] + 1) + "/1/1 " + std::to_string(f[1] - nv) + "//1 " +
             std::to_string(f[2] + 1) + "\n";
    }
    o += "l 1 2\n";
    return o;
}

std::string stl_ascii(const Surface& s) {
    std::string o;
    for (int solid = 0; solid < 2; ++solid) {
        o += "solid part" + std::to_string(solid) + "\n";
        for (size_t t = 0; t < s.triangles.size(); ++t) {
            if (static_cast<int>(t % 2) != solid) continue;
            o += "  facet normal 0 0 1\n    outer loop\n";
            for (int32_t v : s.triangles[t])
                o += "      vertex " + num(s.vertices[v][0]) + " " + num(s.vertices[v][1]) + " " +
                     num(s.vertices[v][2]) + "\n";
            o += "    endloop\n  endfacet\n";
        }
        o += "endsolid part" + std::to_string(solid) + "\n";
    }
    return o;
}

std::string ply_ascii(const Surface& s) {
    std::string o = "ply\nformat ascii 1.0\ncomment seed\nelement vertex " + std::to_string(s.vertices.size()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\n"
                    "property list uchar float extra\nelement face " +
                    std::to_string(s.triangles.size()) +
                    "\nproperty list uchar int vertex_indices\nproperty int material\nelement edge 1\n"
                    "property int vertex1\nproperty int vertex2\nend_header\n";
    for (const Vec3& p : s.vertices) o += num(p[0]) + " " + num(p[1]) + " " + num(p[2]) + " 7 2 0.5 1.5\n";
    for (size_t t = 0; t < s.triangles.size(); ++t) {
        const Tri& f = s.triangles[t];
        o += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + " " +
             std::to_string(s.patches[t]) + "\n";
    }
    o += "0 1\n";
    return o;
}

std::string ply_big_endian(const Surface& s) {
    std::string o = "ply\nformat binary_big_endian 1.0\nelement vertex " + std::to_string(s.vertices.size()) +
                    "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
                    std::to_string(s.triangles.size()) +
                    "\nproperty list uint ushort vertex_index\nproperty short region\nend_header\n";
    for (const Vec3& p : s.vertices)
        for (double x : p) put<double>(o, x, true);
    for (size_t t = 0; t < s.triangles.size(); ++t) {
        put<uint32_t>(o, 3, true);
        for (int32_t v : s.triangles[t]) put<uint16_t>(o, static_cast<uint16_t>(v), true);
        put<int16_t>(o, static_cast<int16_t>(s.patches[t]), true);
    }
    return o;
}

std::string msh22_ascii(const Surface& s) {
    std::string o = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"skin\"\n$EndPhysicalNames\n$Nodes\n" +
                    std::to_string(s.vertices.size()) + "\n";
    for (size_t i = 0; i < s.vertices.size(); ++i)
        o += std::to_string(10 + 2 * i) + " " + num(s.vertices[i][0]) + " " + num(s.vertices[i][1]) + " " +
             num(s.vertices[i][2]) + "\n";
    o += "$EndNodes\n$Elements\n" + std::to_string(s.triangles.size() + 1) + "\n1 1 2 0 1 10 12\n";
    for (size_t t = 0; t < s.triangles.size(); ++t) {
        const Tri& f = s.triangles[t];
        o += std::to_string(t + 2) + " 2 2 " + std::to_string(s.patches[t]) + " 1 " + std::to_string(10 + 2 * f[0]) +
             " " + std::to_string(10 + 2 * f[1]) + " " + std::to_string(10 + 2 * f[2]) + "\n";
    }
    o += "$EndElements\n";
    return o;
}

std::string msh22_binary(const Surface& s, bool big_endian) {
    std::string o = "$MeshFormat\n2.2 1 8\n";
    put<int32_t>(o, 1, big_endian);
    o += "\n$EndMeshFormat\n$Nodes\n" + std::to_string(s.vertices.size()) + "\n";
    for (size_t i = 0; i < s.vertices.size(); ++i) {
        put<int32_t>(o, static_cast<int32_t>(i + 1), big_endian);
        for (double x : s.vertices[i]) put<double>(o, x, big_endian);
    }
    o += "\n$EndNodes\n$Elements\n" + std::to_string(s.triangles.size() + 1) + "\n";
    // one point element (type 15) to be skipped, then the triangles
    for (int32_t v : {15, 1, 2, 1, 9, 9, 1}) put<int32_t>(o, v, big_endian);
    for (int32_t v : {2, static_cast<int32_t>(s.triangles.size()), 2}) put<int32_t>(o, v, big_endian);
    for (size_t t = 0; t < s.triangles.size(); ++t) {
        put<int32_t>(o, static_cast<int32_t>(t + 2), big_endian);
        put<int32_t>(o, s.patches[t], big_endian);
        put<int32_t>(o, 1, big_endian);
        for (int32_t v : s.triangles[t]) put<int32_t>(o, v + 1, big_endian);
    }
    o += "\n$EndElements\n";
    return o;
}

// MSH 4.1 binary: one surface entity with a physical tag, one node block, one line
// element block (skipped) and one triangle block.
std::string msh41_binary(const Surface& s) {
    std::string o = "$MeshFormat\n4.1 1 8\n";
    put<int32_t>(o, 1);
    o += "\n$EndMeshFormat\n$Entities\n";
    for (uint64_t c : {0, 1, 1, 0}) put<uint64_t>(o, c);
    put<int32_t>(o, 1);  // curve 1
    for (int k = 0; k < 6; ++k) put<double>(o, 0);
    put<uint64_t>(o, 0);  // no physical tags
    put<uint64_t>(o, 0);  // no bounding points
    put<int32_t>(o, 1);  // surface 1
    for (int k = 0; k < 6; ++k) put<double>(o, k < 3 ? 0 : 1);
    put<uint64_t>(o, 1);
    put<int32_t>(o, 5);  // physical tag 5
    put<uint64_t>(o, 1);
    put<int32_t>(o, 1);  // bounded by curve 1
    o += "\n$EndEntities\n$Nodes\n";
    const uint64_t nv = s.vertices.size(), nt = s.triangles.size();
    for (uint64_t c : {uint64_t(1), nv, uint64_t(1), nv}) put<uint64_t>(o, c);
    put<int32_t>(o, 2), put<int32_t>(o, 1), put<int32_t>(o, 0), put<uint64_t>(o, nv);
    for (uint64_t i = 1; i <= nv; ++i) put<uint64_t>(o, i);
    for (const Vec3& p : s.vertices)
        for (double x : p) put<double>(o, x);
    o += "\n$EndNodes\n$Elements\n";
    for (uint64_t c : {uint64_t(2), nt + 1, uint64_t(1), nt + 1}) put<uint64_t>(o, c);
    put<int32_t>(o, 1), put<int32_t>(o, 1), put<int32_t>(o, 1), put<uint64_t>(o, 1);  // a line
    for (uint64_t v : {nt + 1, uint64_t(1), uint64_t(2)}) put<uint64_t>(o, v);
    put<int32_t>(o, 2), put<int32_t>(o, 1), put<int32_t>(o, 2), put<uint64_t>(o, nt);
    for (uint64_t t = 0; t < nt; ++t) {
        put<uint64_t>(o, t + 1);
        for (int32_t v : s.triangles[t]) put<uint64_t>(o, static_cast<uint64_t>(v) + 1);
    }
    o += "\n$EndElements\n";
    return o;
}


// Legacy VTK: POLYDATA in both encodings and both cell layouts (4.2 records, 5.1
// OFFSETS / CONNECTIVITY), with a line cell, a strip, cell data patches and point data of
// several kinds; an UNSTRUCTURED_GRID with a skipped vertex cell.
struct VtkSeed {
    bool binary;
    std::string o;
    void line(const std::string& t) { o += t + "\n"; }
    template <class T>
    void values(const std::vector<T>& v) {
        for (size_t i = 0; i < v.size(); ++i) {
            if (binary) put<T>(o, v[i], true);
            else o += (i ? " " : "") + num(static_cast<double>(v[i]));
        }
        o += "\n";
    }
    void cells(const std::string& keyword, const std::vector<std::vector<int32_t>>& cells, bool new_layout) {
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
        } else {
            line(keyword + " " + std::to_string(cells.size()) + " " + std::to_string(total + cells.size()));
            std::vector<int32_t> flat;
            for (const auto& c : cells) {
                flat.push_back(static_cast<int32_t>(c.size()));
                flat.insert(flat.end(), c.begin(), c.end());
            }
            values(flat);
        }
    }
};

std::string vtk_polydata(const Surface& s, bool binary, bool new_layout) {
    VtkSeed w{binary, std::string("# vtk DataFile Version ") + (new_layout ? "5.1" : "4.2") + "\nseed\n" +
                          (binary ? "BINARY" : "ASCII") + "\n"};
    w.line("DATASET POLYDATA");
    w.line("FIELD FieldData 1");
    w.line("TimeValue 1 1 double");
    w.values(std::vector<double>{1.5});
    w.line("POINTS " + std::to_string(s.vertices.size()) + " double");
    std::vector<double> xyz;
    for (const Vec3& p : s.vertices) xyz.insert(xyz.end(), p.begin(), p.end());
    w.values(xyz);
    std::vector<std::vector<int32_t>> polys;
    for (size_t t = 1; t < s.triangles.size(); ++t) polys.push_back({s.triangles[t][0], s.triangles[t][1], s.triangles[t][2]});
    w.cells("LINES", {{0, 1}}, new_layout);
    w.cells("POLYGONS", polys, new_layout);
    // The first triangle as a strip of three points.
    w.cells("TRIANGLE_STRIPS", {{s.triangles[0][0], s.triangles[0][1], s.triangles[0][2]}}, new_layout);
    w.line("CELL_DATA " + std::to_string(s.triangles.size() + 1));
    w.line("SCALARS material int 1");
    w.line("LOOKUP_TABLE default");
    std::vector<int32_t> patches{0};
    for (size_t t = 1; t < s.triangles.size(); ++t) patches.push_back(s.patches[t]);
    patches.push_back(s.patches[0]);
    w.values(patches);
    w.line("POINT_DATA " + std::to_string(s.vertices.size()));
    w.line("SCALARS temp float");
    w.line("LOOKUP_TABLE default");
    std::vector<float> temp;
    for (size_t i = 0; i < s.vertices.size(); ++i) temp.push_back(static_cast<float>(i) * 0.5f);
    w.values(temp);
    w.line("NORMALS Normals double");
    w.values(xyz);
    w.line("METADATA");
    w.line("INFORMATION 1");
    w.line("NAME L2_NORM_RANGE LOCATION vtkDataArray");
    w.line("DATA 2 0 1");
    w.line("");
    w.line("COLOR_SCALARS rgb 3");
    if (binary) w.values(std::vector<uint8_t>(3 * s.vertices.size(), 128));
    else w.values(std::vector<float>(3 * s.vertices.size(), 0.5f));
    w.line("FIELD FieldData 2");
    w.line("ids 1 " + std::to_string(s.vertices.size()) + " vtkIdType");
    std::vector<int32_t> ids;
    for (size_t i = 0; i < s.vertices.size(); ++i) ids.push_back(static_cast<int32_t>(i));
    w.values(ids);
    w.line("bits 1 " + std::to_string(s.vertices.size()) + " bit");
    if (binary) w.values(std::vector<uint8_t>((s.vertices.size() + 7) / 8, 0xa5));
    else w.values(std::vector<int32_t>(s.vertices.size(), 1));
    return w.o;
}

std::string vtk_grid(const Surface& s, bool binary) {
    VtkSeed w{binary, std::string("# vtk DataFile Version 5.1\nseed\n") + (binary ? "BINARY" : "ASCII") + "\n"};
    w.line("DATASET UNSTRUCTURED_GRID");
    w.line("POINTS " + std::to_string(s.vertices.size()) + " float");
    std::vector<float> xyz;
    for (const Vec3& p : s.vertices)
        for (double x : p) xyz.push_back(static_cast<float>(x));
    w.values(xyz);
    std::vector<std::vector<int32_t>> cells{{0}};
    for (const Tri& t : s.triangles) cells.push_back({t[0], t[1], t[2]});
    w.cells("CELLS", cells, true);
    w.line("CELL_TYPES " + std::to_string(cells.size()));
    std::vector<int32_t> types(cells.size(), 5);
    types[0] = 1;
    w.values(types);
    w.line("CELL_DATA " + std::to_string(cells.size()));
    w.line("FIELD FieldData 1");
    w.line("gmsh:physical 1 " + std::to_string(cells.size()) + " int");
    std::vector<int32_t> physical{0};
    physical.insert(physical.end(), s.patches.begin(), s.patches.end());
    w.values(physical);
    return w.o;
}

// Amira HyperSurface: one Patches entry per patch id (a run of triangles), with the
// sections that are parsed and skipped (Parameters, boundary curves, branching points,
// Surfaces); binary values big-endian.
std::string surf(const Surface& s, bool binary) {
    std::string o = std::string("# HyperSurface 0.1 ") + (binary ? "BINARY" : "ASCII") + "\n\n";
    o += "Parameters {\n    Materials {\n        Exterior { Id 0 }\n        M0 { Color 1 0.5 0, Id 1 }\n    }\n"
         "    Units { Coordinates \"mm\" } # comment }\n}\n";
    auto ints = [&](const std::string& key, const std::vector<int32_t>& v, size_t per) {
        o += key + " " + std::to_string(v.size() / per) + "\n";
        for (size_t i = 0; i < v.size(); ++i) {
            if (binary) put<int32_t>(o, v[i], true);
            else o += std::to_string(v[i]) + (i % per == per - 1 ? "\n" : " ");
        }
        if (binary) o += "\n";
    };
    o += "Vertices " + std::to_string(s.vertices.size()) + "\n";
    for (const Vec3& p : s.vertices) {
        for (int k = 0; k < 3; ++k) {
            if (binary) put<float>(o, static_cast<float>(p[k]), true);
            else o += num(p[k]) + (k == 2 ? "\n" : " ");
        }
    }
    if (binary) o += "\n";
    o += "NBranchingPoints 1\nNVerticesOnCurves 0\nBoundaryCurves 1\n{\n";
    ints("Vertices", {1, 2, 1}, 1);
    std::vector<std::pair<size_t, size_t>> runs;  // [begin, end) of each patch run
    for (size_t t = 0; t < s.triangles.size(); ++t) {
        if (t == 0 || s.patches[t] != s.patches[t - 1]) runs.push_back({t, t});
        runs.back().second = t + 1;
    }
    o += "}\nPatches " + std::to_string(runs.size()) + "\n";
    for (size_t r = 0; r < runs.size(); ++r) {
        o += "{\nInnerRegion M" + std::to_string(r) + "\nOuterRegion Exterior\nBoundaryID 0\n";
        ints("BranchingPoints", {1}, 1);
        std::vector<int32_t> indices;
        for (size_t t = runs[r].first; t < runs[r].second; ++t)
            for (int32_t v : s.triangles[t]) indices.push_back(v + 1);
        ints("Triangles", indices, 3);
        o += "}\n";
    }
    o += "Surfaces 1\n{\nRegion M0\n";
    ints("Patches", {1}, 1);
    return o + "}\n";
}

void write_surface_seeds(const std::string& stem, const Surface& s) {
    for (const char* ext : {"off", "obj", "stl", "ply", "msh"})
        write_surface((g_out / ext / (stem + "." + ext)).string(), s);
    put_file("off", stem + "_colours.off", off_colours(s));
    put_file("obj", stem + "_features.obj", obj_features(s));
    put_file("stl", stem + "_ascii.stl", stl_ascii(s));
    put_file("ply", stem + "_ascii.ply", ply_ascii(s));
    put_file("ply", stem + "_big_endian.ply", ply_big_endian(s));
    put_file("msh", stem + "_22_ascii.msh", msh22_ascii(s));
    put_file("msh", stem + "_22_binary.msh", msh22_binary(s, false));
    put_file("msh", stem + "_22_binary_be.msh", msh22_binary(s, true));
    put_file("msh", stem + "_41_binary.msh", msh41_binary(s));
    for (const bool binary : {false, true}) {
        const std::string encoding = binary ? "_binary" : "_ascii";
        put_file("vtk", stem + encoding + "_42.vtk", vtk_polydata(s, binary, false));
        put_file("vtk", stem + encoding + "_51.vtk", vtk_polydata(s, binary, true));
        put_file("vtk", stem + encoding + "_grid.vtk", vtk_grid(s, binary));
        put_file("surf", stem + encoding + ".surf", surf(s, binary));
    }
}

BpmFile wrap(Parametrization p, const std::string& what) {
    BpmFile f;
    f.param = std::move(p);
    f.units = "mm";
    f.provenance.push_back({"bpm-fuzz-seeds", "1", what, ""});
    return f;
}

}  // namespace

// NIfTI-1 label images: a 5x4x3 block of labels 0-3 (uint8, sform) and the same as int16
// big-endian with a qform.
std::string nifti(bool int16_big_endian) {
    std::string h(352, '\0');
    const auto put_at = [&](size_t at, const void* p, size_t n, bool swap) {
        std::string b(static_cast<const char*>(p), n);
        if (swap) std::reverse(b.begin(), b.end());
        h.replace(at, n, b);
    };
    const bool sw = int16_big_endian;
    const int32_t hdr = 348;
    put_at(0, &hdr, 4, sw);
    const int16_t dim[8] = {3, 5, 4, 3, 1, 1, 1, 1};
    for (int i = 0; i < 8; ++i) put_at(40 + 2 * size_t(i), &dim[i], 2, sw);
    const int16_t type = int16_big_endian ? 4 : 2, bits = int16_big_endian ? 16 : 8;
    put_at(70, &type, 2, sw);
    put_at(72, &bits, 2, sw);
    const float pixdim[4] = {-1, 1, 1.5f, 2};
    for (int i = 0; i < 4; ++i) put_at(76 + 4 * size_t(i), &pixdim[i], 4, sw);
    const float offset = 352;
    put_at(108, &offset, 4, sw);
    const int16_t code = 1;
    if (int16_big_endian) {
        put_at(252, &code, 2, sw);
        const float q[6] = {0, 0, 0.7071f, 1, 2, 3};
        for (int i = 0; i < 6; ++i) put_at(256 + 4 * size_t(i), &q[i], 4, sw);
    } else {
        put_at(254, &code, 2, sw);
        const float srow[12] = {1, 0, 0, -2, 0, 1, 0, -2, 0, 0, 1, -2};
        for (int i = 0; i < 12; ++i) put_at(280 + 4 * size_t(i), &srow[i], 4, sw);
    }
    h.replace(344, 4, std::string("n+1\0", 4));
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 5; ++i) {
                const int16_t l = int16_t((i / 2 + j / 2 + k) % 4);
                if (int16_big_endian) put_at(h.size(), &l, 2, true);
                else h.push_back(char(l));
            }
    return h;
}

void write_nifti_seeds() {
    std::ofstream((g_out / "nifti" / "labels_uint8.nii").string(), std::ios::binary) << nifti(false);
    std::ofstream((g_out / "nifti" / "labels_int16_be.nii").string(), std::ios::binary) << nifti(true);
}

// The same 5x4x3 block of labels 0-3 as NRRD and MetaImage files, in every encoding the
// readers take: one byte per label, or as 16-bit `big` / little endian.
std::string block_voxels(int bytes_per_voxel, bool big_endian) {
    std::string out;
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 5; ++i) {
                const char l = char((i / 2 + j / 2 + k) % 4);
                std::string v(size_t(bytes_per_voxel), '\0');
                v[big_endian ? v.size() - 1 : 0] = l;
                out += v;
            }
    return out;
}

std::string zlib_compress(const std::string& raw, bool gzip) {
    z_stream z{};
    deflateInit2(&z, 9, Z_DEFLATED, gzip ? 15 + 16 : 15, 8, Z_DEFAULT_STRATEGY);
    std::string out(deflateBound(&z, uLong(raw.size())) + 32, '\0');
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(raw.data()));
    z.avail_in = uInt(raw.size());
    z.next_out = reinterpret_cast<Bytef*>(&out[0]);
    z.avail_out = uInt(out.size());
    deflate(&z, Z_FINISH);
    out.resize(z.total_out);
    deflateEnd(&z);
    return out;
}

void write_nrrd_seeds() {
    const std::string head = "NRRD0004\n# bpm-fuzz-seeds\ndimension: 3\nsizes: 5 4 3\n";
    const std::string lps = "space: left-posterior-superior\nspace directions: (-1,0,0) (0,-1.5,0) (0,0,2)\n"
                            "space origin: (2,2,-2)\n";
    put_file("nrrd", "labels_raw_lps.nrrd", head + "type: uchar\nencoding: raw\n" + lps + "\n" + block_voxels(1, false));
    put_file("nrrd", "labels_gzip_short_be.nrrd",
             head + "type: short\nencoding: gzip\nendian: big\nspace: right-anterior-superior\n"
                    "space directions: (1,0,0) (0,1,0) (0,0,1)\n\n" + zlib_compress(block_voxels(2, true), true));
    std::string ascii;
    for (const char l : block_voxels(1, false)) ascii += std::to_string(int(l)) + " ";
    put_file("nrrd", "labels_ascii_spacings.nrrd", head + "type: int\nencoding: ascii\nspacings: 1 1 2\n\n" + ascii + "\n");
    // A one-layer .seg.nrrd as 3D Slicer writes it: 4 axes, the first 'none', segment names.
    put_file("nrrd", "labels.seg.nrrd",
             "NRRD0004\ntype: unsigned char\ndimension: 4\nspace: left-posterior-superior\nsizes: 1 5 4 3\n"
             "space directions: none (1,0,0) (0,1,0) (0,0,1)\nkinds: list domain domain domain\nencoding: gzip\n"
             "space origin: (0,0,0)\nSegment0_ID:=Segment_1\nSegment0_LabelValue:=1\nSegment0_Layer:=0\n"
             "Segment0_Name:=bone\nSegment1_LabelValue:=2\nSegment1_Name:=marrow\n\n" +
                 zlib_compress(block_voxels(1, false), true));
}

void write_metaimage_seeds() {
    const std::string head = "ObjectType = Image\nNDims = 3\nBinaryData = True\n";
    const std::string geometry = "TransformMatrix = -1 0 0 0 -1 0 0 0 1\nOffset = 2 2 -2\nCenterOfRotation = 0 0 0\n"
                                 "AnatomicalOrientation = RAI\nElementSpacing = 1 1.5 2\nDimSize = 5 4 3\n";
    put_file("metaimage", "labels_uchar.mha",
             head + "BinaryDataByteOrderMSB = False\nCompressedData = False\n" + geometry +
                 "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n" + block_voxels(1, false));
    const std::string packed = zlib_compress(block_voxels(2, true), false);
    put_file("metaimage", "labels_short_msb_zlib.mha",
             head + "ElementByteOrderMSB = True\nCompressedData = True\nCompressedDataSize = " +
                 std::to_string(packed.size()) + "\n" + geometry + "ElementType = MET_SHORT\nElementDataFile = LOCAL\n" +
                 packed);
    std::string floats;
    for (const char l : block_voxels(1, false)) {
        const float x = float(l);
        floats.append(reinterpret_cast<const char*>(&x), 4);
    }
    put_file("metaimage", "labels_float_headersize.mha",
             head + "HeaderSize = 0\nElementSize = 1 1 1\nPosition = 0 0 0\nDimSize = 5 4 3\n"
                    "ElementNumberOfChannels = 1\nElementType = MET_FLOAT\nElementDataFile = LOCAL\n" + floats);
}

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: bpm-fuzz-seeds OUTDIR\n");
        return 2;
    }
    g_out = argv[1];
    try {
        for (const char* d : {"off", "obj", "stl", "ply", "msh", "vtk", "surf", "nifti", "nrrd", "metaimage", "bpm"}) fs::create_directories(g_out / d);

        write_surface_seeds("tetrahedron", tetrahedron());
        write_nifti_seeds();
        write_nrrd_seeds();
        write_metaimage_seeds();
        write_surface_seeds("octahedron1", test::make_subdivided_octahedron(1).original);
        write_surface_seeds("height_field", test::make_height_field(4, 2, test::default_height).original);

        write_bpm((g_out / "bpm" / "two_triangles.bpm").string(), test::make_two_triangles_example());
        write_bpm((g_out / "bpm" / "octahedron0.bpm").string(), wrap(test::make_subdivided_octahedron(0), "oct 0"));
        write_bpm((g_out / "bpm" / "octahedron1.bpm").string(), wrap(test::make_subdivided_octahedron(1), "oct 1"));
        write_bpm((g_out / "bpm" / "height_field.bpm").string(),
                  wrap(test::make_height_field(4, 2, test::default_height), "height field 4 2"));
        write_bpm((g_out / "bpm" / "identity.bpm").string(),
                  wrap(make_identity_parametrization(tetrahedron()), "identity tetrahedron"));
        {
            // What bpm-simplify --record-steps writes: a real simplification with its record.
            BpmFile f;
            SimplifyOptions so;
            so.target_vertices = 8;
            so.record_steps = true;
            SimplifyResult r = simplify(test::make_subdivided_octahedron(2).original, so, Context{}, f.param);
            f.simplification_steps = std::move(r.steps);
            f.provenance.push_back({"bpm-fuzz-seeds", "1", "simplify oct 2 --vertices 8 --record-steps", ""});
            write_bpm((g_out / "bpm" / "octahedron2_simplified_steps.bpm").string(), f);
        }
        try {
            BpmFile f = wrap(test::make_subdivided_octahedron(1), "oct 1 + tetmesh");
            TetMesh mesh;
            generate_tetmesh(f.param, TetMeshOptions{}, Context{}, mesh);
            f.tetmesh = mesh;
            write_bpm((g_out / "bpm" / "octahedron1_tetmesh.bpm").string(), f);
            TetRefineOptions ro;
            ro.levels = 1;
            TetMesh fine;
            refine_tetmesh(f.param, mesh, ro, Context{}, fine);
            f.tetmesh = fine;
            write_bpm((g_out / "bpm" / "octahedron1_tetmesh_refined.bpm").string(), f);
        } catch (const ExternalToolError& e) {
            std::fprintf(stderr, "bpm-fuzz-seeds: warning: no tetrahedral-mesh seeds (%s)\n", e.what());
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bpm-fuzz-seeds: error: %s\n", e.what());
        return 4;
    }
    return 0;
}
