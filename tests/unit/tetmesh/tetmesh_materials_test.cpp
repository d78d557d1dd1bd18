// Tests of patch information (bpm/patch_info.h) and region materials
// (bpm/tetmesh_materials.h): the name conventions, the file-per-material and fused-interface
// rules, the resolution of region materials (oriented, unordered, conflicts, user names),
// the /patch_info and /tetmesh material datasets in .bpm files, and the exports.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "bpm/bpm_file.h"
#include "bpm/errors.h"
#include "bpm/patch_info.h"
#include "bpm/surface_io.h"
#include "bpm/write_tetmesh.h"
#include "bpm/tetmesh.h"
#include "bpm/write_tetmesh.h"
#include "bpm/tetmesh_materials.h"
#include "fixtures_surfaces.h"
#include "test_support.h"

using namespace bpm;
namespace fs = std::filesystem;

namespace {

// Two tetrahedra sharing the face (0, 1, 2): A = (0,1,2,3) above it, B = (0,2,1,4) below
// (both positively oriented), region 1 = A, region 2 = B; faces = the 7 triangles of the
// surface, oriented outwards, the shared one (0, 2, 1) with its normal -z into B.
// Patches: 0 = A's outside, 1 = B's outside, 2 = the shared face.
TetMesh two_tets() {
    TetMesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.25, 0.25, -1}};
    m.tetrahedra = {{0, 1, 2, 3}, {0, 2, 1, 4}};
    m.regions = {1, 2};
    m.faces = {{0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {0, 4, 1}, {1, 4, 2}, {2, 4, 0}, {0, 2, 1}};
    m.face_coarse_triangle = {0, 1, 2, 3, 4, 5, 6};
    m.face_patches = {0, 0, 0, 1, 1, 1, 2};
    m.vertex_coarse_vertex = {0, 1, 2, 3, 4};
    return m;
}

std::vector<std::string> region_names(const TetMesh& m) {
    std::vector<std::string> out;
    for (int32_t id : m.region_material) out.push_back(m.material_names[size_t(id - 1)]);
    return out;
}

// Meshes `s` with TetGen, assigns the materials `patch_info` gives, and returns the
// region names sorted (regions are numbered as TetGen found them).
MaterialResult mesh_and_assign(const Surface& s, const std::vector<PatchInfo>& patch_info,
                               std::vector<std::string>& sorted_names) {
    TetMesh m;
    (void)generate_tetmesh(make_identity_parametrization(s), TetMeshOptions{}, Context{}, m);
    const MaterialResult r = assign_materials(m, patch_info);
    sorted_names = region_names(m);
    std::sort(sorted_names.begin(), sorted_names.end());
    return r;
}

}  // namespace

TEST_CASE("patch names: only the documented conventions give materials", "[materials]") {
    using P = std::pair<std::string, std::string>;
    CHECK(materials_from_patch_name("liver|Exterior") == P{"liver", "Exterior"});
    CHECK(materials_from_patch_name(" soft tissue | bone ") == P{"soft tissue", "bone"});
    CHECK(materials_from_patch_name("pair_bone_muscle") == P{"bone", "muscle"});
    CHECK(materials_from_patch_name("interface_1_2") == P{"1", "2"});
    // Where one material would end is not known, or there is no pair at all.
    CHECK(!materials_from_patch_name("pair_soft_tissue_bone"));
    CHECK(!materials_from_patch_name("a|b|c"));
    CHECK(!materials_from_patch_name("A|A"));
    CHECK(!materials_from_patch_name("|A"));
    CHECK(!materials_from_patch_name("patch_3"));
    CHECK(!materials_from_patch_name("outer_boundary"));
}

