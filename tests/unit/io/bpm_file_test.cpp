// The bpm file format: round trips, determinism, the golden example, and malformed
// files (each must give an InputError that names the dataset at fault).

#include <hdf5.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include "bpm/bpm_file.h"
#include "bpm/errors.h"
#include "bpm/check.h"
#include "bpm/phi_evaluation.h"
#include "bpm/simplify.h"
#include "bpm/version.h"
#include "fixtures_hdf5.h"
#include "fixtures_phi.h"
#include "fixtures_surfaces.h"
#include "test_support.h"

using namespace bpm;
using Image = bpm::test::Hdf5Image;
using bpm::test::require_input_error;

namespace {

Surface two_triangle_surface() {
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.5}, {0, 1, 0.25}};
    s.triangles = {{0, 1, 2}, {0, 2, 3}};
    s.patches = {3, 7};
    return s;
}

bool same_double(double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

void require_equal(const Surface& a, const Surface& b) {
    REQUIRE(a.vertices == b.vertices);
    REQUIRE(a.triangles == b.triangles);
    REQUIRE(a.patches == b.patches);
    REQUIRE(a.vertex_data.size() == b.vertex_data.size());
    for (size_t i = 0; i < a.vertex_data.size(); ++i) {
        CHECK(a.vertex_data[i].name == b.vertex_data[i].name);
        CHECK(a.vertex_data[i].components == b.vertex_data[i].components);
        CHECK(a.vertex_data[i].values == b.vertex_data[i].values);
    }
}

void require_equal(const BpmFile& a, const BpmFile& b) {
    require_equal(a.param.original, b.param.original);
    require_equal(a.param.coarse, b.param.coarse);
    const Parametrization &p = a.param, &q = b.param;
    REQUIRE(p.coarse_vertex_origin == q.coarse_vertex_origin);
    REQUIRE(p.node_offsets == q.node_offsets);
    REQUIRE(p.node_barycentric == q.node_barycentric);
    REQUIRE(p.node_image == q.node_image);
    REQUIRE(p.node_kind == q.node_kind);
    REQUIRE(p.node_original_vertex == q.node_original_vertex);
    REQUIRE(p.node_original_edge == q.node_original_edge);
    REQUIRE(p.node_edge_parameter.size() == q.node_edge_parameter.size());
    for (size_t i = 0; i < p.node_edge_parameter.size(); ++i)
        REQUIRE(same_double(p.node_edge_parameter[i], q.node_edge_parameter[i]));
    REQUIRE(p.piece_offsets == q.piece_offsets);
    REQUIRE(p.pieces == q.pieces);
    REQUIRE(p.piece_original_triangle == q.piece_original_triangle);
    REQUIRE(a.units == b.units);
    REQUIRE(a.coordinate_frame == b.coordinate_frame);
    REQUIRE(a.provenance.size() == b.provenance.size());
    for (size_t i = 0; i < a.provenance.size(); ++i) {
        CHECK(a.provenance[i].tool == b.provenance[i].tool);
        CHECK(a.provenance[i].version == b.provenance[i].version);
        CHECK(a.provenance[i].arguments == b.provenance[i].arguments);
        CHECK(a.provenance[i].timestamp == b.provenance[i].timestamp);
    }
}

BpmFile with_provenance(Parametrization p) {
    BpmFile f;
    f.param = std::move(p);
    f.units = "mm";
    f.provenance.push_back({"bpm-simplify", "0.1.0", "bpm-simplify in.off -o out.bpm --target 100", "2026-11-22T03:00:00Z"});
    f.provenance.push_back({"bpm-smooth", "0.1.0", "bpm-smooth out.bpm -o smooth.bpm \"quoted\" ünïcode", ""});
    return f;
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string valid_file() { return write_bpm_to_memory(with_provenance(test::make_height_field(4, 2, test::default_height))); }

}  // namespace

TEST_CASE("format version comes from the build", "[format]") {
    CHECK(bpm_format_version().major == BPM_FORMAT_VERSION_MAJOR);
    CHECK(bpm_format_version().minor == BPM_FORMAT_VERSION_MINOR);
    CHECK(bpm_format_version().major == 2);
}

TEST_CASE("identity parametrization round-trips exactly", "[format]") {
    const BpmFile f = with_provenance(make_identity_parametrization(two_triangle_surface()));
    const BpmFile g = read_bpm_from_memory(write_bpm_to_memory(f), "mem");
    require_equal(f, g);
}

TEST_CASE("fixtures with non-trivial phi round-trip exactly", "[format]") {
    SECTION("subdivided octahedron") {
        const BpmFile f = with_provenance(test::make_subdivided_octahedron(3));
        require_equal(f, read_bpm_from_memory(write_bpm_to_memory(f), "mem"));
    }
    SECTION("height field with edge crossings") {
        const BpmFile f = with_provenance(test::make_height_field(6, 3, test::default_height));
        require_equal(f, read_bpm_from_memory(write_bpm_to_memory(f), "mem"));
    }
    SECTION("large enough to be chunked and compressed") {
        // More than 16384 rows: the datasets earlier writers compressed (now every dataset
        // of at least 512 bytes, bpm_write.cpp, spec §3.2).
        const BpmFile f = with_provenance(test::make_height_field(132, 6, test::default_height));
        REQUIRE(f.param.num_nodes() > 16384);
        REQUIRE(f.param.original.num_triangles() > 16384);
        const std::string bytes = write_bpm_to_memory(f);
        require_equal(f, read_bpm_from_memory(bytes, "mem"));
    }
    SECTION("empty provenance and units") {
        BpmFile f;
        f.param = make_identity_parametrization(two_triangle_surface());
        require_equal(f, read_bpm_from_memory(write_bpm_to_memory(f), "mem"));
    }
}

TEST_CASE("the coordinate frame round-trips, and files without one have none (format 2.1)", "[format]") {
    BpmFile f = with_provenance(make_identity_parametrization(two_triangle_surface()));
    f.coordinate_frame = "LPS";
    const std::string with = write_bpm_to_memory(f);
    const BpmFile g = read_bpm_from_memory(with, "mem");
    require_equal(f, g);
    CHECK(g.coordinate_frame == "LPS");
    CHECK(g.format_version.minor == BPM_FORMAT_VERSION_MINOR);
    f.coordinate_frame.clear();
    const std::string without = write_bpm_to_memory(f);
    CHECK(without.find("coordinate_frame") == std::string::npos);  // not written when unknown
    CHECK(with.find("coordinate_frame") != std::string::npos);
    CHECK(read_bpm_from_memory(without, "mem").coordinate_frame.empty());
    // Another value (written elsewhere) reads as unknown, so that no tool copies it on.
    f.coordinate_frame = "scanner-xyz";
    CHECK(read_bpm_from_memory(write_bpm_to_memory(f), "mem").coordinate_frame.empty());
}

TEST_CASE("with crash isolation the parsed data comes back from the child unchanged", "[format]") {
    // What the tools do (set_hdf5_isolation): HDF5 runs in a forked child, whose reads the
    // parent replays. The result must be the same file, and errors the same errors.
    struct Isolation {
        Isolation() { set_hdf5_isolation(true); }
        ~Isolation() { set_hdf5_isolation(false); }
    } isolation;
    for (const BpmFile& f : {with_provenance(test::make_subdivided_octahedron(3)),
                             with_provenance(test::make_height_field(60, 6, test::default_height))}) {
        const std::string bytes = write_bpm_to_memory(f);
        require_equal(f, read_bpm_from_memory(bytes, "mem"));
    }
    const std::string bytes = valid_file();
    std::string isolated, direct;
    try {
        (void)read_bpm_from_memory(bytes.substr(0, bytes.size() / 2), "half");
    } catch (const InputError& e) {
        isolated = e.what();
    }
    set_hdf5_isolation(false);
    try {
        (void)read_bpm_from_memory(bytes.substr(0, bytes.size() / 2), "half");
    } catch (const InputError& e) {
        direct = e.what();
    }
    CHECK(!isolated.empty());
    CHECK(isolated == direct);
}

TEST_CASE("writing is deterministic and write_bpm writes the same bytes", "[format]") {
    const BpmFile f = with_provenance(test::make_height_field(60, 6, test::default_height));
    const std::string a = write_bpm_to_memory(f);
    const std::string b = write_bpm_to_memory(f);
    REQUIRE(a == b);
    const test_support::ScratchDir scratch("bpm_file_test");
    const std::string path = scratch.file("written.bpm");
    write_bpm(path, f);
    CHECK(read_file(path) == a);
    require_equal(f, read_bpm(path));
}

TEST_CASE("a file written in place has the bytes of the in-memory image, also with compressed chunks", "[format]") {
    // write_bpm streams through its own HDF5 driver (io/hdf5_fd_driver.h), the image goes
    // through the core driver: the layout must not depend on the driver. 200 x 100 cells
    // give 40000 triangles, so large deflated chunks too.
    const BpmFile f = with_provenance(test::make_height_field(200, 100, test::default_height));
    REQUIRE(f.param.original.num_triangles() > 16384);
    const test_support::ScratchDir scratch("bpm_file_chunked");
    const std::string path = scratch.file("chunked.bpm");
    write_bpm(path, f);
    CHECK(read_file(path) == write_bpm_to_memory(f));
    // Over an existing file, and nothing else is left in the directory.
    write_bpm(path, f);
    CHECK(read_file(path) == write_bpm_to_memory(f));
    size_t entries = 0;
    for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(path).parent_path())) {
        (void)e;
        ++entries;
    }
    CHECK(entries == 1);
}

