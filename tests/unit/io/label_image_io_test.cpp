// Label image files (NIfTI-1, NRRD, MetaImage) read through read_surface_from_memory:
// files built in code from one label array. The same segmentation saved in different
// formats (each in its own world frame: NIfTI RAS, 3D Slicer / NRRD LPS) gives the same
// coordinates, in the frame asked for (SurfaceReadOptions::label_image.frame).
#include <catch2/catch.hpp>
#include <cstring>
#include <string>
#include <vector>
#include <zlib.h>

#include "bpm/errors.h"
#include "bpm/label_image.h"
#include "bpm/surface_io.h"

using namespace bpm;

namespace {

// An asymmetric label array (an L of label 1 and a block of label 2 to one side), so that
// a mirror or a turn would show: nx x ny x nz voxels, i fastest.
constexpr int kN[3] = {7, 6, 5};
std::vector<uint8_t> l_shape() {
    std::vector<uint8_t> l(size_t(kN[0] * kN[1] * kN[2]), 0);
    for (int k = 1; k < 4; ++k)
        for (int j = 1; j < 5; ++j)
            for (int i = 1; i < 6; ++i) {
                uint8_t v = 0;
                if (i < 3 || j < 2) v = 1;
                if (i >= 4 && j >= 3 && k < 3) v = 2;
                l[size_t(i + kN[0] * (j + kN[1] * k))] = v;
            }
    return l;
}

template <class T>
void put(std::string& s, size_t at, T value) {
    std::memcpy(&s[at], &value, sizeof value);
}

// NIfTI-1 (little endian) with an sform: voxel (i, j, k) at srow * (i, j, k, 1), RAS.
std::string nifti(const std::vector<uint8_t>& labels, const double srow[3][4]) {
    std::string h(352, '\0');
    put<int32_t>(h, 0, 348);
    const int16_t dim[8] = {3, int16_t(kN[0]), int16_t(kN[1]), int16_t(kN[2]), 1, 1, 1, 1};
    for (int i = 0; i < 8; ++i) put<int16_t>(h, 40 + 2 * size_t(i), dim[i]);
    put<int16_t>(h, 70, 2);  // uint8
    put<int16_t>(h, 72, 8);
    for (int i = 0; i < 4; ++i) put<float>(h, 76 + 4 * size_t(i), 1.0f);
    put<float>(h, 108, 352.0f);
    put<int16_t>(h, 254, 1);  // sform_code
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) put<float>(h, 280 + 16 * size_t(r) + 4 * size_t(c), float(srow[r][c]));
    h.replace(344, 4, std::string("n+1\0", 4));
    return h + std::string(labels.begin(), labels.end());
}

// NRRD, raw uint8, with the given space, directions and origin fields.
std::string nrrd(const std::vector<uint8_t>& labels, const std::string& space_fields) {
    std::string h = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: " + std::to_string(kN[0]) + " " + std::to_string(kN[1]) +
                    " " + std::to_string(kN[2]) + "\nencoding: raw\n" + space_fields + "\n";
    return h + std::string(labels.begin(), labels.end());
}

Surface read(const std::string& bytes, SurfaceFormat format, ImageFrame frame, SurfaceReadReport* report = nullptr) {
    SurfaceReadOptions options;
    options.label_image.frame = frame;
    return read_surface_from_memory(bytes, format, "image", options, report);
}

void check_same(const Surface& a, const Surface& b) {
    REQUIRE(a.num_vertices() == b.num_vertices());
    REQUIRE(a.triangles == b.triangles);
    CHECK(a.patches == b.patches);
    for (size_t v = 0; v < a.vertices.size(); ++v)
        for (int d = 0; d < 3; ++d) {
            INFO("vertex " << v << " axis " << d);
            CHECK(a.vertices[v][d] == Approx(b.vertices[v][d]).margin(1e-12));
        }
}