TEST_CASE("materials: a face's front region is the tet its normal points into (hand-made two tetrahedra)",
          "[materials]") {
    TetMesh m = two_tets();
    // As an Amira file says it: front = OuterRegion, back = InnerRegion.
    const std::vector<PatchInfo> oriented = {{0, "A|Exterior", "Exterior", "A", true},
                                             {1, "B|Exterior", "Exterior", "B", true},
                                             {2, "A|B", "B", "A", true}};
    MaterialResult r = assign_materials(m, oriented);
    CHECK(region_names(m) == std::vector<std::string>{"A", "B"});
    CHECK(m.material_names == std::vector<std::string>{"A", "B"});
    CHECK(r.regions_from_input == 2);
    CHECK(r.problems.empty());
    CHECK(!r.orientation_ignored);
    CHECK(find_material_inconsistency(m).empty());
    CHECK(tet_materials(m) == std::vector<int32_t>{1, 2});

    SECTION("unordered pairs are resolved through the exterior and propagation") {
        std::vector<PatchInfo> unordered = oriented;
        for (PatchInfo& p : unordered) {
            std::swap(p.front, p.back);  // the order must not matter
            p.oriented = false;
        }
        r = assign_materials(m, unordered);
        CHECK(region_names(m) == std::vector<std::string>{"A", "B"});
        CHECK(r.problems.empty());
    }
    SECTION("reversed normals: the oriented reading conflicts, the unordered one is kept") {
        std::vector<PatchInfo> reversed = oriented;
        for (PatchInfo& p : reversed) std::swap(p.front, p.back);
        r = assign_materials(m, reversed);
        CHECK(r.orientation_ignored);
        CHECK(region_names(m) == std::vector<std::string>{"A", "B"});
        CHECK(r.problems.empty());
    }
    SECTION("a real conflict is reported and the region keeps a name of its own") {
        std::vector<PatchInfo> bad = oriented;
        bad[2] = {2, "C|C", "C", "C", true};  // says region 1 is C, patch 0 says A
        r = assign_materials(m, bad);
        REQUIRE(r.problems.size() == 2);
        CHECK(r.problems[0] == "region 1: its sides say A and C (conflict); named region_1");
        CHECK(region_names(m)[0] == "region_1");
    }
    SECTION("without information every region is its own material region_<r>; the user's names win") {
        r = assign_materials(m, {});
        CHECK(region_names(m) == std::vector<std::string>{"region_1", "region_2"});
        CHECK(r.problems.empty());
        MaterialOptions user;
        user.region_names = {{2, "marrow"}};
        r = assign_materials(m, oriented, user);
        CHECK(region_names(m) == std::vector<std::string>{"A", "marrow"});
        CHECK(r.regions_from_user == 1);
        user.region_names = {{3, "x"}};
        CHECK_THROWS_AS(assign_materials(m, oriented, user), OptionError);
    }
}

TEST_CASE("materials: a patch whose weak exterior side lies in a meshed region is named after it (hand-made "
          "two tetrahedra)", "[materials]") {
    // Patch 2 as the reader gives a file nested in another ("A|exterior": every file's outer
    // side says exterior), though its front is region 2 = B. The regions were right; the
    // patch kept "A|exterior" in /patch_info and the MSH physical names.
    TetMesh m = two_tets();
    std::vector<PatchInfo> infos = {{0, "A|exterior", "exterior", "A", true},
                                    {1, "B|exterior", "exterior", "B", true},
                                    {2, "A|exterior", "exterior", "A", true}};
    const MaterialResult r = assign_materials(m, infos);
    REQUIRE(region_names(m) == std::vector<std::string>{"A", "B"});
    CHECK(r.problems.empty());
    CHECK(name_patches_after_regions(m, infos) == 1);
    CHECK(infos[0] == PatchInfo{0, "A|exterior", "exterior", "A", true});  // the outside is exterior
    CHECK(infos[1] == PatchInfo{1, "B|exterior", "exterior", "B", true});
    CHECK(infos[2] == PatchInfo{2, "A|B", "B", "A", true});
    CHECK(name_patches_after_regions(m, infos) == 0);  // nothing left to do

    SECTION("a name of the user's own stays; unordered pairs and patches without materials are left alone") {
        std::vector<PatchInfo> named = {{0, "skin", "exterior", "A", true},
                                        {1, "B|exterior", "exterior", "B", false},
                                        {2, "lid", "Exterior", "A", true}};
        CHECK(name_patches_after_regions(m, named) == 1);
        CHECK(named[0] == PatchInfo{0, "skin", "exterior", "A", true});
        CHECK(named[1] == PatchInfo{1, "B|exterior", "exterior", "B", false});
        CHECK(named[2] == PatchInfo{2, "lid", "B", "A", true});
    }
    SECTION("a mesh without materials changes nothing") {
        TetMesh plain = two_tets();
        std::vector<PatchInfo> kept = infos;
        kept[2] = {2, "A|exterior", "exterior", "A", true};
        CHECK(name_patches_after_regions(plain, kept) == 0);
        CHECK(kept[2] == PatchInfo{2, "A|exterior", "exterior", "A", true});
    }
}