TEST_CASE("datasets of small files are compressed too, and tiny ones stay contiguous", "[format]") {
    // Earlier writers deflated only datasets of more than 16384 rows, which left the whole
    // .bpm of a small input raw (elephant: 1.29 MB, 0.58 MB deflated).
    // bpm_write.cpp compresses every dataset of at least 512 bytes (spec §3.2).
    const BpmFile f = with_provenance(test::make_subdivided_octahedron(3));
    REQUIRE(f.param.num_nodes() < 16384);
    REQUIRE(f.param.num_nodes() * 8 >= 512);
    Image image(write_bpm_to_memory(f));
    const auto filters = [&](const char* path) {
        const hid_t ds = H5Dopen2(image.file, path, H5P_DEFAULT);
        REQUIRE(ds >= 0);
        const hid_t dcpl = H5Dget_create_plist(ds);
        std::vector<H5Z_filter_t> out;
        const int n = H5Pget_nfilters(dcpl);
        for (int i = 0; i < n; ++i) {
            unsigned flags = 0;
            size_t nvalues = 0;
            out.push_back(H5Pget_filter2(dcpl, unsigned(i), &flags, &nvalues, nullptr, 0, nullptr, nullptr));
        }
        const H5D_layout_t layout = H5Pget_layout(dcpl);
        H5Pclose(dcpl);
        H5Dclose(ds);
        return std::make_pair(layout, out);
    };
    for (const char* path : {"/phi/node_edge_parameter", "/phi/node_barycentric", "/phi/pieces", "/original/vertices",
                             "/original/triangles"}) {
        INFO(path);
        const auto [layout, list] = filters(path);
        CHECK(layout == H5D_CHUNKED);
        REQUIRE(!list.empty());
        CHECK(list.back() == H5Z_FILTER_DEFLATE);
    }
    const auto [layout, list] = filters("/VTKHDF/NumberOfPoints");
    CHECK(layout == H5D_CONTIGUOUS);
    CHECK(list.empty());
    require_equal(f, read_bpm_from_memory(write_bpm_to_memory(f), "mem"));
}

