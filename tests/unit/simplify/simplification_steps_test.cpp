// The record of simplification steps (bpm/simplification_steps.h): what the simplifier
// records, the optional /simplification_steps group of format 1.1 (round trip,
// compatibility with 1.0 files, malformed groups), spec/bpm-format.md §10.1.

#include <hdf5.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <functional>
#include <string>
#include <vector>

#include "bpm/bpm_file.h"
#include "bpm/errors.h"
#include "bpm/simplify.h"
#include "fixtures_hdf5.h"
#include "fixtures_surfaces.h"

using namespace bpm;
using Image = bpm::test::Hdf5Image;
using bpm::test::require_input_error;

namespace {

BpmFile simplified(const Surface& s, double ratio, bool record) {
    SimplifyOptions o;
    o.target_ratio = ratio;
    o.record_steps = record;
    BpmFile f;
    SimplifyResult r = simplify(s, o, Context{}, f.param);
    f.simplification_steps = std::move(r.steps);
    f.provenance.push_back({"bpm-simplify", "test", "simplify", ""});
    return f;
}

}  // namespace

TEST_CASE("simplify records one step per removal, only when asked", "[steps]") {
    const Surface torus = fixtures::torus(16, 12);
    const BpmFile without = simplified(torus, 0.2, false);
    CHECK_FALSE(without.simplification_steps);
    const BpmFile with = simplified(torus, 0.2, true);
    REQUIRE(with.simplification_steps);
    const SimplificationSteps& st = *with.simplification_steps;
    CHECK(st.num_steps() == torus.num_vertices() - with.param.coarse.num_vertices());
    CHECK(st.triangle_offsets.size() == st.vertex.size() + 1);
    CHECK(st.triangle_patches.size() == st.triangles.size());
    // Recording does not change the result.
    CHECK(with.param.coarse.triangles == without.param.coarse.triangles);
    // Removed vertices are distinct and none of them is in the coarse surface.
    std::vector<int32_t> removed = st.vertex;
    std::sort(removed.begin(), removed.end());
    CHECK(std::adjacent_find(removed.begin(), removed.end()) == removed.end());
    for (int32_t v : with.param.coarse_vertex_origin)
        CHECK_FALSE(std::binary_search(removed.begin(), removed.end(), v));
    // A torus vertex of degree d is replaced by d - 2 triangles: 2 fewer triangles per step.
    CHECK(st.num_triangles() > 0);
    CHECK(torus.num_triangles() - 2 * st.num_steps() == with.param.coarse.num_triangles());
}

TEST_CASE("the record round-trips through the file, and files without one are unchanged", "[steps][format]") {
    const BpmFile f = simplified(fixtures::two_cubes(3), 0.3, true);
    const std::string bytes = write_bpm_to_memory(f);
    const BpmFile g = read_bpm_from_memory(bytes, "mem");
    REQUIRE(g.simplification_steps);
    CHECK(g.simplification_steps->vertex == f.simplification_steps->vertex);
    CHECK(g.simplification_steps->triangle_offsets == f.simplification_steps->triangle_offsets);
    CHECK(g.simplification_steps->triangles == f.simplification_steps->triangles);
    CHECK(g.simplification_steps->triangle_patches == f.simplification_steps->triangle_patches);
    CHECK(write_bpm_to_memory(g) == bytes);  // deterministic, and nothing lost

    BpmFile plain = f;
    plain.simplification_steps.reset();
    const std::string plain_bytes = write_bpm_to_memory(plain);
    Image im(plain_bytes);
    CHECK_FALSE(im.exists("/simplification_steps"));
    CHECK_FALSE(read_bpm_from_memory(plain_bytes, "plain").simplification_steps);

    SECTION("an empty record (no removal) is kept as such") {
        BpmFile e = plain;
        e.simplification_steps = SimplificationSteps{};
        const BpmFile r = read_bpm_from_memory(write_bpm_to_memory(e), "empty");
        REQUIRE(r.simplification_steps);
        CHECK(r.simplification_steps->num_steps() == 0);
        CHECK(r.simplification_steps->triangle_offsets == std::vector<int64_t>{0});
    }
    SECTION("a format 1.0 file (no record) still reads") {
        Image old(plain_bytes);
        old.set_root_ints("format_version", {1, 0});
        // 1.x files stored the node images (format 2.0 dropped them).
        old.create("/phi/node_image", H5T_NATIVE_DOUBLE, {plain.param.node_image.size(), 3},
                   plain.param.node_image.data());
        const BpmFile r = read_bpm_from_memory(old.bytes(), "old.bpm");
        CHECK_FALSE(r.simplification_steps);
        CHECK(r.param.coarse.triangles == plain.param.coarse.triangles);
    }
}

TEST_CASE("the writer refuses an inconsistent record", "[steps][format]") {
    BpmFile f = simplified(fixtures::torus(12, 8), 0.5, true);
    auto require_output_error = [&](const BpmFile& g, const std::string& part) {
        try {
            write_bpm_to_memory(g);
            FAIL("no OutputError; expected one mentioning " << part);
        } catch (const OutputError& e) {
            INFO(e.what());
            CHECK(std::string(e.what()).find(part) != std::string::npos);
        }
    };
    SECTION("vertex out of range") {
        f.simplification_steps->vertex[1] = f.param.original.num_vertices();
        require_output_error(f, "/simplification_steps/vertex");
    }
    SECTION("corner out of range") {
        f.simplification_steps->triangles[2][1] = -1;
        require_output_error(f, "/simplification_steps/triangles");
    }
    SECTION("offsets") {
        f.simplification_steps->triangle_offsets[1] = f.simplification_steps->triangle_offsets[2] + 1;
        require_output_error(f, "/simplification_steps/triangle_offsets");
    }
    SECTION("patches") {
        f.simplification_steps->triangle_patches.pop_back();
        require_output_error(f, "/simplification_steps/triangle_patches");
    }
}