TEST_CASE("materials: the HyperSurface fixture's InnerRegion/OuterRegion name the regions", "[materials][surf]") {
    // The two-tetrahedra surface of read_surf_test as an ASCII HyperSurface.
    const std::string surf =
        "# HyperSurface 0.1 ASCII\n\nParameters {\n    Materials { Exterior { Id 0 } A { Id 1 } B { Id 2 } }\n}\n\n"
        "Vertices 5\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.25 0.25 -1\nNBranchingPoints 0\nNVerticesOnCurves 0\n"
        "BoundaryCurves 0\nPatches 3\n"
        "{\nInnerRegion A\nOuterRegion Exterior\nBoundaryID 0\nBranchingPoints 0\n\nTriangles 3\n1 2 4\n2 3 4\n3 1 4\n}\n"
        "{\nInnerRegion B\nOuterRegion Exterior\nBoundaryID 0\nBranchingPoints 0\n\nTriangles 3\n1 5 2\n2 5 3\n3 5 1\n}\n"
        "{\nInnerRegion A\nOuterRegion B\nBoundaryID 0\nBranchingPoints 0\n\nTriangles 1\n1 3 2\n}\n";
    SurfaceReadReport report;
    const Surface s = read_surface_from_memory(surf, SurfaceFormat::Surf, "two.surf", {}, &report);
    REQUIRE(report.patch_info.size() == 3);
    CHECK(report.patch_info[2] == PatchInfo{2, "A|B", "B", "A", true});
    TetMesh m = two_tets();
    REQUIRE(std::vector<Tri>(s.triangles) == m.faces);
    const MaterialResult r = assign_materials(m, report.patch_info);
    CHECK(region_names(m) == std::vector<std::string>{"A", "B"});
    CHECK(r.problems.empty());
}

TEST_CASE("materials: one file per material, interfaces fused, name the materials after the files", "[materials]") {
    const test_support::ScratchDir scratch("materials_test");
    const fs::path& dir = scratch.path;
    // The two cubes of fixtures::two_cubes as two closed surfaces, left.off and right.off.
    const Surface both = fixtures::two_cubes();
    for (const auto& [name, label] : {std::pair{"left", 1}, std::pair{"right", 2}}) {
        Surface part;
        part.vertices = both.vertices;
        for (size_t t = 0; t < both.triangles.size(); ++t) {
            const int32_t p = both.patches[t];
            if (p == label) part.triangles.push_back(both.triangles[t]);
            if (p == 102) {  // the shared square, outward for this cube (its normal points from 2 to 1)
                Tri tri = both.triangles[t];
                if (label == 1) std::swap(tri[1], tri[2]);
                part.triangles.push_back(tri);
            }
        }
        part.patches.assign(part.triangles.size(), 0);
        drop_unreferenced_vertices(part);
        write_surface((dir / (std::string(name) + ".off")).string(), part);
    }
    SurfaceReadOptions options;
    options.merge_duplicate_vertices = true;
    options.merge_duplicate_triangles = true;
    SurfaceReadReport report;
    const Surface s = read_surfaces({(dir / "left.off").string(), (dir / "right.off").string()}, options, &report);
    REQUIRE(report.patch_info.size() == 3);
    CHECK(report.patch_info[0] == PatchInfo{0, "left|exterior", "exterior", "left", true});
    CHECK(report.patch_info[1] == PatchInfo{1, "right|exterior", "exterior", "right", true});
    CHECK(report.patch_info[2] == PatchInfo{2, "left|right", "right", "left", true});

    // One file alone encloses its material too; standard input and memory say nothing.
    SurfaceReadReport one;
    (void)read_surface((dir / "left.off").string(), {}, &one);
    CHECK(one.patch_info == std::vector<PatchInfo>{{0, "left|exterior", "exterior", "left", true}});

    REQUIRE_TETGEN();
    std::vector<std::string> names;
    const MaterialResult r = mesh_and_assign(s, report.patch_info, names);
    REQUIRE(names.size() == 2);
    CHECK(names == std::vector<std::string>{"left", "right"});
    CHECK(r.problems.empty());
}