TEST_CASE("a chunk deflate cannot shrink is stored unfiltered, and chunked datasets read back exactly", "[format]") {
    // bpm_write.cpp compresses the chunks itself and hands them to HDF5 as stored
    // (H5Dwrite_chunk), with a filter mask saying which filters it skipped: a chunk that
    // deflate does not shrink (random bits) is stored raw with the deflate filter marked
    // skipped, the last of several chunks is padded to a whole one. A wrong mask or
    // padding makes the file unreadable or its values different.
    BpmFile f = with_provenance(test::make_height_field(200, 100, test::default_height));
    REQUIRE(f.param.num_nodes() > 65536);  // the node arrays have several chunks, the last partial
    REQUIRE(f.param.num_nodes() % 65536 != 0);
    std::mt19937_64 rng(21);
    VertexArray noise{"noise", 1, {}};
    while (noise.values.size() < f.param.original.vertices.size()) {
        const uint64_t bits = rng();
        double x;
        std::memcpy(&x, &bits, sizeof x);
        if (std::isfinite(x)) noise.values.push_back(x);
    }
    f.param.original.vertex_data.push_back(noise);
    const std::string bytes = write_bpm_to_memory(f);
    {
        Image image(bytes);
        const hid_t ds = H5Dopen2(image.file, "/original/point_data/noise", H5P_DEFAULT);
        REQUIRE(ds >= 0);
        const hid_t dcpl = H5Dget_create_plist(ds);
        CHECK(H5Pget_layout(dcpl) == H5D_CHUNKED);
        REQUIRE(H5Pget_nfilters(dcpl) == 1);  // no shuffle: it does not pay on random bits either
        H5Pclose(dcpl);
        unsigned mask = 0;
        hsize_t stored = 0;
        const hid_t space = H5Dget_space(ds);
        const herr_t info = H5Dget_chunk_info(ds, space, 0, nullptr, &mask, nullptr, &stored);
        H5Sclose(space);
        H5Dclose(ds);
        REQUIRE(info >= 0);
        CHECK(mask == 1u);  // deflate (filter 0) skipped
        CHECK(stored == noise.values.size() * sizeof(double));
    }
    require_equal(f, read_bpm_from_memory(bytes, "mem"));
}

