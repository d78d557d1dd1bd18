// MetaImage label images (ITK's MetaIO: .mha one file, .mhd header + data file): a text
// header of "Key = Value" lines, the last one ElementDataFile; with "LOCAL" the voxels
// follow that line in the same file, else they are in the file it names (relative to the
// header's directory; read through the caller's loader).
//
// Keys used (as MetaIO spells them; matched without regard to case): ObjectType (Image),
// NDims (3 only), DimSize, ElementType (MET_UCHAR, MET_CHAR, MET_USHORT, MET_SHORT, MET_UINT,
// MET_INT, MET_ULONG, MET_LONG (4 bytes in MetaIO), MET_FLOAT / MET_DOUBLE holding
// integers), ElementNumberOfChannels (1 only), ElementByteOrderMSB / BinaryDataByteOrderMSB,
// BinaryData (True only), CompressedData (zlib or gzip stream, inflated up to the size
// the voxels need and no further: a decompression bomb stops there), HeaderSize (bytes to
// skip in a data file; -1: the data is the file's last bytes), ElementSpacing (else
// ElementSize, else 1), Offset / Position / Origin, TransformMatrix / Rotation /
// Orientation (9 numbers: the directions of the axes i, j, k one after the other, as ITK
// reads them), AnatomicalOrientation (checked, then only reported: as in ITK, the world
// coordinates of a MetaImage file are LPS, LabelImage::frame Lps, whatever it says).
// Other keys (CenterOfRotation, ElementMin/Max, Comment, ...) are ignored. Refused with
// the key named: ElementDataFile LIST or a file-name pattern (one file per slice), a
// missing data file, sizes whose product overflows, data that ends early.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <zlib.h>

#include "bpm/errors.h"
#include "bpm/label_image.h"
#include "core/number_text.h"
#include "io/label_image_readers.h"
#include "io/surface_readers.h"

namespace bpm::detail {

namespace {

// `expected` bytes inflated from a zlib (or gzip) stream; more data than that is refused
// without producing it.
std::string inflate_exactly(std::string_view in, size_t expected, const std::string& name) {
    const auto fail = [&](const std::string& message) { throw InputError(name, "CompressedData: " + message); };
    // zlib expands at most ~1032 times: a smaller stream cannot hold the voxels.
    if (double(expected) > 1032.0 * double(in.size()) + 1024)
        fail("the voxels need " + std::to_string(expected) + " bytes, but " + std::to_string(in.size()) +
             " compressed bytes cannot hold that many (truncated?)");
    std::string out(expected, '\0');
    z_stream z{};
    if (inflateInit2(&z, 15 + 32) != Z_OK) fail("zlib cannot start");  // 15 + 32: zlib or gzip header
    size_t fed = 0, made = 0;
    int rc = Z_OK;
    while (rc == Z_OK) {
        const size_t feed = std::min<size_t>(in.size() - fed, 1u << 30);
        z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data())) + fed;
        z.avail_in = uInt(feed);
        const size_t room = std::min<size_t>(expected - made, 1u << 30);
        unsigned char spare;
        // With no room left, offer one byte: if zlib writes it, there is more data than the voxels need.
        z.next_out = room > 0 ? reinterpret_cast<Bytef*>(&out[made]) : &spare;
        z.avail_out = room > 0 ? uInt(room) : 1;
        rc = inflate(&z, Z_NO_FLUSH);
        const size_t produced = (room > 0 ? room : 1) - z.avail_out;
        fed += feed - z.avail_in;
        if (room == 0 && produced > 0) {
            inflateEnd(&z);
            fail("the stream holds more than the " + std::to_string(expected) + " bytes the voxels need");
        }
        made += produced;
        if (rc == Z_OK && produced == 0 && feed - z.avail_in == 0) rc = Z_BUF_ERROR;
    }
    inflateEnd(&z);
    if (rc != Z_STREAM_END) {
        fail(std::string(rc == Z_DATA_ERROR ? "not valid zlib data" : rc == Z_BUF_ERROR ? "the stream ends early" : "zlib error") +
             " after " + std::to_string(made) + " of " + std::to_string(expected) + " bytes");
    }
    if (made != expected)
        fail("the stream holds " + std::to_string(made) + " bytes, the voxels need " + std::to_string(expected));
    return out;
}

}  // namespace

