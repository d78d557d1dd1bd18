// bpm-info's summary (bpm/bpm_info.h): the feature structure of the coarse surface, phi's
// distortion as bpm-check measures it, and the outline read (only what is reported) that
// must say exactly what a full read_bpm says.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>
#include <limits>
#include <string>

#include "bpm/bpm_file.h"
#include "bpm/bpm_info.h"
#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/simplify.h"
#include "bpm/surface_topology.h"
#include "fixtures_phi.h"
#include "fixtures_surfaces.h"

using namespace bpm;
namespace fs = std::filesystem;

namespace {

// The cube (res x res squares per face) simplified to its 8 corners.
BpmFile simplified_cube(int res) {
    BpmFile file;
    SimplifyOptions options;
    options.target_vertices = 8;
    simplify(fixtures::cube(res), options, Context{}, file.param);
    file.units = "m";
    file.provenance.push_back({"bpm-simplify", "test", "bpm-simplify cube.off --vertices 8", ""});
    return file;
}

struct TempDir {
    fs::path path = fs::temp_directory_path() / ("bpm_info_test_" + std::to_string(::getpid()));
    TempDir() { fs::create_directories(path); }
    ~TempDir() { fs::remove_all(path); }
};

void check_same(const BpmInfo& a, const BpmInfo& b) {
    CHECK(a.format_version.major == b.format_version.major);
    CHECK(a.format_version.minor == b.format_version.minor);
    CHECK(a.units == b.units);
    CHECK(a.original_vertices == b.original_vertices);
    CHECK(a.original_triangles == b.original_triangles);
    CHECK(a.coarse_vertices == b.coarse_vertices);
    CHECK(a.coarse_triangles == b.coarse_triangles);
    CHECK(a.phi_nodes == b.phi_nodes);
    CHECK(a.phi_pieces == b.phi_pieces);
    CHECK(a.original_point_data == b.original_point_data);
    REQUIRE(a.patches.size() == b.patches.size());
    for (size_t i = 0; i < a.patches.size(); ++i) {
        CHECK(a.patches[i].id == b.patches[i].id);
        CHECK(a.patches[i].original_triangles == b.patches[i].original_triangles);
        CHECK(a.patches[i].coarse_triangles == b.patches[i].coarse_triangles);
    }
    CHECK(a.materials == b.materials);
    CHECK(a.features.feature_vertices == b.features.feature_vertices);
    CHECK(a.features.feature_lines == b.features.feature_lines);
    CHECK(a.features.crease_edges == b.features.crease_edges);
    CHECK(a.simplification_steps == b.simplification_steps);
    REQUIRE(a.provenance.size() == b.provenance.size());
    for (size_t i = 0; i < a.provenance.size(); ++i) CHECK(a.provenance[i].arguments == b.provenance[i].arguments);
    CHECK(a.tetmesh.has_value() == b.tetmesh.has_value());
}

}  // namespace

TEST_CASE("bpm-info: the cube simplified to 8 vertices has 8 feature vertices and 12 crease lines",
          "[info][features]") {
    const BpmFile file = simplified_cube(4);
    REQUIRE(file.param.coarse.num_vertices() == 8);
    const BpmFeatureSummary f = summarize_bpm(file).features;
    CHECK(f.feature_angle_degrees == 60.0);
    CHECK(f.crease_edges == 12);  // the cube's edges; the face diagonals are flat
    CHECK(f.boundary_edges == 0);
    CHECK(f.non_manifold_edges == 0);
    CHECK(f.interface_edges == 0);
    CHECK(f.feature_edges == 12);
    CHECK(f.feature_vertices == 8);
    CHECK(f.feature_lines == 12);
    CHECK(f.feature_loops == 0);
    // Creases are geometry: above the cube's 90 degrees there are none.
    BpmInfoOptions flat;
    flat.feature_angle_degrees = 95;
    const BpmFeatureSummary none = summarize_bpm(file, flat).features;
    CHECK(none.feature_edges == 0);
    CHECK(none.feature_vertices == 0);
    CHECK(none.feature_lines == 0);
}

