// Tests of bpm/tetmesh.h: TetGen meshing of coarse surfaces, regions, the /tetmesh group
// of .bpm files and the exports. Tests that need the `tetgen` executable skip (with a
// message saying so) when it is not on PATH.

#include <hdf5.h>

#include <catch2/catch.hpp>

#include "test_support.h"
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "bpm/bpm_file.h"
#include "bpm/errors.h"
#include "bpm/predicates.h"
#include "bpm/tetmesh.h"
#include "bpm/write_tetmesh.h"
#include "fixtures_surfaces.h"

using namespace bpm;
using test_support::run_command;
using test_support::ScratchDir;

namespace {


TetMesh mesh_of(const Parametrization& p, TetMeshResult* result = nullptr) {
    TetMesh m;
    TetMeshResult r = generate_tetmesh(p, TetMeshOptions{}, Context{}, m);
    if (result) *result = r;
    return m;
}

std::array<int32_t, 3> sorted(const Tri& t) {
    std::array<int32_t, 3> k{t[0], t[1], t[2]};
    std::sort(k.begin(), k.end());
    return k;
}

// Faces of the tets that belong to exactly one tet, and the number of tets per face.
std::map<std::array<int32_t, 3>, int> face_counts(const TetMesh& m) {
    std::map<std::array<int32_t, 3>, int> count;
    for (const Tet& t : m.tetrahedra)
        for (int k = 0; k < 4; ++k) {
            Tri f{t[(k + 1) % 4], t[(k + 2) % 4], t[(k + 3) % 4]};
            ++count[sorted(f)];
        }
    return count;
}

}  // namespace

TEST_CASE("tetmesh: the boundary faces are exactly the coarse triangles", "[tetmesh]") {
    REQUIRE_TETGEN();
    const std::vector<std::pair<std::string, Surface>> cases = {{"cube", fixtures::cube(2)},
                                                                {"two_cubes", fixtures::two_cubes(2)},
                                                                {"cylinder_wedges", fixtures::cylinder_wedges()},
                                                                {"octants", fixtures::octants()}};
    for (const auto& [name, surface] : cases) {
        INFO(name);
        const Parametrization p = fixtures::identity_parametrization(surface);
        TetMeshResult r;
        const TetMesh m = mesh_of(p, &r);
        REQUIRE(find_tetmesh_inconsistency(m, p.coarse).empty());
        REQUIRE(m.faces.size() == surface.triangles.size());
        CHECK(r.steiner_points == m.num_vertices() - surface.num_vertices());
        for (int32_t v = 0; v < surface.num_vertices(); ++v) {
            CHECK(m.vertices[v] == surface.vertices[v]);
            CHECK(m.vertex_coarse_vertex[v] == v);
        }
        const auto counts = face_counts(m);
        std::set<std::array<int32_t, 3>> coarse;
        for (size_t t = 0; t < surface.triangles.size(); ++t) {
            CHECK(m.faces[t] == surface.triangles[t]);
            CHECK(m.face_coarse_triangle[t] == int32_t(t));
            CHECK(m.face_patches[t] == surface.patches[t]);
            coarse.insert(sorted(surface.triangles[t]));
            CHECK(counts.count(sorted(surface.triangles[t])) == 1);  // every coarse triangle is a tet face
        }
        for (const auto& [face, n] : counts) {
            REQUIRE(n <= 2);
            if (n == 1) CHECK(coarse.count(face) == 1);  // the hull of the mesh lies on S
        }
        for (const Tet& t : m.tetrahedra)
            CHECK(orient3d(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], m.vertices[t[3]]) == 1);
        CHECK(tetmesh_stats(m).inverted == 0);
    }
}