TEST_CASE("datasets with the bytes of an earlier surface dataset store its chunks and read back exactly", "[format]") {
    // bpm_write.cpp writes a surface dataset whose type, shape and bytes are those of one
    // written before (the coarse surface of an identity phi is the original; /VTKHDF
    // repeats the coarse surface) as a copy of that one's stored chunks, read back raw. The
    // copies must be the chunks compressing them would give, several chunks included.
    const Parametrization hf = test::make_height_field(300, 150, test::default_height);
    const BpmFile f = with_provenance(make_identity_parametrization(hf.original));
    REQUIRE(f.param.coarse.triangles.size() > 65536);  // several chunks
    const std::string bytes = write_bpm_to_memory(f);
    require_equal(f, read_bpm_from_memory(bytes, "mem"));
    Image image(bytes);
    const auto chunks = [&](const char* path) {
        const hid_t ds = H5Dopen2(image.file, path, H5P_DEFAULT);
        REQUIRE(ds >= 0);
        std::vector<std::string> out;
        hsize_t n = 0;
        const hid_t space = H5Dget_space(ds);
        REQUIRE(H5Dget_num_chunks(ds, space, &n) >= 0);
        for (hsize_t i = 0; i < n; ++i) {
            hsize_t offset[2] = {0, 0}, size = 0;
            unsigned mask = 0;
            haddr_t addr = 0;
            REQUIRE(H5Dget_chunk_info(ds, space, i, offset, &mask, &addr, &size) >= 0);
            std::string chunk(size_t(size), '\0');
            uint32_t read_mask = 0;
            REQUIRE(H5Dread_chunk(ds, H5P_DEFAULT, offset, &read_mask, chunk.data()) >= 0);
            out.push_back(std::to_string(read_mask) + ":" + chunk);
        }
        H5Sclose(space);
        H5Dclose(ds);
        return out;
    };
    CHECK(chunks("/original/triangles").size() > 1);
    CHECK(chunks("/coarse/triangles") == chunks("/original/triangles"));
    CHECK(chunks("/coarse/vertices") == chunks("/original/vertices"));
    CHECK(chunks("/VTKHDF/Points") == chunks("/original/vertices"));
    CHECK(chunks("/VTKHDF/CellData/patch") == chunks("/original/patches"));
}