TEST_CASE("bpm-info: a long shallow crease counts as the simplifier counts it", "[info][features][chains]") {
    // The lens's rim: 48 edges 27.5 degrees sharp, below the feature angle, one long even
    // line: a crease by the chain rule bpm-simplify uses (its default), one closed line.
    const Surface lens = fixtures::ridged_lens(48, 12, 20.0);
    const BpmFeatureSummary f = summarize_features(lens);
    CHECK(f.crease_chain_angle_degrees == 20.0);
    CHECK(f.crease_edges == 48);
    CHECK(f.chain_crease_edges == 48);
    CHECK(f.feature_lines == 1);
    CHECK(f.feature_loops == 1);
    const BpmFeatureSummary off = summarize_features(lens, 60.0, 180.0);
    CHECK(off.crease_edges == 0);
    CHECK(off.chain_crease_edges == 0);
}

TEST_CASE("bpm-info: angles and lengths out of range are refused as the simplifier refuses them", "[info][features]") {
    // A negative or NaN angle made every sheet edge a crease (or none) without a word; the
    // library call names the option, as SimplifyOptions' checks do.
    const Surface lens = fixtures::ridged_lens(48, 12, 20.0);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_AS(summarize_features(lens, -1.0), OptionError);
    CHECK_THROWS_AS(summarize_features(lens, 181.0), OptionError);
    CHECK_THROWS_AS(summarize_features(lens, nan), OptionError);
    CHECK_THROWS_AS(summarize_features(lens, 60.0, -5.0), OptionError);
    CHECK_THROWS_AS(summarize_features(lens, 60.0, nan), OptionError);
    CHECK_THROWS_AS(summarize_features(lens, 60.0, 20.0, 1.5), OptionError);
    CHECK_THROWS_AS(summarize_features(lens, 60.0, 20.0, -0.1), OptionError);
    CHECK_THROWS_WITH(summarize_features(lens, 60.0, 20.0, 1.5), Catch::Contains("crease_chain_length"));
    CHECK_NOTHROW(summarize_features(lens, 180.0, 180.0, 1.0));
    CHECK_NOTHROW(summarize_features(lens, 0.0, 0.0, 0.0));
    // read_bpm_info refuses them before it opens the file (this one does not exist).
    BpmInfoOptions bad;
    bad.crease_chain_angle_degrees = -1;
    CHECK_THROWS_AS(read_bpm_info("/nonexistent/bpm-info-options.bpm", bad), OptionError);
}

TEST_CASE("bpm-info: feature edges of every kind, lines and loops on fixtures", "[info][features]") {
    SECTION("a flat disk: its boundary is one closed line without feature vertices") {
        const BpmFeatureSummary f = summarize_features(fixtures::disk(4));
        CHECK(f.boundary_edges == 16);
        CHECK(f.crease_edges == 0);
        CHECK(f.feature_vertices == 0);
        CHECK(f.feature_lines == 1);
        CHECK(f.feature_loops == 1);
    }
    SECTION("two cubes: the shared square's 4 edges have 3 sheets, the box's 16 edges are creases") {
        const Surface s = fixtures::two_cubes(1);
        const BpmFeatureSummary hard = summarize_features(s, 180);
        CHECK(hard.non_manifold_edges == 4);
        CHECK(hard.crease_edges == 0);
        CHECK(hard.feature_vertices == 0);
        CHECK(hard.feature_lines == 1);
        CHECK(hard.feature_loops == 1);
        const BpmFeatureSummary f = summarize_features(s, 60);
        CHECK(f.non_manifold_edges == 4);
        CHECK(f.crease_edges == 16);
        // 8 corners of the box, and the square's 4 corners, where two creases meet its line.
        CHECK(f.feature_vertices == 12);
        CHECK(f.feature_lines == 20);
        CHECK(f.feature_loops == 0);
    }
    SECTION("without creases the counts are bpm-check's (surface_topology.h)") {
        for (const Surface& s : {fixtures::octants(1), fixtures::hourglass(8), fixtures::cylinder_wedges(12, 2),
                                 fixtures::moebius(16), fixtures::two_cubes(2), fixtures::disk(3)}) {
            const SurfaceTopology t = compute_topology(s);
            const BpmFeatureSummary f = summarize_features(s, 180);
            INFO(describe_topology(t));
            CHECK(f.feature_vertices == int64_t(t.feature_vertices.size()));
            CHECK(f.feature_lines == int64_t(t.feature_lines.size()));
            int64_t loops = 0;
            for (const FeatureLine& line : t.feature_lines) loops += line.closed;
            CHECK(f.feature_loops == loops);
        }
    }
}