TEST_CASE("tetmesh: regions of multi-material surfaces have the right count and volumes", "[tetmesh]") {
    REQUIRE_TETGEN();
    struct Case {
        std::string name;
        Surface surface;
        std::vector<double> volumes;
    };
    const double wedge = 0.5 * 12 * 4 * std::sin(2 * 3.14159265358979323846 / 12) * 2 / 3;  // 12-gon area * height / 3
    const std::vector<Case> cases = {{"cube", fixtures::cube(), {1.0}},
                                     {"two_cubes", fixtures::two_cubes(), {1.0, 1.0}},
                                     {"cylinder_wedges", fixtures::cylinder_wedges(12, 2), {wedge, wedge, wedge}},
                                     {"octants", fixtures::octants(), std::vector<double>(8, 1.0)}};
    for (const auto& c : cases) {
        INFO(c.name);
        const Parametrization p = fixtures::identity_parametrization(c.surface);
        const TetMesh m = mesh_of(p);
        REQUIRE(m.num_regions() == int32_t(c.volumes.size()));
        const TetMeshStats st = tetmesh_stats(m);
        const auto on_original = region_volumes_on_original(p, m);
        std::vector<double> got = st.region_volumes, want = c.volumes;
        std::sort(got.begin(), got.end());
        for (size_t r = 0; r < want.size(); ++r) {
            CHECK(got[r] == Approx(want[r]).epsilon(1e-12));
            CHECK(on_original[r] == Approx(st.region_volumes[r]).epsilon(1e-12));
        }
        // every region id is used, and regions are edge-connected blocks separated by S
        std::set<int32_t> ids(m.regions.begin(), m.regions.end());
        CHECK(ids.size() == c.volumes.size());
        CHECK(*ids.begin() == 1);
    }
    // two_cubes: region 1 is in front of coarse triangle 0 or behind it, and the two cubes
    // [0,1]^3 and [1,2]x[0,1]^2 are different regions.
    const Parametrization p = fixtures::identity_parametrization(fixtures::two_cubes());
    const TetMesh m = mesh_of(p);
    std::set<int32_t> left, right;
    for (size_t t = 0; t < m.tetrahedra.size(); ++t) {
        double cx = 0;
        for (int32_t v : m.tetrahedra[t]) cx += 0.25 * m.vertices[v][0];
        (cx < 1 ? left : right).insert(m.regions[t]);
    }
    REQUIRE(left.size() == 1);
    REQUIRE(right.size() == 1);
    CHECK(*left.begin() != *right.begin());
}

TEST_CASE("tetmesh: components touching at a vertex (hourglass) are two regions", "[tetmesh]") {
    REQUIRE_TETGEN();
    const Parametrization p = fixtures::identity_parametrization(fixtures::hourglass());
    const TetMesh m = mesh_of(p);
    REQUIRE(m.num_regions() == 2);
    const auto st = tetmesh_stats(m);
    const auto on_original = region_volumes_on_original(p, m);
    CHECK(st.inverted == 0);
    for (int r = 0; r < 2; ++r) {
        CHECK(st.region_volumes[r] > 0);
        CHECK(st.region_volumes[r] == Approx(on_original[r]).epsilon(1e-12));
    }
}