TEST_CASE("identity phi read from a file evaluates to the input exactly", "[format][phi]") {
    const Surface s = two_triangle_surface();
    const BpmFile g = read_bpm_from_memory(write_bpm_to_memory(with_provenance(make_identity_parametrization(s))), "m");
    PhiEvaluator eval(g.param);
    const Vec3 bs[] = {{0.2, 0.3, 0.5}, {1, 0, 0}, {0, 0.7, 0.3}, {0.1, 0.1, 0.8}};
    for (int32_t t = 0; t < 2; ++t)
        for (const Vec3& b : bs) {
            const Tri& tri = s.triangles[static_cast<size_t>(t)];
            const PhiSample r = eval.evaluate(t, b);
            CHECK(r.position == barycentric_point(s.vertices[static_cast<size_t>(tri[0])],
                                                  s.vertices[static_cast<size_t>(tri[1])],
                                                  s.vertices[static_cast<size_t>(tri[2])], b));
            CHECK(r.original_triangle == t);
            CHECK(r.original_barycentric == b);
        }
}

TEST_CASE("writer refuses an inconsistent parametrization", "[format]") {
    BpmFile f = with_provenance(make_identity_parametrization(two_triangle_surface()));
    f.param.pieces[0][1] = 5;
    CHECK_THROWS_AS(write_bpm_to_memory(f), OutputError);
    try {
        write_bpm_to_memory(f);
    } catch (const OutputError& e) {
        CHECK(std::string(e.what()).find("/phi/pieces") != std::string::npos);
    }
}

TEST_CASE("writer refuses node images that are not the points their nodes name", "[format]") {
    // Files store no images since format 2.0 and readers recompute them, so a caller's
    // image that differs from its node's point would be replaced silently on reading.
    BpmFile f = with_provenance(make_identity_parametrization(two_triangle_surface()));
    const Vec3 named = node_image_from_kind(f.param, 4);
    f.param.node_image[4] = named + Vec3{0, 1e-3, 0};
    try {
        write_bpm_to_memory(f);
        FAIL("written");
    } catch (const OutputError& e) {
        CHECK(std::string(e.what()).find("node_image[4]") != std::string::npos);
        CHECK(std::string(e.what()).find("node_images_from_kinds") != std::string::npos);
    }
    // Within bpm-check's tolerance (1e-9 of the diagonal) it is the same point: written,
    // and read back as the recomputed one.
    f.param.node_image[4] = named + Vec3{0, 1e-12, 0};
    CHECK(read_bpm_from_memory(write_bpm_to_memory(f), "m").param.node_image[4] == named);
}

TEST_CASE("write_bpm into a missing directory is an OutputError", "[format]") {
    const BpmFile f = with_provenance(make_identity_parametrization(two_triangle_surface()));
    CHECK_THROWS_AS(write_bpm("/nonexistent-dir-bpm/x.bpm", f), OutputError);
}

namespace {

bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0);
}

// /phi/node_image as a file stores it, read with HDF5 directly (not through read_bpm).
std::vector<Vec3> stored_images(const std::string& bytes) {
    Image im(bytes);
    std::vector<Vec3> out;
    im.edit<double>("/phi/node_image", H5T_NATIVE_DOUBLE, [&](auto& v) {
        out.resize(v.size() / 3);
        std::memcpy(out.data(), v.data(), v.size() * sizeof(double));
    });
    return out;
}

}  // namespace