LabelImage read_metaimage_image(std::string_view bytes, const std::string& name, const DataFileLoader& load,
                                std::vector<std::string>* notes) {
    const auto fail = [&](const std::string& message) -> void { throw InputError(name, message); };
    // Header lines up to ElementDataFile (which MetaIO requires to be the last key).
    std::map<std::string, std::pair<std::string, std::string>> field;  // lower-case key -> (key, value)
    HeaderLines lines(bytes);
    std::string_view line;
    bool ended = false;
    while (lines.next(line)) {
        if (header_trim(line).empty()) continue;
        const size_t eq = line.find('=');
        if (eq == std::string_view::npos)
            fail("line " + std::to_string(lines.number()) + ": expected 'Key = Value', found " + quote_token(line.substr(0, 80)));
        const std::string key = header_trim(line.substr(0, eq));
        if (key.empty() || key.size() > 64)
            fail("line " + std::to_string(lines.number()) + ": expected 'Key = Value', found " + quote_token(line.substr(0, 80)));
        field[header_lower(key)] = {key, header_trim(line.substr(eq + 1))};
        if (header_lower(key) == "elementdatafile") {
            ended = true;
            break;
        }
    }
    if (!ended) fail("key ElementDataFile is missing: the header has no end (truncated?)");
    const auto has = [&](const char* key) { return field.count(key) > 0; };
    const auto value = [&](const char* key) -> const std::string& { return field.at(key).second; };
    const auto need = [&](const char* key, const char* spelled) -> const std::string& {
        if (!has(key)) fail(std::string("key ") + spelled + " is missing");
        return value(key);
    };
    const auto boolean = [&](const char* key, const char* spelled) {
        if (!has(key)) return false;
        const std::string v = header_lower(value(key));
        if (v == "true" || v == "1") return true;
        if (v == "false" || v == "0") return false;
        fail(std::string("key ") + spelled + " is " + quote_token(value(key)) + ", not True or False");
        return false;
    };
    const auto numbers = [&](const char* key, const char* spelled, size_t count) {
        const std::vector<std::string> w = header_words(value(key));
        if (w.size() != count)
            fail(std::string("key ") + spelled + " has " + std::to_string(w.size()) + " values, expected " + std::to_string(count));
        std::vector<double> out(count);
        for (size_t i = 0; i < count; ++i) {
            const auto [p, ec] = parse_double(w[i].data(), w[i].data() + w[i].size(), out[i]);
            if (ec != std::errc() || p != w[i].data() + w[i].size() || !std::isfinite(out[i]))
                fail(std::string("key ") + spelled + ": " + quote_token(w[i]) + " is not a finite number");
        }
        return out;
    };

    if (has("objecttype") && header_lower(value("objecttype")) != "image")
        fail("key ObjectType is " + quote_token(value("objecttype")) + ", not Image");
    {
        const std::string& n = need("ndims", "NDims");
        if (header_trim(n) != "3")
            fail("key NDims is " + quote_token(n) + "; a label image has 3 dimensions");
    }
    if (has("elementnumberofchannels") && header_trim(value("elementnumberofchannels")) != "1")
        fail("key ElementNumberOfChannels is " + quote_token(value("elementnumberofchannels")) +
             "; a label image has one value per voxel");
    if (has("binarydata") && !boolean("binarydata", "BinaryData"))
        fail("key BinaryData is False (voxels as text); bpm reads binary MetaImage data");

    LabelImage image;
    {
        const std::vector<std::string> w = header_words(need("dimsize", "DimSize"));
        if (w.size() != 3) fail("key DimSize has " + std::to_string(w.size()) + " values, expected 3");
        for (int d = 0; d < 3; ++d) {
            int64_t n = 0;
            const std::string& t = w[size_t(d)];
            const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), n);
            if (ec != std::errc() || p != t.data() + t.size() || n < 1 || n > (int64_t(1) << 31))
                fail("key DimSize: " + quote_token(t) + " is not a size from 1 to 2^31");
            image.size[size_t(d)] = n;
        }
        if (double(image.size[0]) * double(image.size[1]) * double(image.size[2]) > 1e11)
            fail("key DimSize: " + std::to_string(image.size[0]) + " x " + std::to_string(image.size[1]) + " x " +
                 std::to_string(image.size[2]) + " voxels is too large");
    }
    const std::string type_text = need("elementtype", "ElementType");
    VoxelType type = VoxelType::U8;  // set below, or fail() throws (clang cannot tell: -Wsometimes-uninitialized)
    {
        const std::string t = header_lower(type_text);
        if (t == "met_uchar") type = VoxelType::U8;
        else if (t == "met_char") type = VoxelType::I8;
        else if (t == "met_ushort") type = VoxelType::U16;
        else if (t == "met_short") type = VoxelType::I16;
        else if (t == "met_uint" || t == "met_ulong") type = VoxelType::U32;
        else if (t == "met_int" || t == "met_long") type = VoxelType::I32;
        else if (t == "met_float") type = VoxelType::F32;
        else if (t == "met_double") type = VoxelType::F64;
        else {
            fail("key ElementType is " + quote_token(type_text) +
                 "; a label image needs integer labels (MET_UCHAR, MET_CHAR, MET_USHORT, MET_SHORT, MET_UINT, MET_INT, "
                 "MET_ULONG, MET_LONG; or MET_FLOAT / MET_DOUBLE holding integers)");
        }
    }
    bool msb = false;
    if (has("elementbyteordermsb")) msb = boolean("elementbyteordermsb", "ElementByteOrderMSB");
    else if (has("binarydatabyteordermsb")) msb = boolean("binarydatabyteordermsb", "BinaryDataByteOrderMSB");
    const bool swap = voxel_type_size(type) > 1 && msb != InputCursor::host_is_big_endian();

    // Geometry.
    std::vector<double> spacing{1, 1, 1};
    if (has("elementspacing")) spacing = numbers("elementspacing", "ElementSpacing", 3);
    else if (has("elementsize")) spacing = numbers("elementsize", "ElementSize", 3);
    for (int d = 0; d < 3; ++d) {
        if (!(spacing[size_t(d)] > 0))
            fail(std::string("key ") + (has("elementspacing") ? "ElementSpacing" : "ElementSize") + ": " +
                 std::to_string(spacing[size_t(d)]) + " is not a positive voxel size");
        image.spacing[size_t(d)] = spacing[size_t(d)];
    }
    for (const auto& [key, spelled] : {std::pair{"offset", "Offset"}, {"position", "Position"}, {"origin", "Origin"}})
        if (has(key)) {
            const std::vector<double> o = numbers(key, spelled, 3);
            image.origin = {o[0], o[1], o[2]};
            break;
        }
    std::string placed = "no TransformMatrix: axes x, y, z";
    for (const auto& [key, spelled] :
         {std::pair{"transformmatrix", "TransformMatrix"}, {"rotation", "Rotation"}, {"orientation", "Orientation"}})
        if (has(key)) {
            const std::vector<double> m = numbers(key, spelled, 9);
            for (int axis = 0; axis < 3; ++axis) {
                const double* a = &m[3 * size_t(axis)];
                const double len = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
                if (!(len > 0) || !std::isfinite(len))
                    fail(std::string("key ") + spelled + ": the direction of axis " + std::to_string(axis) + " has length 0");
                // Column `axis` of the direction matrix.
                for (int r = 0; r < 3; ++r) image.direction[3 * size_t(r) + size_t(axis)] = a[r] / len;
            }
            placed = std::string("placed by the ") + spelled;
            break;
        }
    std::string orientation;
    if (has("anatomicalorientation")) {
        // Three letters, one of R/L, A/P, S/I each ('?' unknown), as MetaIO writes them.
        const std::string o = header_trim(value("anatomicalorientation"));
        bool good = o.size() == 3;
        int seen[3] = {0, 0, 0};
        for (const char c : o) {
            const char u = char(std::toupper(static_cast<unsigned char>(c)));
            const int axis = u == 'R' || u == 'L' ? 0 : u == 'A' || u == 'P' ? 1 : u == 'S' || u == 'I' ? 2 : u == '?' ? -1 : -2;
            if (axis == -2 || (axis >= 0 && seen[axis]++)) good = false;
        }
        if (!good)
            fail("key AnatomicalOrientation is " + quote_token(o) + ", not three letters of R/L, A/P, S/I (e.g. RAI)");
        orientation = o;
    }
    image.frame = ImageFrame::Lps;

    // Data.
    const int size = voxel_type_size(type);
    const double needed_double = double(image.num_voxels()) * size;
    const size_t needed = size_t(needed_double);
    const std::string& data_file = field.at("elementdatafile").second;
    std::string loaded;
    std::string_view data;
    std::string source;  // for messages: "after the header" or "data file 'x.raw'"
    if (header_lower(data_file) == "local") {
        data = bytes.substr(lines.offset());
        source = "the data after the header";
    } else {
        if (data_file.empty()) fail("key ElementDataFile is empty");
        if (header_lower(data_file).rfind("list", 0) == 0 || data_file.find('%') != std::string::npos ||
            header_words(data_file).size() > 1)
            fail("key ElementDataFile is " + quote_token(data_file) +
                 ": the voxels are split over several files (one per slice); bpm reads one data file");
        if (!load)
            fail("key ElementDataFile names the data file " + quote_token(data_file) +
                 "; reading from memory or standard input, it cannot be found: give the header's path");
        try {
            loaded = load(data_file);
        } catch (const InputError& e) {
            fail("key ElementDataFile: the data file " + quote_token(data_file) + " cannot be read: " + e.where() + ": " +
                 e.what());
        }
        data = loaded;
        source = "data file " + quote_token(data_file);
    }
    if (has("headersize")) {
        int64_t skip = 0;
        const std::string& t = value("headersize");
        const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), skip);
        if (ec != std::errc() || p != t.data() + t.size() || skip < -1)
            fail("key HeaderSize is " + quote_token(t) + ", not a byte count (or -1)");
        const bool compressed = boolean("compresseddata", "CompressedData");
        if (skip == -1) {
            if (compressed) fail("key HeaderSize is -1 (data at the end of the file), which compressed data cannot use");
            if (needed_double > double(data.size()))
                fail("truncated: " + source + " has " + std::to_string(data.size()) + " bytes, the voxels need " +
                     std::to_string(needed));
            data = data.substr(data.size() - needed);
        } else {
            if (size_t(skip) > data.size())
                fail("key HeaderSize is " + t + ", beyond the end of " + source + " (" + std::to_string(data.size()) + " bytes)");
            data = data.substr(size_t(skip));
        }
    }
    std::string inflated;
    const bool compressed = boolean("compresseddata", "CompressedData");
    if (compressed) {
        if (has("compresseddatasize")) {
            int64_t n = 0;
            const std::string& t = value("compresseddatasize");
            const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), n);
            if (ec != std::errc() || p != t.data() + t.size() || n < 0)
                fail("key CompressedDataSize is " + quote_token(t) + ", not a byte count");
            if (uint64_t(n) > data.size())
                fail("truncated: key CompressedDataSize is " + t + ", but " + source + " has " + std::to_string(data.size()) +
                     " bytes");
            data = data.substr(0, size_t(n));
        }
        inflated = inflate_exactly(data, needed, name);
        data = inflated;
    } else if (needed_double > double(data.size())) {
        fail("truncated: " + std::to_string(image.size[0]) + " x " + std::to_string(image.size[1]) + " x " +
             std::to_string(image.size[2]) + " voxels of " + voxel_type_name(type) + " need " + std::to_string(needed) +
             " bytes, but " + source + " has " + std::to_string(data.size()));
    }
    decode_labels(reinterpret_cast<const unsigned char*>(data.data()), type, swap, 1, 0, "", image, name);
    if (notes) {
        notes->push_back("MetaImage label image: " + std::to_string(image.size[0]) + " x " + std::to_string(image.size[1]) +
                         " x " + std::to_string(image.size[2]) + " voxels of " + voxel_type_name(type) +
                         (compressed ? " (compressed)" : "") + (header_lower(data_file) == "local" ? "" : " in " + quote_token(data_file)) +
                         ", " + placed + "; world coordinates LPS" +
                         (orientation.empty() ? std::string() : " (AnatomicalOrientation " + orientation + ")"));
    }
    return image;
}

}  // namespace bpm::detail