// A segmentation placed at voxel size 1, origin (-3, -2, -1) in RAS: the NIfTI sform is
// diagonal; the LPS file (3D Slicer) has directions (-1,0,0) (0,-1,0) (0,0,1), origin (3, 2, -1).
const double kSrow[3][4] = {{1, 0, 0, -3}, {0, 1, 0, -2}, {0, 0, 1, -1}};
const char* kLps = "space: left-posterior-superior\nspace directions: (-1,0,0) (0,-1,0) (0,0,1)\nspace origin: (3,2,-1)\n";
const char* kRas = "space: right-anterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: (-3,-2,-1)\n";

}  // namespace

TEST_CASE("label images: one segmentation as NIfTI (RAS) and as NRRD (LPS) gives the same coordinates") {
    const std::vector<uint8_t> labels = l_shape();
    SurfaceReadReport rn, rl;
    const Surface from_nifti = read(nifti(labels, kSrow), SurfaceFormat::Nifti, ImageFrame::Lps, &rn);
    const Surface from_nrrd = read(nrrd(labels, kLps), SurfaceFormat::Nrrd, ImageFrame::Lps, &rl);
    check_same(from_nifti, from_nrrd);
    CHECK(rn.frame == ImageFrame::Lps);
    CHECK(rl.frame == ImageFrame::Lps);
    // An NRRD in RAS too.
    check_same(from_nifti, read(nrrd(labels, kRas), SurfaceFormat::Nrrd, ImageFrame::Lps));
    // And all of them in RAS, where the NIfTI file is as it was.
    const Surface ras = read(nifti(labels, kSrow), SurfaceFormat::Nifti, ImageFrame::Ras);
    check_same(ras, read(nrrd(labels, kLps), SurfaceFormat::Nrrd, ImageFrame::Ras));
    // LPS is RAS turned about z: (x, y, z) -> (-x, -y, z), the same triangles.
    REQUIRE(ras.triangles == from_nifti.triangles);
    for (size_t v = 0; v < ras.vertices.size(); ++v) {
        CHECK(ras.vertices[v][0] == -from_nifti.vertices[v][0]);
        CHECK(ras.vertices[v][1] == -from_nifti.vertices[v][1]);
        CHECK(ras.vertices[v][2] == from_nifti.vertices[v][2]);
    }
    // Voxel (0, 0, 0) is at RAS (-3, -2, -1): the surface lies at x >= -3.5 in RAS, x <= 3.5 in LPS.
    double lo = 1e9;
    for (const Vec3& p : ras.vertices) lo = std::min(lo, p[0]);
    CHECK(lo > -3.5);
}

TEST_CASE("label images: NRRD spaces without an anatomical frame are used as they are, LAS becomes LPS") {
    const std::vector<uint8_t> labels = l_shape();
    SurfaceReadReport report;
    const Surface scanner = read(nrrd(labels, "space: scanner-xyz\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n"
                                              "space origin: (-3,-2,-1)\n"),
                                 SurfaceFormat::Nrrd, ImageFrame::Lps, &report);
    CHECK(report.frame == ImageFrame::Unknown);
    // As given: the RAS coordinates of the NIfTI file, untouched.
    check_same(scanner, read(nifti(labels, kSrow), SurfaceFormat::Nifti, ImageFrame::Ras));
    (void)read(nrrd(labels, "spacings: 1 1 1\n"), SurfaceFormat::Nrrd, ImageFrame::Lps, &report);
    CHECK(report.frame == ImageFrame::Unknown);
    // LAS: x as LPS, y as RAS. The same place is (3, -2, -1) in LAS.
    const Surface las = read(nrrd(labels, "space: left-anterior-superior\nspace directions: (-1,0,0) (0,1,0) (0,0,1)\n"
                                          "space origin: (3,-2,-1)\n"),
                             SurfaceFormat::Nrrd, ImageFrame::Lps, &report);
    CHECK(report.frame == ImageFrame::Lps);
    check_same(las, read(nifti(labels, kSrow), SurfaceFormat::Nifti, ImageFrame::Lps));
    CHECK_THROWS_WITH(read(nrrd(labels, "space: right-anterior-superior-time\n"), SurfaceFormat::Nrrd, ImageFrame::Lps),
                      Catch::Contains("field 'space' is 'right-anterior-superior-time'"));
}