TEST_CASE("format 2.0 stores no node images, the reader recomputes the simplifier's to the bit", "[format]") {
    // Issue 21: /phi/node_image was a third of a simplified file; every image is what its
    // node names (spec 6.2), so the reader recomputes it. The simplifier's output, with
    // edge crossings whose ends the caller's vertex order swapped (vertex_order.cpp).
    SimplifyOptions options;
    options.target_ratio = 0.1;
    Parametrization p;
    simplify(fixtures::torus(24, 16), options, Context{}, p);
    int64_t crossings = 0;
    for (const NodeKind k : p.node_kind) crossings += k == NodeKind::EdgeCrossing;
    REQUIRE(crossings > 100);
    const BpmFile f = with_provenance(p);
    const std::string bytes = write_bpm_to_memory(f);
    Image im(bytes);
    CHECK_FALSE(im.exists("/phi/node_image"));
    const BpmFile g = read_bpm_from_memory(bytes, "torus.bpm");
    CHECK(g.format_version.major == 2);
    CHECK(g.stored_node_image.empty());
    CHECK(same_bits(g.param.node_image, p.node_image));
    require_equal(f, g);
}

TEST_CASE("format 1.x files still read, with the images they stored", "[format]") {
    for (const char* name : {"two_triangles-1.3.bpm", "two_cubes-1.3.bpm"}) {
        INFO(name);
        const std::string bytes = read_file(std::string(BPM_SOURCE_DIR) + "/tests/data/format-1/" + name);
        REQUIRE(!bytes.empty());
        const std::vector<Vec3> stored = stored_images(bytes);
        const BpmFile f = read_bpm_from_memory(bytes, name);
        CHECK(f.format_version.major == 1);
        CHECK(f.format_version.minor == 3);
        REQUIRE(stored.size() == size_t(f.param.num_nodes()));
        CHECK(same_bits(f.stored_node_image, stored));
        CHECK(same_bits(f.param.node_image, stored));  // the recomputation, equal to the bit
        CHECK(check_format(f).passed);
        // Rewritten, it is a 2.0 file with the same images.
        const BpmFile g = read_bpm_from_memory(write_bpm_to_memory(f), name);
        CHECK(g.format_version.major == 2);
        CHECK(same_bits(g.param.node_image, stored));
    }
}

TEST_CASE("a 1.x file whose stored image is not its node's point fails the format check", "[format]") {
    Image im(read_file(std::string(BPM_SOURCE_DIR) + "/tests/data/format-1/two_cubes-1.3.bpm"));
    const BpmFile good = read_bpm_from_memory(im.bytes(), "good.bpm");
    im.edit<double>("/phi/node_image", H5T_NATIVE_DOUBLE, [](auto& v) { v[3 * 5 + 2] += 0.5; });
    const BpmFile bad = read_bpm_from_memory(im.bytes(), "bad.bpm");
    // Everything else in libbpm sees the images the nodes name, not the corrupt copy.
    CHECK(same_bits(bad.param.node_image, good.param.node_image));
    const CheckResult r = check_format(bad);
    CHECK_FALSE(r.passed);
    REQUIRE(!r.problems.empty());
    CHECK(r.problems[0].describe().find("stored image") != std::string::npos);
    CHECK(r.problems[0].id("node") == 5);
    CHECK(check_format(bad.param).passed);  // the recomputed images are right
}

TEST_CASE("the spec example is the golden file and reads", "[format]") {
    const std::string path = std::string(BPM_SOURCE_DIR) + "/spec/examples/two_triangles.bpm";
    const std::string committed = read_file(path);
    REQUIRE(!committed.empty());
    const BpmFile expected = test::make_two_triangles_example();
    // Byte-identical: the writer is deterministic, and a change of layout must be a
    // deliberate change of the spec example too (bpm-make-example two_triangles FILE).
    CHECK(write_bpm_to_memory(expected) == committed);
    const BpmFile read = read_bpm(path);
    require_equal(expected, read);
    CHECK(read.param.num_pieces() == 4);
    int crossings = 0;
    for (auto k : read.param.node_kind) crossings += k == NodeKind::EdgeCrossing;
    CHECK(crossings == 2);
}

TEST_CASE("reading rejects inputs that are not bpm files", "[format]") {
    require_input_error("", {"empty"});
    require_input_error("solid x\nendsolid\n", {"not an HDF5 file"});
    const std::string good = valid_file();
    require_input_error(good.substr(0, good.size() / 2), {"HDF5"});
    CHECK_THROWS_AS(read_bpm("/nonexistent-bpm-file.bpm"), InputError);
}