TEST_CASE("tetmesh: surfaces TetGen cannot mesh are refused before TetGen runs, saying where", "[tetmesh]") {
    // Open surface: no tetgen needed, the check comes first.
    const Surface disk = fixtures::disk(3);
    try {
        check_meshable(disk);
        FAIL("an open surface was accepted");
    } catch (const AlgorithmError& e) {
        const std::string what = e.what();
        CHECK(what.find("surface has 12 boundary edges, first from vertex") != std::string::npos);
        // Positions, which mean something in the input, not only coarse vertex numbers.
        CHECK(what.find(") to vertex ") != std::string::npos);
    }
    // Two overlapping cubes: self-intersection.
    Surface both = fixtures::cube();
    const Surface shifted = fixtures::cube();
    const int32_t offset = both.num_vertices();
    for (Vec3 v : shifted.vertices) both.vertices.push_back(v + Vec3{0.5, 0.25, 0.125});
    for (size_t t = 0; t < shifted.triangles.size(); ++t) {
        const Tri& x = shifted.triangles[t];
        both.triangles.push_back({x[0] + offset, x[1] + offset, x[2] + offset});
        both.patches.push_back(2);
    }
    try {
        check_meshable(both);
        FAIL("a self-intersecting surface was accepted");
    } catch (const AlgorithmError& e) {
        const std::string what = e.what();
        CHECK(what.find("intersects") != std::string::npos);
        CHECK(what.find("triangle") != std::string::npos);
    }
    // generate_tetmesh refuses it too (with AlgorithmError, not TetGen's error).
    TetMesh m;
    CHECK_THROWS_AS(generate_tetmesh(fixtures::identity_parametrization(disk), {}, {}, m), AlgorithmError);
    CHECK_NOTHROW(check_meshable(fixtures::two_cubes()));
}

TEST_CASE("tetmesh: a missing or failing tetgen is an ExternalToolError naming the package", "[tetmesh]") {
    const Parametrization p = fixtures::identity_parametrization(fixtures::cube());
    TetMesh m;
    TetMeshOptions o;
    o.tetgen = "bpm-no-such-tetgen-executable";
    try {
        generate_tetmesh(p, o, {}, m);
        FAIL("no error for a missing tetgen");
    } catch (const ExternalToolError& e) {
        const std::string what = e.what();
        CHECK(what.find("Debian package 'tetgen'") != std::string::npos);
    }
    o.tetgen = "/bin/false";
    try {
        generate_tetmesh(p, o, {}, m);
        FAIL("no error for a failing tetgen");
    } catch (const ExternalToolError& e) {
        const std::string what = e.what();
        CHECK(what.find("tetgen failed (exit status 1)") != std::string::npos);
    }
    // A script standing in for TetGen that prints an error: its output is in the message.
    const ScratchDir scratch("tetmesh_test");
    const std::string fake = scratch.file("fake-tetgen.sh");
    {
        std::ofstream out(fake);
        out << "#!/bin/sh\necho 'Error:  A self-intersection was detected.'\nexit 3\n";
    }
    std::filesystem::permissions(fake, std::filesystem::perms::owner_all);
    o.tetgen = fake;
    try {
        generate_tetmesh(p, o, {}, m);
        FAIL("no error for a failing tetgen");
    } catch (const ExternalToolError& e) {
        const std::string what = e.what();
        CHECK(what.find("A self-intersection was detected") != std::string::npos);
    }
}

TEST_CASE("tetmesh: .bpm files carry the tet mesh through write and read", "[tetmesh][bpm_file]") {
    REQUIRE_TETGEN();
    BpmFile file;
    file.param = fixtures::identity_parametrization(fixtures::two_cubes());
    const std::string without = write_bpm_to_memory(file);
    file.tetmesh = mesh_of(file.param);
    const std::string with = write_bpm_to_memory(file);
    CHECK(with != without);
    CHECK(write_bpm_to_memory(file) == with);  // deterministic
    const BpmFile back = read_bpm_from_memory(with, "mem");
    REQUIRE(back.tetmesh.has_value());
    const TetMesh& a = *file.tetmesh;
    const TetMesh& b = *back.tetmesh;
    CHECK(a.vertices == b.vertices);
    CHECK(a.tetrahedra == b.tetrahedra);
    CHECK(a.regions == b.regions);
    CHECK(a.faces == b.faces);
    CHECK(a.face_coarse_triangle == b.face_coarse_triangle);
    CHECK(a.face_patches == b.face_patches);
    CHECK(a.vertex_coarse_vertex == b.vertex_coarse_vertex);
    CHECK(a.vertex_parameter_points == b.vertex_parameter_points);
    CHECK(a.level == b.level);
    CHECK(b.tet_ancestor.empty());
    // Without a tet mesh nothing changes and nothing is read.
    CHECK(!read_bpm_from_memory(without, "mem").tetmesh.has_value());

    // The writer refuses an inconsistent mesh.
    BpmFile bad = file;
    bad.tetmesh->tetrahedra[3][2] = bad.tetmesh->num_vertices();
    try {
        write_bpm_to_memory(bad);
        FAIL("an inconsistent tet mesh was written");
    } catch (const OutputError& e) {
        CHECK(std::string(e.what()).find("/tetmesh/tetrahedra: entry [3, 2]") != std::string::npos);
    }
    bad = file;
    bad.tetmesh->face_patches[0] += 1;
    CHECK_THROWS_AS(write_bpm_to_memory(bad), OutputError);
}

