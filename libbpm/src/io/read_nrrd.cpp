// NRRD label images (.nrrd, and 3D Slicer's segmentations .seg.nrrd): a text header
// "NRRD000N" + "field: value" lines (and "key:=value" pairs) up to an empty line, then the
// data (attached only: "data file" is refused).
//
// Fields used: type (the integer types, float/double holding integers), dimension (3; or
// 4 with a first axis of size 1, as a one-layer .seg.nrrd may be), sizes, encoding (raw,
// gzip/gz, ascii/text/txt), endian, space directions (with "none" for a non-spatial first
// axis) and space origin, or else spacings. Without directions the axes are x, y, z.
// Other fields (kinds, measurement frame, ...) are ignored; "byte skip" and "line skip"
// other than 0 are refused.
//
// Frame (LabelImage::frame): "space" left-posterior-superior (LPS, 3D Slicer's) and
// right-anterior-superior (RAS) are taken as they are; left-anterior-superior (LAS) is
// made LPS by negating y (the triangles are still oriented, the surface code sees the
// reflection). Spaces without an anatomical frame (scanner-xyz, 3D-right-handed,
// 3D-left-handed) and files without "space" are passed through: frame Unknown, the
// coordinates as the file gives them, said in a note. 4-D spaces (...-time) are refused.
//
// .seg.nrrd key/values: Segment<N>_LabelValue:=L and Segment<N>_Name:=NAME name label L's
// material (a '|' in a name becomes '_', since "A|B" names the patches); segments in more
// than one layer (Segment<N>_Layer other than 0, i.e. overlapping segments) are refused.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>

#include "bpm/errors.h"
#include "bpm/label_image.h"
#include "core/gzip.h"
#include "core/number_text.h"
#include "io/label_image_readers.h"
#include "io/surface_readers.h"