TEST_CASE("malformed files give an InputError naming the dataset", "[format]") {
    const std::string good = valid_file();
    REQUIRE_NOTHROW(read_bpm_from_memory(good, "good.bpm"));

    SECTION("missing dataset") {
        Image im(good);
        im.remove("/phi/pieces");
        require_input_error(im.bytes(), {"/phi/pieces", "missing"});
    }
    SECTION("missing group") {
        Image im(good);
        im.remove("/coarse");
        require_input_error(im.bytes(), {"/coarse/", "missing"});
    }
    SECTION("wrong dtype") {
        Image im(good);
        const BpmFile f = read_bpm_from_memory(good, "x");
        std::vector<double> tri;
        for (auto& t : f.param.original.triangles) tri.insert(tri.end(), t.begin(), t.end());
        im.replace("/original/triangles", H5T_NATIVE_DOUBLE, {f.param.original.triangles.size(), 3}, tri.data());
        require_input_error(im.bytes(), {"/original/triangles", "datatype"});
    }
    SECTION("wrong shape") {
        Image im(good);
        const std::vector<double> xy(20, 0.5);
        im.replace("/original/vertices", H5T_NATIVE_DOUBLE, {10, 2}, xy.data());
        require_input_error(im.bytes(), {"/original/vertices", "shape"});
    }
    SECTION("row count that does not match") {
        Image im(good);
        const std::vector<int32_t> patches(3, 0);
        im.replace("/coarse/patches", H5T_STD_I32LE, {3}, patches.data());
        require_input_error(im.bytes(), {"/coarse/patches"});
    }
    SECTION("index out of range") {
        Image im(good);
        im.edit<int32_t>("/original/triangles", H5T_NATIVE_INT32, [](auto& v) { v[4] = 100000; });
        require_input_error(im.bytes(), {"/original/triangles", "out of range", "100000"});
    }
    SECTION("index that does not fit int32") {
        Image im(good);
        const BpmFile f = read_bpm_from_memory(good, "x");
        std::vector<int64_t> ot(f.param.piece_original_triangle.begin(), f.param.piece_original_triangle.end());
        ot[0] = int64_t(1) << 40;
        im.replace("/phi/piece_original_triangle", H5T_NATIVE_INT64, {ot.size()}, ot.data());
        require_input_error(im.bytes(), {"/phi/piece_original_triangle"});
    }
    SECTION("piece corner out of its triangle's node range") {
        Image im(good);
        im.edit<int32_t>("/phi/pieces", H5T_NATIVE_INT32, [](auto& v) { v[0] = -1; });
        require_input_error(im.bytes(), {"/phi/pieces", "out of range"});
    }
    SECTION("broken CSR offsets") {
        Image im(good);
        im.edit<int64_t>("/phi/node_offsets", H5T_NATIVE_INT64, [](auto& v) { v[1] = v[2] + 1; });
        require_input_error(im.bytes(), {"/phi/node_offsets", "non-decreasing"});
    }
    SECTION("CSR offsets not starting at 0") {
        Image im(good);
        im.edit<int64_t>("/phi/piece_offsets", H5T_NATIVE_INT64, [](auto& v) { v[0] = 1; });
        require_input_error(im.bytes(), {"/phi/piece_offsets", "must be 0"});
    }
    SECTION("CSR offsets not ending at the dataset length") {
        Image im(good);
        im.edit<int64_t>("/phi/node_offsets", H5T_NATIVE_INT64, [](auto& v) { v.back() -= 1; });
        require_input_error(im.bytes(), {"/phi/node_offsets", "last entry"});
    }
    SECTION("invalid node kind") {
        Image im(good);
        im.edit<uint8_t>("/phi/node_kind", H5T_NATIVE_UINT8, [](auto& v) { v[2] = 7; });
        require_input_error(im.bytes(), {"/phi/node_kind", "7"});
    }
    SECTION("NaN coordinate") {
        Image im(good);
        im.edit<double>("/original/vertices", H5T_NATIVE_DOUBLE, [](auto& v) { v[5] = std::nan(""); });
        require_input_error(im.bytes(), {"/original/vertices", "not finite"});
    }
    SECTION("infinite stored image (format 1.x)") {
        Image im(read_file(std::string(BPM_SOURCE_DIR) + "/tests/data/format-1/two_cubes-1.3.bpm"));
        im.edit<double>("/phi/node_image", H5T_NATIVE_DOUBLE, [](auto& v) { v[0] = HUGE_VAL; });
        require_input_error(im.bytes(), {"/phi/node_image", "not finite"});
    }
    SECTION("too few stored images (format 1.x)") {
        Image im(read_file(std::string(BPM_SOURCE_DIR) + "/tests/data/format-1/two_cubes-1.3.bpm"));
        const BpmFile f = read_bpm_from_memory(im.bytes(), "x");
        const std::vector<double> rows(3 * (f.stored_node_image.size() - 1), 0.0);
        im.replace("/phi/node_image", H5T_NATIVE_DOUBLE, {f.stored_node_image.size() - 1, 3}, rows.data());
        require_input_error(im.bytes(), {"/phi/node_image", "rows"});
    }
    SECTION("edge parameter outside [0, 1] for a crossing") {
        const BpmFile f = read_bpm_from_memory(good, "x");
        size_t crossing = 0;
        while (f.param.node_kind[crossing] != NodeKind::EdgeCrossing) ++crossing;
        Image im(good);
        im.edit<double>("/phi/node_edge_parameter", H5T_NATIVE_DOUBLE, [&](auto& v) { v[crossing] = 1.5; });
        require_input_error(im.bytes(), {"/phi/node_edge_parameter"});
    }
    SECTION("unknown major version") {
        Image im(good);
        im.set_root_ints("format_version", {3, 0});
        require_input_error(im.bytes(), {"format_version", "3.0", "supports major versions 1 to 2 only", "newer"});
        im.set_root_ints("format_version", {0, 9});
        require_input_error(im.bytes(), {"format_version", "0.9", "supports major versions 1 to 2 only"});
    }
    SECTION("newer minor version is accepted") {
        Image im(good);
        im.set_root_ints("format_version", {BPM_FORMAT_VERSION_MAJOR, 7});
        CHECK_NOTHROW(read_bpm_from_memory(im.bytes(), "newer-minor.bpm"));
    }
    SECTION("a 1.x file without /phi/node_image (required there)") {
        Image im(good);
        im.set_root_ints("format_version", {1, 3});
        require_input_error(im.bytes(), {"/phi/node_image", "missing"});
    }
    SECTION("wrong format attribute") {
        Image im(good);
        REQUIRE(H5Adelete(im.file, "format") >= 0);
        require_input_error(im.bytes(), {"format", "missing"});
    }
    SECTION("unknown groups and attributes are ignored") {
        Image im(good);
        hid_t g = H5Gcreate2(im.file, "/tetmesh_future_thing", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        H5Gclose(g);
        im.set_root_ints("format_version", {BPM_FORMAT_VERSION_MAJOR, 0});
        hsize_t n = 1;
        hid_t space = H5Screate_simple(1, &n, nullptr);
        hid_t a = H5Acreate2(im.file, "some_future_attribute", H5T_STD_I32LE, space, H5P_DEFAULT, H5P_DEFAULT);
        int32_t one = 1;
        H5Awrite(a, H5T_NATIVE_INT32, &one);
        H5Aclose(a);
        H5Sclose(space);
        CHECK_NOTHROW(read_bpm_from_memory(im.bytes(), "extended.bpm"));
    }
    SECTION("a huge declared dataset is refused before allocating") {
        Image im(good);
        im.replace("/original/vertices", H5T_NATIVE_DOUBLE, {hsize_t(1) << 32, 3}, nullptr, false);
        require_input_error(im.bytes(), {"/original/vertices", "bytes"});
    }
}