TEST_CASE("malformed records give an InputError naming the dataset", "[steps][format]") {
    const BpmFile f = simplified(fixtures::torus(12, 8), 0.5, true);
    const std::string good = write_bpm_to_memory(f);
    REQUIRE_NOTHROW(read_bpm_from_memory(good, "good.bpm"));
    const int64_t ns = f.simplification_steps->num_steps();
    const int64_t nr = f.simplification_steps->num_triangles();

    SECTION("missing dataset in the group") {
        Image im(good);
        im.remove("/simplification_steps/triangle_patches");
        require_input_error(im.bytes(), {"/simplification_steps/triangle_patches", "missing"});
    }
    SECTION("removed vertex out of range") {
        Image im(good);
        im.edit<int32_t>("/simplification_steps/vertex", H5T_NATIVE_INT32, [](auto& v) { v[3] = 1 << 30; });
        require_input_error(im.bytes(), {"/simplification_steps/vertex", "entry 3", "out of range"});
    }
    SECTION("negative removed vertex") {
        Image im(good);
        im.edit<int32_t>("/simplification_steps/vertex", H5T_NATIVE_INT32, [](auto& v) { v[0] = -1; });
        require_input_error(im.bytes(), {"/simplification_steps/vertex", "out of range"});
    }
    SECTION("triangle corner out of range") {
        Image im(good);
        im.edit<int32_t>("/simplification_steps/triangles", H5T_NATIVE_INT32, [](auto& v) { v[7] = 99999; });
        require_input_error(im.bytes(), {"/simplification_steps/triangles", "[2, 1]", "out of range"});
    }
    SECTION("offsets not starting at 0") {
        Image im(good);
        im.edit<int64_t>("/simplification_steps/triangle_offsets", H5T_NATIVE_INT64, [](auto& v) { v[0] = 1; });
        require_input_error(im.bytes(), {"/simplification_steps/triangle_offsets", "must be 0"});
    }
    SECTION("decreasing offsets") {
        Image im(good);
        im.edit<int64_t>("/simplification_steps/triangle_offsets", H5T_NATIVE_INT64,
                         [](auto& v) { v[1] = v[2] + 1; });
        require_input_error(im.bytes(), {"/simplification_steps/triangle_offsets", "non-decreasing"});
    }
    SECTION("offsets not ending at the number of triangles") {
        Image im(good);
        im.edit<int64_t>("/simplification_steps/triangle_offsets", H5T_NATIVE_INT64, [](auto& v) { v.back() -= 1; });
        require_input_error(im.bytes(), {"/simplification_steps/triangle_offsets", "last entry"});
    }
    SECTION("offsets with the wrong number of entries") {
        Image im(good);
        const std::vector<int64_t> offsets(static_cast<size_t>(ns), 0);
        im.replace("/simplification_steps/triangle_offsets", H5T_NATIVE_INT64, {offsets.size()}, offsets.data());
        require_input_error(im.bytes(), {"/simplification_steps/triangle_offsets", "rows"});
    }
    SECTION("patches with the wrong number of rows") {
        Image im(good);
        const std::vector<int32_t> patches(static_cast<size_t>(nr + 1), 0);
        im.replace("/simplification_steps/triangle_patches", H5T_NATIVE_INT32, {patches.size()}, patches.data());
        require_input_error(im.bytes(), {"/simplification_steps/triangle_patches", "rows"});
    }
    SECTION("triangles of the wrong shape") {
        Image im(good);
        const std::vector<int32_t> pairs(static_cast<size_t>(2 * nr), 0);
        im.replace("/simplification_steps/triangles", H5T_NATIVE_INT32, {static_cast<hsize_t>(nr), 2}, pairs.data());
        require_input_error(im.bytes(), {"/simplification_steps/triangles", "shape"});
    }
    SECTION("floating-point vertex indices") {
        Image im(good);
        const std::vector<double> v(static_cast<size_t>(ns), 1.0);
        im.replace("/simplification_steps/vertex", H5T_NATIVE_DOUBLE, {v.size()}, v.data());
        require_input_error(im.bytes(), {"/simplification_steps/vertex", "datatype"});
    }
    SECTION("an index that does not fit int32") {
        Image im(good);
        std::vector<int64_t> v(f.simplification_steps->vertex.begin(), f.simplification_steps->vertex.end());
        v[0] = int64_t(1) << 40;
        im.replace("/simplification_steps/vertex", H5T_NATIVE_INT64, {v.size()}, v.data());
        require_input_error(im.bytes(), {"/simplification_steps/vertex", "int32"});
    }
    SECTION("a huge declared extent is refused before allocating") {
        Image im(good);
        im.replace("/simplification_steps/triangles", H5T_NATIVE_INT32, {hsize_t(1) << 36, 3}, nullptr, false);
        require_input_error(im.bytes(), {"/simplification_steps/triangles", "bytes"});
    }
}