TEST_CASE("bpm-info: phi's distortion is bpm-check's, and only measured when asked for", "[info][distortion]") {
    const BpmFile file = simplified_cube(6);
    CHECK_FALSE(summarize_bpm(file).distortion.has_value());
    BpmInfoOptions options;
    options.distortion = true;
    const BpmInfo info = summarize_bpm(file, options);
    REQUIRE(info.distortion.has_value());
    const BpmDistortionSummary& d = *info.distortion;
    const CheckResult check = check_distortion(file.param);
    CHECK(d.pieces == file.param.num_pieces());
    CHECK(d.pieces == check.count("pieces"));
    CHECK(d.pieces_turned_over_60_degrees == check.count("pieces_turned_over_60_degrees"));
    CHECK(d.pieces_turned_over_90_degrees == check.count("pieces_turned_over_90_degrees"));
    for (const WorstValue& m : check.measures) {
        if (m.name == "area_squeeze_max") CHECK(d.area_squeeze_max == m.value);
        if (m.name == "area_squeeze_p99") CHECK(d.area_squeeze_p99 == m.value);
        if (m.name == "normal_deviation_degrees_max") CHECK(d.normal_deviation_degrees_max == m.value);
        if (m.name == "normal_deviation_degrees_p50") CHECK(d.normal_deviation_degrees_p50 == m.value);
    }
    // The cube's coarse faces are its faces: phi maps each flat onto the original.
    CHECK(d.normal_deviation_degrees_max < 1e-6);
    CHECK(d.pieces_turned_over_60_degrees == 0);
    CHECK(d.area_squeeze_p50 >= 1.0);

    // The identity parametrization is an isometry.
    BpmFile identity;
    identity.param = fixtures::identity_parametrization(fixtures::torus());
    const BpmDistortionSummary id = *summarize_bpm(identity, options).distortion;
    CHECK(id.pieces == identity.param.num_pieces());
    CHECK(id.area_squeeze_max == Approx(1.0));
    CHECK(id.normal_deviation_degrees_max < 1e-4);  // acos near 1: about 1e-6 degrees of rounding
}

TEST_CASE("bpm-info reads only what it reports, and says what a full read says", "[info]") {
    TempDir dir;
    BpmFile file = simplified_cube(4);
    const size_t nv0 = file.param.original.vertices.size();
    file.param.original.vertex_data.push_back({"temperature", 1, std::vector<double>(nv0, 3.0)});
    const std::string path = (dir.path / "cube.bpm").string();
    write_bpm(path, file);

    const BpmInfo outline = read_bpm_info(path);
    const BpmInfo full = summarize_bpm(read_bpm(path));
    check_same(outline, full);
    CHECK(outline.file == path);
    CHECK(outline.file_bytes == int64_t(fs::file_size(path)));
    CHECK(outline.original_point_data == std::vector<std::string>{"temperature"});
    CHECK(outline.features.feature_vertices == 8);
    CHECK_FALSE(outline.distortion.has_value());

    BpmInfoOptions options;
    options.distortion = true;
    const BpmInfo measured = read_bpm_info(path, options);
    check_same(measured, outline);
    REQUIRE(measured.distortion.has_value());
    CHECK(measured.distortion->pieces == file.param.num_pieces());
}

TEST_CASE("bpm-info's outline read refuses what read_bpm refuses in what it reads", "[info]") {
    TempDir dir;
    const std::string bytes = write_bpm_to_memory(test::make_two_triangles_example());
    const std::string cut = (dir.path / "cut.bpm").string();
    {
        std::FILE* f = std::fopen(cut.c_str(), "wb");
        REQUIRE(f);
        std::fwrite(bytes.data(), 1, bytes.size() / 2, f);
        std::fclose(f);
    }
    CHECK_THROWS_AS(read_bpm_info(cut), InputError);
    CHECK_THROWS_AS(read_bpm_info((dir.path / "missing.bpm").string()), InputError);
}