TEST_CASE("materials: a file nested in another lies in the enclosing file's material, not in exterior",
          "[materials]") {
    // outer.off = a cube of edge 3, inner.off = a unit cube inside it (the nested spheres of
    // bench/dune_torsion.py --nested-spheres: the shell was named "exterior", since every
    // file's outer side says exterior).
    const test_support::ScratchDir scratch("materials_nested_test");
    const fs::path& dir = scratch.path;
    Surface outer = fixtures::cube(), inner = fixtures::cube();
    for (Vec3& v : outer.vertices) v = {3 * v[0] - 1, 3 * v[1] - 1, 3 * v[2] - 1};
    write_surface((dir / "outer.off").string(), outer);
    write_surface((dir / "inner.off").string(), inner);
    SurfaceReadReport report;
    const Surface s = read_surfaces({(dir / "outer.off").string(), (dir / "inner.off").string()}, {}, &report);
    REQUIRE(report.patch_info.size() == 2);
    CHECK(report.patch_info[1] == PatchInfo{1, "inner|exterior", "exterior", "inner", true});

    REQUIRE_TETGEN();
    std::vector<std::string> names;
    const MaterialResult r = mesh_and_assign(s, report.patch_info, names);
    REQUIRE(names.size() == 2);
    CHECK(names == std::vector<std::string>{"inner", "outer"});
    CHECK(r.problems.empty());
    CHECK_FALSE(r.orientation_ignored);

    // Once meshed, the inner file's patch is named after the regions on its two sides.
    TetMesh m;
    (void)generate_tetmesh(make_identity_parametrization(s), TetMeshOptions{}, Context{}, m);
    (void)assign_materials(m, report.patch_info);
    std::vector<PatchInfo> infos = report.patch_info;
    CHECK(name_patches_after_regions(m, infos) == 1);
    CHECK(infos[0] == PatchInfo{0, "outer|exterior", "exterior", "outer", true});
    CHECK(infos[1] == PatchInfo{1, "inner|outer", "outer", "inner", true});
}

TEST_CASE("materials: .bpm files carry /patch_info and the region materials, older files read without them",
          "[materials][bpm_file]") {
    REQUIRE_TETGEN();
    BpmFile file;
    file.param = make_identity_parametrization(fixtures::two_cubes());
    const std::string plain = write_bpm_to_memory(file);
    file.patch_info = {{1, "left|exterior", "exterior", "left", true},
                       {2, "right|exterior", "exterior", "right", true},
                       {102, "pair_left_right", "left", "right", false}};
    TetMesh m;
    (void)generate_tetmesh(file.param, TetMeshOptions{}, Context{}, m);
    const TetMesh without_materials = m;
    const MaterialResult r = assign_materials(m, file.patch_info);
    CHECK(r.problems.empty());
    file.tetmesh = m;
    const BpmFile back = read_bpm_from_memory(write_bpm_to_memory(file), "mem");
    CHECK(back.patch_info == file.patch_info);
    REQUIRE(back.tetmesh);
    CHECK(back.tetmesh->region_material == m.region_material);
    CHECK(back.tetmesh->material_names == m.material_names);
    // A file without the new items (as 1.2 writers wrote them) reads with none.
    const BpmFile old = read_bpm_from_memory(plain, "old");
    CHECK(old.patch_info.empty());
    file.tetmesh = without_materials;
    file.patch_info.clear();
    const BpmFile old_mesh = read_bpm_from_memory(write_bpm_to_memory(file), "old mesh");
    REQUIRE(old_mesh.tetmesh);
    CHECK(old_mesh.tetmesh->region_material.empty());
    CHECK(old_mesh.tetmesh->material_names.empty());

    // The writer refuses what the reader would reject.
    file.tetmesh = m;
    file.tetmesh->region_material[0] = 3;
    CHECK_THROWS_WITH(write_bpm_to_memory(file), Catch::Contains("/tetmesh/region_material: entry 0 = 3"));
    file.tetmesh = m;
    file.tetmesh->material_names[1] = file.tetmesh->material_names[0];
    CHECK_THROWS_WITH(write_bpm_to_memory(file), Catch::Contains("is repeated"));
    file.tetmesh = m;
    file.patch_info = {{1, "a", "", "", true}, {1, "b", "", "", true}};
    CHECK_THROWS_WITH(write_bpm_to_memory(file), Catch::Contains("patch 1 is described twice"));
}

