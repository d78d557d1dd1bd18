// gzip-compressed input: every reader takes FILE.EXT.gz (format from EXT) and gzip data in
// memory or on standard input (by its magic bytes); truncated or corrupt gzip data, and
// a .gz name over plain data, are InputErrors that say so, never a crash.
#include <catch2/catch.hpp>

#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "bpm/bpm_file.h"
#include "bpm/bpm_info.h"
#include "bpm/errors.h"
#include "bpm/surface_io.h"
#include "fixtures_phi.h"
#include "test_support.h"

using namespace bpm;
namespace fs = std::filesystem;

namespace {

const std::string kTetOff =
    "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

// `bytes` as one gzip member, as `gzip -c` writes it.
std::string gzip(const std::string& bytes) {
    z_stream s{};
    REQUIRE(deflateInit2(&s, 6, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) == Z_OK);
    std::string out(deflateBound(&s, uLong(bytes.size())) + 32, '\0');
    s.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    s.avail_in = uInt(bytes.size());
    s.next_out = reinterpret_cast<Bytef*>(out.data());
    s.avail_out = uInt(out.size());
    REQUIRE(deflate(&s, Z_FINISH) == Z_STREAM_END);
    out.resize(s.total_out);
    deflateEnd(&s);
    return out;
}

std::string error_of(const std::function<void()>& read) {
    try {
        read();
    } catch (const InputError& e) {
        return std::string(e.where()) + ": " + e.what();
    }
    return "no error";
}

void write_file(const fs::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out << bytes;
}

}  // namespace

TEST_CASE("gzip data in memory is read like the plain data", "[io][gzip]") {
    const Surface plain = read_surface_from_memory(kTetOff, SurfaceFormat::Off, "tet.off");
    const Surface unzipped = read_surface_from_memory(gzip(kTetOff), SurfaceFormat::Off, "tet.off.gz");
    CHECK(unzipped.vertices == plain.vertices);
    CHECK(unzipped.triangles == plain.triangles);
    // Two members (`cat a.gz b.gz`) are one stream, as gzip -d reads them.
    const std::string two = gzip(kTetOff.substr(0, 20)) + gzip(kTetOff.substr(20));
    CHECK(read_surface_from_memory(two, SurfaceFormat::Off, "two.off.gz").triangles == plain.triangles);
}

TEST_CASE("truncated or corrupt gzip data is an InputError that says so", "[io][gzip]") {
    std::string text;
    for (int i = 0; i < 200; ++i) text += "# a comment line that compresses well " + std::to_string(i) + "\n";
    text += kTetOff;
    const std::string zipped = gzip(text);
    for (const size_t keep : {size_t(10), zipped.size() / 2, zipped.size() - 4}) {
        INFO("kept " << keep << " of " << zipped.size() << " bytes");
        const std::string message = error_of([&] {
            (void)read_surface_from_memory(zipped.substr(0, keep), SurfaceFormat::Off, "cut.off.gz");
        });
        CHECK_THAT(message, Catch::Contains("cut.off.gz: truncated gzip data"));
    }
    std::string flipped = zipped;
    flipped[zipped.size() / 2] = char(flipped[zipped.size() / 2] ^ 0x55);
    CHECK_THAT(error_of([&] { (void)read_surface_from_memory(flipped, SurfaceFormat::Off, "bad.off.gz"); }),
               Catch::Contains("bad.off.gz: corrupt gzip data"));
    std::string wrong_crc = zipped;
    wrong_crc[zipped.size() - 6] = char(wrong_crc[zipped.size() - 6] ^ 1);  // in the CRC-32 of the trailer
    CHECK_THAT(error_of([&] { (void)read_surface_from_memory(wrong_crc, SurfaceFormat::Off, "crc.off.gz"); }),
               Catch::Contains("corrupt gzip data"));
    CHECK_THAT(error_of([&] {
                   (void)read_surface_from_memory(zipped + "garbage!", SurfaceFormat::Off, "tail.off.gz");
               }),
               Catch::Contains("unexpected bytes after gzip member 1"));
}

TEST_CASE("FILE.EXT.gz: the format from EXT, the material from the name without .gz", "[io][gzip]") {
    CHECK(surface_format_from_path("dir.d/femur.OFF.gz") == SurfaceFormat::Off);
    CHECK(surface_format_from_path("bone.stl.GZ") == SurfaceFormat::Stl);
    CHECK_FALSE(surface_format_from_path("femur.gz").has_value());

    const test_support::ScratchDir scratch("gzip_input_test");
    const fs::path& dir = scratch.path;
    write_file(dir / "bone.off.gz", gzip(kTetOff));
    SurfaceReadReport report;
    const Surface s = read_surface((dir / "bone.off.gz").string(), {}, &report);
    CHECK(s.num_triangles() == 4);
    REQUIRE(report.patch_info.size() == 1);
    CHECK(report.patch_info[0].back == "bone");

    write_file(dir / "plain.off.gz", kTetOff);
    CHECK_THAT(error_of([&] { (void)read_surface((dir / "plain.off.gz").string()); }),
               Catch::Contains("plain.off.gz: is not gzip data"));
    write_file(dir / "empty.off.gz", "");
    CHECK_THAT(error_of([&] { (void)read_surface((dir / "empty.off.gz").string()); }),
               Catch::Contains("empty.off.gz: is empty"));
    // gzip data under a plain name is recognised by its magic bytes.
    write_file(dir / "zipped.off", gzip(kTetOff));
    CHECK(read_surface((dir / "zipped.off").string()).num_triangles() == 4);
}

TEST_CASE(".bpm.gz is read like the .bpm", "[io][gzip]") {
    const BpmFile file = test::make_two_triangles_example();
    const std::string bytes = write_bpm_to_memory(file);
    const BpmFile back = read_bpm_from_memory(gzip(bytes), "example.bpm.gz");
    CHECK(write_bpm_to_memory(back) == bytes);
    CHECK(back.format_version.major == bpm_format_version().major);
    CHECK(back.format_version.minor == bpm_format_version().minor);

    const test_support::ScratchDir scratch("gzip_bpm_test");
    const fs::path& dir = scratch.path;
    const std::string zipped = gzip(bytes);
    write_file(dir / "example.bpm.gz", zipped);
    const BpmInfo info = read_bpm_info((dir / "example.bpm.gz").string());
    CHECK(info.file_bytes == int64_t(zipped.size()));
    CHECK(info.coarse_triangles == file.param.coarse.num_triangles());
    write_file(dir / "cut.bpm.gz", zipped.substr(0, zipped.size() / 2));
    CHECK_THAT(error_of([&] { (void)read_bpm((dir / "cut.bpm.gz").string()); }),
               Catch::Contains("cut.bpm.gz: truncated gzip data"));
}