TEST_CASE("tetmesh: the reader rejects a malformed /tetmesh group naming the dataset", "[tetmesh][bpm_file]") {
    REQUIRE_TETGEN();
    BpmFile file;
    file.param = fixtures::identity_parametrization(fixtures::cube());
    file.tetmesh = mesh_of(file.param);
    const ScratchDir scratch("tetmesh_test");
    const std::string path = scratch.file("malformed.bpm");
    auto mutate = [&](const std::function<void(hid_t)>& change) {
        write_bpm(path, file);
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
        hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
        REQUIRE(f >= 0);
        change(f);
        H5Fclose(f);
    };
    auto expect_error = [&](const std::string& text) {
        try {
            read_bpm(path);
            FAIL("a malformed file was accepted; expected: " + text);
        } catch (const InputError& e) {
            INFO(e.what());
            CHECK(std::string(e.what()).find(text) != std::string::npos);
        }
    };
    // A tetrahedron corner out of range.
    mutate([&](hid_t f) {
        hid_t ds = H5Dopen2(f, "/tetmesh/tetrahedra", H5P_DEFAULT);
        std::vector<int32_t> data(4 * file.tetmesh->tetrahedra.size());
        H5Dread(ds, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
        data[5] = 100000;
        H5Dwrite(ds, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
        H5Dclose(ds);
    });
    expect_error("/tetmesh/tetrahedra: entry [1, 1] = 100000 is out of range");
    // A region id of 0.
    mutate([&](hid_t f) {
        hid_t ds = H5Dopen2(f, "/tetmesh/regions", H5P_DEFAULT);
        std::vector<int32_t> data(file.tetmesh->regions.size());
        H5Dread(ds, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
        data[0] = 0;
        H5Dwrite(ds, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
        H5Dclose(ds);
    });
    expect_error("/tetmesh/regions: entry 0 = 0 is not a region id");
    // A face on a coarse triangle that does not exist.
    mutate([&](hid_t f) {
        hid_t ds = H5Dopen2(f, "/tetmesh/face_coarse_triangle", H5P_DEFAULT);
        std::vector<int32_t> data(file.tetmesh->faces.size());
        H5Dread(ds, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
        data[2] = -5;
        H5Dwrite(ds, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
        H5Dclose(ds);
    });
    expect_error("/tetmesh/face_coarse_triangle: entry 2 = -5 is out of range");
    // Wrong type and shape.
    mutate([&](hid_t f) {
        H5Ldelete(f, "/tetmesh/vertices", H5P_DEFAULT);
        hsize_t dims[2] = {file.tetmesh->vertices.size(), 2};
        hid_t space = H5Screate_simple(2, dims, nullptr);
        hid_t ds = H5Dcreate2(f, "/tetmesh/vertices", H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        H5Dclose(ds);
        H5Sclose(space);
    });
    expect_error("/tetmesh/vertices: expected shape (#V, 3)");
    mutate([&](hid_t f) { H5Ldelete(f, "/tetmesh/regions", H5P_DEFAULT); });
    expect_error("/tetmesh/regions: missing dataset");
    mutate([&](hid_t f) { H5Adelete_by_name(f, "/tetmesh", "level", H5P_DEFAULT); });
    expect_error("/tetmesh: attribute 'level': missing");
}

TEST_CASE("tetmesh: exports are read back by independent readers", "[tetmesh][export]") {
    REQUIRE_TETGEN();
    const Parametrization p = fixtures::identity_parametrization(fixtures::cylinder_wedges());
    const TetMesh m = mesh_of(p);
    const int64_t nt = m.num_tetrahedra(), nf = static_cast<int64_t>(m.faces.size()), nv = m.num_vertices();
    std::map<int32_t, int64_t> per_region, per_patch;
    for (int32_t r : m.regions) ++per_region[r];
    for (int32_t q : m.face_patches) ++per_patch[q];

    const ScratchDir scratch("tetmesh_test");
    const std::string msh = scratch.file("wedges.msh");
    const std::string vtu = scratch.file("wedges.vtu");
    const std::string medit = scratch.file("wedges.mesh");
    write_tetmesh(msh, m, TetMeshFormat::Msh);
    write_tetmesh(vtu, m, TetMeshFormat::Vtu);
    write_tetmesh(medit, m, TetMeshFormat::Medit);
    CHECK(tetmesh_format_from_path("a/b.MSH") == TetMeshFormat::Msh);
    CHECK(tetmesh_format_from_path("x.mesh") == TetMeshFormat::Medit);
    CHECK(!tetmesh_format_from_path("x.off"));
    CHECK_THROWS_AS(write_tetmesh(scratch.file("x.bpm"), m, TetMeshFormat::Bpm), OutputError);

    // MEDIT: parse here.
    {
        std::ifstream in(medit);
        std::string word;
        int64_t vertices = -1, tets = -1, tris = -1;
        std::map<int32_t, int64_t> regions;
        while (in >> word) {
            if (word == "Vertices") {
                in >> vertices;
                double x;
                for (int64_t i = 0; i < 4 * vertices; ++i) in >> x;
            } else if (word == "Tetrahedra") {
                in >> tets;
                for (int64_t i = 0; i < tets; ++i) {
                    int64_t a, b, c, d, r;
                    in >> a >> b >> c >> d >> r;
                    CHECK((a >= 1 && d <= nv));
                    ++regions[static_cast<int32_t>(r)];
                }
            } else if (word == "Triangles") {
                in >> tris;
            }
        }
        CHECK(vertices == nv);
        CHECK(tets == nt);
        CHECK(tris == nf);
        CHECK(regions == per_region);
    }

    std::string out;
    if (run_command("/usr/bin/python3 -c 'import sys' 2>/dev/null", out) != 0) {
        WARN("SKIPPED: /usr/bin/python3 is not available; MSH and VTU exports not re-read");
        return;
    }
    // Gmsh MSH 4.1 by a small independent Python reader (meshio is not installed here).
    const std::string reader = scratch.file("read_msh.py");
    {
        std::ofstream py(reader);
        py << R"PY(import sys
lines = open(sys.argv[1]).read().split("\n")
i = 0
def section(name):
    global i
    while lines[i] != "$" + name: i += 1
    i += 1
section("MeshFormat"); assert lines[i].split()[0] == "4.1"
section("PhysicalNames"); n = int(lines[i]); names = {}
for k in range(n):
    d, tag, name = lines[i + 1 + k].split(" ", 2); names[(int(d), int(tag))] = name.strip('"')
section("Entities"); counts = list(map(int, lines[i].split())); i += 1
phys = {}
for dim in range(4):
    for k in range(counts[dim]):
        f = lines[i].split(); i += 1
        tag = int(f[0])
        if dim == 0: nphys = int(f[4]); ph = f[5:5 + nphys]
        else: nphys = int(f[7]); ph = f[8:8 + nphys]
        phys[(dim, tag)] = [int(x) for x in ph]
section("Nodes"); nblocks, nnodes, _, _ = map(int, lines[i].split()); i += 1
coords = {}
for b in range(nblocks):
    _, _, param, cnt = map(int, lines[i].split()); i += 1
    tags = [int(lines[i + k]) for k in range(cnt)]; i += cnt
    for k in range(cnt): coords[tags[k]] = tuple(map(float, lines[i + k].split())); 
    i += cnt
section("Elements"); nblocks, nelem, _, _ = map(int, lines[i].split()); i += 1
result = {}
for b in range(nblocks):
    dim, ent, etype, cnt = map(int, lines[i].split()); i += 1
    for k in range(cnt):
        f = list(map(int, lines[i + k].split()))
        assert all(v in coords for v in f[1:])
        if etype == 4:
            a, b2, c, d = (coords[v] for v in f[1:])
            u = [b2[j] - a[j] for j in range(3)]; v = [c[j] - a[j] for j in range(3)]; w = [d[j] - a[j] for j in range(3)]
            det = u[0]*(v[1]*w[2]-v[2]*w[1]) - u[1]*(v[0]*w[2]-v[2]*w[0]) + u[2]*(v[0]*w[1]-v[1]*w[0])
            assert det > 0, "negative tetrahedron"
    i += cnt
    for p in phys[(dim, ent)]:
        assert (dim, p) in names
        result[(etype, p)] = result.get((etype, p), 0) + cnt
print(nnodes)
for (etype, p), c in sorted(result.items()): print(etype, p, c)
)PY";
    }
    REQUIRE(run_command("/usr/bin/python3 " + reader + " " + msh, out) == 0);
    std::ostringstream expected;
    expected << nv << "\n";
    for (const auto& [patch, count] : per_patch) expected << "2 " << patch + 1 << " " << count << "\n";  // physical tag = patch + 1
    for (const auto& [region, count] : per_region) expected << "4 " << region << " " << count << "\n";
    CHECK(out == expected.str());

    // VTU by VTK's own reader (python3-vtk9).
    if (run_command("/usr/bin/python3 -c 'import vtk' 2>/dev/null", out) != 0) {
        WARN("SKIPPED: python3-vtk9 is not installed; VTU export not re-read");
        return;
    }
    const std::string vtk_script = "import vtk, sys\n"
                                   "r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(sys.argv[1]); r.Update()\n"
                                   "g = r.GetOutput(); a = g.GetCellData().GetArray('region')\n"
                                   "print(g.GetNumberOfPoints(), g.GetNumberOfCells(), g.GetCellType(0), "
                                   "int(a.GetRange()[0]), int(a.GetRange()[1]))\n";
    const std::string vtk_reader = scratch.file("read_vtu.py");
    std::ofstream(vtk_reader) << vtk_script;
    REQUIRE(run_command("/usr/bin/python3 " + vtk_reader + " " + vtu + " 2>&1", out) == 0);
    CHECK(out == std::to_string(nv) + " " + std::to_string(nt) + " 10 1 3\n");
}

TEST_CASE("tetmesh: TetGen's optimisation aims below max_dihedral_degrees (-o/), 0 = TetGen's default",
          "[tetmesh]") {
    REQUIRE_TETGEN();
    const Parametrization p = fixtures::identity_parametrization(fixtures::cube(2));
    TetMesh m;
    TetMeshOptions o;
    CHECK(generate_tetmesh(p, o, Context{}, m).tetgen_command.find(" -o/150 ") != std::string::npos);
    o.max_dihedral_degrees = 0;
    CHECK(generate_tetmesh(p, o, Context{}, m).tetgen_command.find("-o/") == std::string::npos);
    o.max_dihedral_degrees = 60;  // below a right angle: no tetrahedron could meet it
    CHECK_THROWS_AS(generate_tetmesh(p, o, Context{}, m), OptionError);
    o.max_dihedral_degrees = 180;
    CHECK_THROWS_AS(generate_tetmesh(p, o, Context{}, m), OptionError);
}