TEST_CASE("materials: MSH export names physical volumes by material and keeps the patch names, which read back",
          "[materials][export]") {
    TetMesh m = two_tets();
    // Completed so that the writers accept it.
    m.vertex_parameter_points = {{0, {1, 0, 0}}, {0, {0, 1, 0}}, {0, {0, 0, 1}}, {0, {0, 0, 1}}, {3, {0, 1, 0}}};
    const std::vector<PatchInfo> infos = {{0, "A|Exterior", "Exterior", "A", true},
                                          {1, "B|Exterior", "Exterior", "B", true},
                                          {2, "pair_A_B", "A", "B", false}};
    MaterialOptions user;
    user.region_names = {{2, "A"}};  // both regions one material: one physical volume
    assign_materials(m, infos, user);
    const std::string msh = write_tetmesh_to_string(m, TetMeshFormat::Msh, infos);
    // Surface physical tags are patch + 1 (Gmsh takes 0 as "no physical group").
    CHECK(msh.find("$PhysicalNames\n4\n2 1 \"A|Exterior\"\n2 2 \"B|Exterior\"\n2 3 \"pair_A_B\"\n3 1 \"A\"\n") !=
          std::string::npos);
    assign_materials(m, infos);
    const std::string msh2 = write_tetmesh_to_string(m, TetMeshFormat::Msh, infos);
    CHECK(msh2.find("3 1 \"A\"\n3 2 \"B\"\n$EndPhysicalNames") != std::string::npos);
    SurfaceReadOptions options;
    options.drop_unreferenced_vertices = true;
    SurfaceReadReport report;
    const Surface s = read_surface_from_memory(msh2, SurfaceFormat::Msh, "mesh.msh", options, &report);
    // Read back, the patches are the same ($BpmPatchIds: patch = physical tag - 1).
    CHECK(msh2.find("$EndElements\n$BpmPatchIds\n1\n$EndBpmPatchIds\n") != std::string::npos);
    CHECK(s.patches == m.face_patches);
    REQUIRE(report.patch_info.size() == 3);
    CHECK(report.patch_info[0] == PatchInfo{0, "A|Exterior", "A", "Exterior", false});
    CHECK(report.patch_info[2] == PatchInfo{2, "pair_A_B", "A", "B", false});
    // And they name the regions again.
    TetMesh again = two_tets();
    assign_materials(again, report.patch_info);
    CHECK(region_names(again) == std::vector<std::string>{"A", "B"});

    const std::string vtu = write_tetmesh_to_string(m, TetMeshFormat::Vtu);
    CHECK(vtu.find("Name=\"material\"") != std::string::npos);
    CHECK(vtu.find("String") == std::string::npos);  // no string arrays: meshio 5 refuses them
    const std::string medit = write_tetmesh_to_string(m, TetMeshFormat::Medit);
    CHECK(medit.find("# material 2 B\n") != std::string::npos);
    CHECK(medit.find("1 3 2 5 2\n") != std::string::npos);  // tet B with reference 2
}

TEST_CASE("MSH reader: $PhysicalNames name patches (2.2 too) and a name without quotes is refused with its line",
          "[materials][surface_io]") {
    const std::string head = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n2 7 \"pair_liver_exterior\"\n";
    const std::string rest =
        "3 1 \"liver\"\n$EndPhysicalNames\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n"
        "$Elements\n1\n1 2 2 7 1 1 2 3\n$EndElements\n";
    SurfaceReadReport report;
    const Surface s =
        read_surface_from_memory(head + "2 8 \"outer wall\"\n" + rest, SurfaceFormat::Msh, "seg.msh", {}, &report);
    CHECK(s.patches == std::vector<int32_t>{7});
    // Volume names (dimension 3) are not patches.
    REQUIRE(report.patch_info.size() == 2);
    CHECK(report.patch_info[0] == PatchInfo{7, "pair_liver_exterior", "liver", "exterior", false});
    CHECK(report.patch_info[1] == PatchInfo{8, "outer wall", "", "", true});
    CHECK_THROWS_WITH(read_surface_from_memory(head + "2 8 outer\n" + rest, SurfaceFormat::Msh, "seg.msh"),
                      Catch::Contains("line 7: expected a quoted name after physical tag 8"));
}