namespace {

// MetaImage with the voxels after the header (ElementDataFile = LOCAL); `extra` lines go
// before ElementDataFile; `data` replaces the raw uint8 voxels.
std::string mha(const std::vector<uint8_t>& labels, const std::string& extra, const std::string* data = nullptr,
                const std::string& type = "MET_UCHAR") {
    std::string h = "ObjectType = Image\nNDims = 3\nDimSize = " + std::to_string(kN[0]) + " " + std::to_string(kN[1]) + " " +
                    std::to_string(kN[2]) + "\nElementType = " + type + "\n" + extra + "ElementDataFile = LOCAL\n";
    return h + (data ? *data : std::string(labels.begin(), labels.end()));
}

// The LPS placement of the NIfTI file above (kSrow): axes -x, -y, z, origin (3, 2, -1).
const char* kMhaLps = "TransformMatrix = -1 0 0 0 -1 0 0 0 1\nOffset = 3 2 -1\nElementSpacing = 1 1 1\n"
                      "AnatomicalOrientation = RAI\n";

std::string zlib(const std::string& raw) {
    uLongf n = compressBound(uLong(raw.size()));
    std::string out(n, '\0');
    REQUIRE(compress(reinterpret_cast<Bytef*>(&out[0]), &n, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size())) == Z_OK);
    out.resize(n);
    return out;
}
}  // namespace

TEST_CASE("label images: MetaImage (LPS) gives the coordinates of the same segmentation as NIfTI and NRRD") {
    const std::vector<uint8_t> labels = l_shape();
    const Surface from_nifti = read(nifti(labels, kSrow), SurfaceFormat::Nifti, ImageFrame::Lps);
    SurfaceReadReport report;
    check_same(from_nifti, read(mha(labels, kMhaLps), SurfaceFormat::MetaImage, ImageFrame::Lps, &report));
    CHECK(report.frame == ImageFrame::Lps);
    // zlib-compressed, with and without CompressedDataSize.
    const std::string packed = zlib(std::string(labels.begin(), labels.end()));
    check_same(from_nifti, read(mha(labels, std::string(kMhaLps) + "CompressedData = True\n", &packed),
                                SurfaceFormat::MetaImage, ImageFrame::Lps));
    check_same(from_nifti, read(mha(labels, std::string(kMhaLps) + "CompressedData = True\nCompressedDataSize = " +
                                                std::to_string(packed.size()) + "\n", &packed),
                                SurfaceFormat::MetaImage, ImageFrame::Lps));
    // Big-endian 16-bit labels; MET_LONG (4 bytes in MetaIO), little-endian.
    std::string be, le32;
    for (const uint8_t l : labels) {
        be += '\0', be += char(l);
        le32 += char(l), le32 += std::string(3, '\0');
    }
    check_same(from_nifti, read(mha(labels, std::string(kMhaLps) + "ElementByteOrderMSB = True\n", &be, "MET_USHORT"),
                                SurfaceFormat::MetaImage, ImageFrame::Lps));
    check_same(from_nifti, read(mha(labels, std::string(kMhaLps) + "BinaryDataByteOrderMSB = False\n", &le32, "MET_LONG"),
                                SurfaceFormat::MetaImage, ImageFrame::Lps));
    // In RAS as NIfTI gives it.
    check_same(read(nifti(labels, kSrow), SurfaceFormat::Nifti, ImageFrame::Ras),
               read(mha(labels, kMhaLps), SurfaceFormat::MetaImage, ImageFrame::Ras));
    // Told by its head without a format.
    CHECK(surface_format_from_name("mha") == SurfaceFormat::MetaImage);
    CHECK(surface_format_from_path("a/b.mhd") == SurfaceFormat::MetaImage);
}