namespace bpm::detail {

namespace {

}  // namespace

LabelImage read_nrrd_image(std::string_view bytes, const std::string& name, std::vector<std::string>* notes) {
    const auto fail = [&](const std::string& message) -> void { throw InputError(name, message); };
    if (bytes.substr(0, 4) != "NRRD") fail("the file does not start with 'NRRD' (the magic of NRRD files)");
    // Header lines up to the first empty line.
    std::map<std::string, std::string> field;
    std::map<std::string, std::string> keys;  // key:=value pairs
    HeaderLines lines(bytes);
    std::string_view line;
    bool ended = false;
    while (lines.next(line)) {
        if (lines.number() == 1) continue;  // NRRD000N
        if (line.empty()) {
            ended = true;
            break;
        }
        if (line[0] == '#') continue;
        const size_t kv = line.find(":=");
        const size_t colon = line.find(": ");
        if (kv != std::string_view::npos && (colon == std::string_view::npos || kv < colon)) {
            keys[std::string(line.substr(0, kv))] = std::string(line.substr(kv + 2));
            continue;
        }
        if (colon == std::string_view::npos)
            fail("line " + std::to_string(lines.number()) + ": expected 'field: value', found " + quote_token(line));
        field[header_lower(header_trim(line.substr(0, colon)))] = header_trim(line.substr(colon + 2));
    }
    if (field.count("data file") || field.count("datafile"))
        fail("field 'data file': the voxels are in another file (a detached header, .nhdr); bpm reads NRRD files "
             "with attached data (.nrrd, .seg.nrrd)");
    if (!ended) fail("the header has no empty line after it: the file ends inside the header (truncated?)");
    const auto need = [&](const char* key) -> const std::string& {
        const auto it = field.find(key);
        if (it == field.end()) fail(std::string("field '") + key + "' is missing");
        return it->second;
    };
    const std::string type_text = header_lower(need("type"));
    VoxelType type;
    if (type_text == "uchar" || type_text == "unsigned char" || type_text == "uint8" || type_text == "uint8_t")
        type = VoxelType::U8;
    else if (type_text == "signed char" || type_text == "int8" || type_text == "int8_t")
        type = VoxelType::I8;
    else if (type_text == "short" || type_text == "short int" || type_text == "signed short" ||
             type_text == "signed short int" || type_text == "int16" || type_text == "int16_t")
        type = VoxelType::I16;
    else if (type_text == "ushort" || type_text == "unsigned short" || type_text == "unsigned short int" ||
             type_text == "uint16" || type_text == "uint16_t")
        type = VoxelType::U16;
    else if (type_text == "int" || type_text == "signed int" || type_text == "int32" || type_text == "int32_t")
        type = VoxelType::I32;
    else if (type_text == "uint" || type_text == "unsigned int" || type_text == "uint32" || type_text == "uint32_t")
        type = VoxelType::U32;
    else if (type_text == "float")
        type = VoxelType::F32;
    else if (type_text == "double")
        type = VoxelType::F64;
    else
        fail("field 'type' is " + quote_token(type_text) + "; a label image needs integer labels (uchar, short, "
             "ushort, int, uint, signed char; or float/double holding integers)");

    const std::vector<std::string> sizes_text = header_words(need("sizes"));
    const std::string dimension_text = need("dimension");
    int64_t dimension = 0;
    {
        const auto [p, ec] = std::from_chars(dimension_text.data(), dimension_text.data() + dimension_text.size(), dimension);
        if (ec != std::errc() || p != dimension_text.data() + dimension_text.size())
            fail("field 'dimension' is " + quote_token(dimension_text) + ", not a number");
    }
    if (int64_t(sizes_text.size()) != dimension)
        fail("field 'sizes' has " + std::to_string(sizes_text.size()) + " values for dimension " + std::to_string(dimension));
    std::vector<int64_t> sizes;
    for (const std::string& w : sizes_text) {
        int64_t n = 0;
        const auto [p, ec] = std::from_chars(w.data(), w.data() + w.size(), n);
        if (ec != std::errc() || p != w.data() + w.size() || n < 1)
            fail("field 'sizes': " + quote_token(w) + " is not a size >= 1");
        sizes.push_back(n);
    }
    // A .seg.nrrd of one layer may carry a first axis of size 1 (kind "list").
    size_t first = 0;
    if (dimension == 4 && sizes[0] == 1) first = 1;
    else if (dimension != 3)
        fail("field 'dimension' is " + std::to_string(dimension) +
             (dimension == 4 ? " with " + std::to_string(sizes[0]) + " layers (overlapping segments, or a time series)"
                             : std::string()) +
             "; a label image has 3 dimensions (export the segmentation as a labelmap)");
    LabelImage image;
    for (int d = 0; d < 3; ++d) image.size[size_t(d)] = sizes[first + size_t(d)];
    if (double(image.size[0]) * double(image.size[1]) * double(image.size[2]) > 1e11)
        fail("field 'sizes': " + std::to_string(image.size[0]) + " x " + std::to_string(image.size[1]) + " x " +
             std::to_string(image.size[2]) + " voxels is too large");

    // Geometry.
    const auto parse_vector = [&](const std::string& text, const std::string& what) -> Vec3 {
        // "(x,y,z)"
        std::string t = header_trim(text);
        if (t.size() < 2 || t.front() != '(' || t.back() != ')') fail(what + ": expected (x,y,z), found " + quote_token(t));
        t = t.substr(1, t.size() - 2);
        Vec3 v{0, 0, 0};
        size_t at = 0;
        for (int c = 0; c < 3; ++c) {
            size_t comma = c < 2 ? t.find(',', at) : t.size();
            if (comma == std::string::npos) fail(what + ": expected 3 components in " + quote_token(text));
            const std::string number = header_trim(std::string_view(t).substr(at, comma - at));
            const auto [p, ec] = parse_double(number.data(), number.data() + number.size(), v[size_t(c)]);
            if (ec != std::errc() || p != number.data() + number.size() || !std::isfinite(v[size_t(c)]))
                fail(what + ": " + quote_token(number) + " is not a finite number");
            at = comma + 1;
        }
        if (at < t.size()) fail(what + ": more than 3 components in " + quote_token(text));
        return v;
    };
    std::array<Vec3, 3> axes{Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};
    std::string method = "no space directions: axes x, y, z";
    if (const auto it = field.find("space directions"); it != field.end()) {
        std::vector<std::string> parts = header_words(it->second);
        if (int64_t(parts.size()) != dimension)
            fail("field 'space directions' has " + std::to_string(parts.size()) + " entries for dimension " +
                 std::to_string(dimension));
        if (first == 1 && parts[0] != "none") fail("field 'space directions': the layer axis must be 'none'");
        for (int d = 0; d < 3; ++d)
            axes[size_t(d)] = parse_vector(parts[first + size_t(d)], "field 'space directions', axis " + std::to_string(d));
        method = "space directions";
    } else if (const auto sp = field.find("spacings"); sp != field.end()) {
        const std::vector<std::string> parts = header_words(sp->second);
        if (int64_t(parts.size()) != dimension) fail("field 'spacings' has " + std::to_string(parts.size()) + " values");
        for (int d = 0; d < 3; ++d) {
            double x = 0;
            const std::string& w = parts[first + size_t(d)];
            const auto [p, ec] = parse_double(w.data(), w.data() + w.size(), x);
            if (ec != std::errc() || p != w.data() + w.size() || !(x > 0) || !std::isfinite(x))
                fail("field 'spacings': " + quote_token(w) + " is not a positive number");
            axes[size_t(d)] = Vec3{0, 0, 0};
            axes[size_t(d)][size_t(d)] = x;
        }
        method = "spacings";
    }
    for (int d = 0; d < 3; ++d) {
        const double len = norm(axes[size_t(d)]);
        if (!(len > 0)) fail("the direction of axis " + std::to_string(d) + " has length 0");
        image.spacing[size_t(d)] = len;
        for (int r = 0; r < 3; ++r) image.direction[3 * size_t(r) + size_t(d)] = axes[size_t(d)][size_t(r)] / len;
    }
    if (const auto it = field.find("space origin"); it != field.end()) {
        const Vec3 o = parse_vector(it->second, "field 'space origin'");
        image.origin = {o[0], o[1], o[2]};
    }
    std::string space_note;
    if (const auto it = field.find("space"); it != field.end()) {
        const std::string space = header_lower(it->second);
        if (space == "left-posterior-superior" || space == "lps") {
            image.frame = ImageFrame::Lps;
        } else if (space == "right-anterior-superior" || space == "ras") {
            image.frame = ImageFrame::Ras;
        } else if (space == "left-anterior-superior" || space == "las") {
            image.frame = ImageFrame::Lps;  // LAS -> LPS: y negated
            image.origin[1] = -image.origin[1];
            for (int c = 0; c < 3; ++c) image.direction[3 + size_t(c)] = -image.direction[3 + size_t(c)];
            space_note = " (LAS, taken as LPS with y negated)";
        } else if (space == "scanner-xyz" || space == "3d-right-handed" || space == "3d-left-handed") {
            space_note = " (space " + it->second + ": no anatomical frame)";
        } else {
            fail("field 'space' is " + quote_token(it->second) +
                 "; bpm reads 3-D spaces: left-posterior-superior, right-anterior-superior, left-anterior-superior, "
                 "scanner-xyz, 3D-right-handed, 3D-left-handed");
        }
    } else if (field.count("space dimension")) {
        space_note = " (no space: no anatomical frame)";
    }
    for (const char* skip : {"byte skip", "line skip"})
        if (const auto it = field.find(skip); it != field.end() && it->second != "0")
            fail(std::string("field '") + skip + "' is " + quote_token(it->second) + "; only 0 is supported");

    // Segment names (.seg.nrrd).
    {
        std::map<std::string, std::pair<std::string, std::string>> segments;  // id -> (label value, name)
        for (const auto& [key, value] : keys) {
            if (key.rfind("Segment", 0) != 0) continue;
            const size_t us = key.find('_');
            if (us == std::string::npos) continue;
            const std::string id = key.substr(7, us - 7), what = key.substr(us + 1);
            if (what == "LabelValue") segments[id].first = value;
            else if (what == "Name") segments[id].second = value;
            else if (what == "Layer" && header_trim(value) != "0")
                fail("key " + key + " is " + quote_token(value) + ": the segments overlap (several layers); bpm needs "
                     "one label per voxel (3D Slicer: export the segmentation as a labelmap)");
        }
        for (const auto& [id, seg] : segments) {
            int64_t label = 0;
            const std::string v = header_trim(seg.first);
            const auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), label);
            if (v.empty() || ec != std::errc() || p != v.data() + v.size() || seg.second.empty()) continue;
            std::string material = seg.second;
            std::replace(material.begin(), material.end(), '|', '_');
            image.names.push_back({int32_t(label), material});
        }
    }

    // Data.
    const std::string encoding = header_lower(need("encoding"));
    std::string_view data = bytes.substr(lines.offset());
    std::string inflated;
    const int64_t voxels = image.num_voxels();
    const int size = voxel_type_size(type);
    if (encoding == "gzip" || encoding == "gz") {
        // At most what the voxels need (and a little): a bomb stops there.
        // The error names the file (InputError::where), as every reader's does; what is wrong
        // with the data goes into the message.
        const std::string packed(data);
        if (!looks_like_gzip(packed))
            fail("field 'encoding' is gzip, but the data after the header does not start with the gzip magic bytes 1f 8b 08");
        try {
            inflated = decompress_if_gzip(packed, name, false, size_t(std::min<double>(double(voxels) * size + 1024, 1e11)));
        } catch (const InputError& e) {
            throw InputError(name, std::string("the voxels (encoding gzip): ") + e.what());
        }
        data = inflated;
    } else if (encoding == "ascii" || encoding == "text" || encoding == "txt") {
        const double most = double(data.size()) / 2 + 1;  // a number and a separator each
        if (double(voxels) > most)
            fail("truncated: " + std::to_string(voxels) + " voxels announced, the ascii data cannot hold them");
        std::string binary;
        binary.reserve(size_t(voxels) * 8);
        InputCursor in(data, name);
        for (int64_t v = 0; v < voxels; ++v) {
            const double x = in.any_double(Label("voxel value ", v));
            binary.append(reinterpret_cast<const char*>(&x), 8);
        }
        inflated = std::move(binary);
        data = inflated;
        type = VoxelType::F64;
    } else if (encoding != "raw") {
        fail("field 'encoding' is " + quote_token(encoding) + "; bpm reads raw, gzip and ascii");
    }
    bool swap = false;
    if (encoding == "raw" || encoding == "gzip" || encoding == "gz") {
        if (size > 1) {
            const auto it = field.find("endian");
            if (it == field.end()) fail("field 'endian' is missing (needed for " + std::string(voxel_type_name(type)) + ")");
            const std::string e = header_lower(it->second);
            if (e != "little" && e != "big") fail("field 'endian' is " + quote_token(it->second) + ", not little or big");
            swap = (e == "big") != InputCursor::host_is_big_endian();
        }
    }
    const double needed = double(voxels) * voxel_type_size(type);
    if (needed > double(data.size()))
        fail("truncated: " + std::to_string(image.size[0]) + " x " + std::to_string(image.size[1]) + " x " +
             std::to_string(image.size[2]) + " voxels of " + voxel_type_name(type) + " need " +
             std::to_string(int64_t(needed)) + " bytes of " + encoding + " data, but there are " +
             std::to_string(data.size()));
    decode_labels(reinterpret_cast<const unsigned char*>(data.data()), type, swap, 1, 0, "", image, name);
    if (notes) {
        std::string named;
        for (const auto& [label, material] : image.names)
            named += (named.empty() ? "" : ", ") + std::to_string(label) + " = " + material;
        notes->push_back("NRRD label image: " + std::to_string(image.size[0]) + " x " + std::to_string(image.size[1]) +
                         " x " + std::to_string(image.size[2]) + " voxels of " + voxel_type_name(type) + " (" +
                         encoding + "), placed by the " + method + space_note +
                         (named.empty() ? std::string() : "; segments " + named));
    }
    return image;
}

}  // namespace bpm::detail
