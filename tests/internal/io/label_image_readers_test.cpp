// The label image readers (io/label_image_readers.h) give the compact form of
// bpm/label_image.h (1 byte a voxel up to 256 distinct labels, else 2), never the int32
// labels: a 512^3 image is 134 MB of labels, not 537 MB.
#include <catch2/catch.hpp>
#include <string>

#include "bpm/errors.h"
#include "bpm/label_image.h"
#include "io/label_image_readers.h"

using namespace bpm;

namespace {

std::string nrrd(const std::string& type, int n, const std::string& data) {
    const std::string s = std::to_string(n);
    return "NRRD0004\ntype: " + type + "\ndimension: 3\nsizes: " + s + " " + s + " " + s +
           "\nencoding: raw\nendian: little\n\n" + data;
}

}  // namespace

TEST_CASE("label image readers: compact labels, 1 byte a voxel for up to 256 labels, else 2") {
    // uint8: labels 0, 3, 200 (the fast path).
    std::string bytes(27, '\0');
    bytes[4] = 3, bytes[13] = char(200);
    LabelImage a = detail::read_nrrd_image(nrrd("uchar", 3, bytes), "a");
    CHECK(a.labels.empty());
    CHECK(a.label_values == std::vector<int32_t>{0, 3, 200});
    REQUIRE(a.label_index8.size() == 27);
    CHECK(a.label_index16.empty());
    CHECK(a.label_at(4) == 3);
    CHECK(a.label_at(13) == 200);
    CHECK(a.label_at(0) == 0);
    CHECK(label_image_problem(a).empty());

    // int16, 300 distinct labels from -100 (and 0): 2 bytes a voxel.
    std::string wide;
    for (int v = 0; v < 343; ++v) {
        const int16_t l = int16_t(v < 300 ? v - 100 : 7);
        wide.append(reinterpret_cast<const char*>(&l), 2);
    }
    LabelImage b = detail::read_nrrd_image(nrrd("short", 7, wide), "b");
    CHECK(b.labels.empty());
    CHECK(b.label_values.size() == 300);
    CHECK(b.label_values.front() == -100);
    REQUIRE(b.label_index16.size() == 343);
    CHECK(b.label_index8.empty());
    for (int v = 0; v < 343; ++v) CHECK(b.label_at(v) == (v < 300 ? v - 100 : 7));
    CHECK(label_image_problem(b).empty());

    // More than 65536 distinct labels: an intensity image, refused by the reader.
    std::string many;
    for (int v = 0; v < 42 * 42 * 42; ++v) {
        const int32_t l = v;
        many.append(reinterpret_cast<const char*>(&l), 4);
    }
    CHECK_THROWS_WITH(detail::read_nrrd_image(nrrd("int", 42, many), "c"),
                      Catch::Contains("more than 65536 distinct labels"));
}