TEST_CASE("label images: bad MetaImage files are refused naming the key, never read past their end") {
    const std::vector<uint8_t> labels = l_shape();
    const auto refused = [&](const std::string& bytes, const std::string& words) {
        INFO(words);
        CHECK_THROWS_WITH(read(bytes, SurfaceFormat::MetaImage, ImageFrame::Lps), Catch::Contains(words));
    };
    const std::string raw(labels.begin(), labels.end());
    const std::string short_data = raw.substr(0, raw.size() - 1);
    refused(mha(labels, "", &short_data), "truncated: 7 x 6 x 5 voxels of uint8 need 210 bytes, but the data after the header has 209");
    refused(mha(labels, "", nullptr, "MET_STRING"), "key ElementType is 'MET_STRING'");
    refused("ObjectType = Image\nNDims = 2\nDimSize = 4 4\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n", "key NDims is '2'");
    refused(mha(labels, "ElementNumberOfChannels = 3\n"), "key ElementNumberOfChannels is '3'");
    refused("ObjectType = Image\nNDims = 3\nDimSize = 2147483648 2147483648 2147483648\nElementType = MET_UCHAR\n"
            "ElementDataFile = LOCAL\n",
            "key DimSize: 2147483648 x 2147483648 x 2147483648 voxels is too large");
    refused("ObjectType = Image\nNDims = 3\nDimSize = 4 -4 4\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n",
            "key DimSize: '-4' is not a size");
    refused(mha(labels, "ElementSpacing = 1 0 1\n"), "ElementSpacing: 0");
    refused(mha(labels, "TransformMatrix = 1 0 0 0 1 0\n"), "key TransformMatrix has 6 values, expected 9");
    refused(mha(labels, "AnatomicalOrientation = RRS\n"), "key AnatomicalOrientation is 'RRS'");
    refused(mha(labels, "ElementByteOrderMSB = maybe\n"), "key ElementByteOrderMSB is 'maybe', not True or False");
    refused("ObjectType = Image\nNDims = 3\nDimSize = 7 6 5\nElementType = MET_UCHAR\n", "key ElementDataFile is missing");
    refused("ObjectType = Image\nNDims = 3\nDimSize = 7 6 5\nElementType = MET_UCHAR\nElementDataFile = labels.raw\n",
            "names the data file 'labels.raw'; reading from memory or standard input, it cannot be found");
    refused("ObjectType = Image\nNDims = 3\nDimSize = 7 6 5\nElementType = MET_UCHAR\nElementDataFile = slice%03d.raw 0 4 1\n",
            "several files (one per slice)");
    refused(mha(labels, "BinaryData = False\n"), "key BinaryData is False");
    // Compressed: garbage, a stream cut short, and a bomb (a stream that inflates beyond the
    // voxels' size is stopped there, not inflated to the end).
    const std::string packed = zlib(raw);
    const std::string cut = packed.substr(0, packed.size() / 2), junk = "not zlib data at all";
    refused(mha(labels, "CompressedData = True\n", &junk), "CompressedData: not valid zlib data");
    refused(mha(labels, "CompressedData = True\n", &cut), "CompressedData: the stream ends early");
    const std::string bomb = zlib(std::string(size_t(200) << 20, '\1'));  // 200 MB of label 1 in ~200 kB
    refused(mha(labels, "CompressedData = True\n", &bomb), "holds more than the 210 bytes the voxels need");
    refused(mha(labels, "CompressedData = True\nCompressedDataSize = 99999\n", &packed), "truncated: key CompressedDataSize is 99999");
    // A non-integer value in a float image names the voxel.
    std::string floats;
    for (const uint8_t l : labels) {
        const float x = l + 0.25f;
        floats.append(reinterpret_cast<const char*>(&x), 4);
    }
    refused(mha(labels, "", &floats, "MET_FLOAT"), "voxel (0, 0, 0) has the value 0.25");
}

TEST_CASE("label images: NRRD gzip data that is not gzip, or corrupt, is an error naming the file") {
    // Found by fuzz_read_nrrd: the error named "image (gzip data)" instead of the input.
    const std::vector<uint8_t> labels = l_shape();
    std::string file = nrrd(labels, "");
    file.replace(file.find("encoding: raw"), 13, "encoding: gzip");
    for (const std::string& data : {std::string("plain bytes"), std::string("\x1f\x8b\x08\x00garbage", 12)}) {
        const std::string bytes = file.substr(0, file.find("\n\n") + 2) + data;
        try {
            (void)read(bytes, SurfaceFormat::Nrrd, ImageFrame::Lps);
            FAIL("accepted");
        } catch (const InputError& e) {
            CHECK(e.where() == "image");
            CHECK(std::string(e.what()).find("gzip") != std::string::npos);
        }
    }
}
