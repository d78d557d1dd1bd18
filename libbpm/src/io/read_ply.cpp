// PLY reader (Stanford polygon format): ascii, binary_little_endian, binary_big_endian.
//
// Every element and property type of PLY 1.0 is understood, so unknown elements
// (edges, materials, ...) and unknown properties (normals, colours, ...) are skipped
// rather than refused. Used:
//   element `vertex`: scalar properties x, y, z (any numeric type); every other scalar
//                     property becomes per-vertex data (Surface::vertex_data): nx/ny/nz
//                     as "normals", red/green/blue(/alpha) as "colors", u/v (or s/t,
//                     texture_u/texture_v) as "texture_coordinates", the rest one array
//                     each under its own name (list properties of vertices are skipped)
//   element `face`:   the list property `vertex_indices` (or `vertex_index`), any count and
//                     index type, three entries per face (polygons are refused, or
//                     with accept_polygons triangulated: the triangulate-polygons repair);
//                     the first scalar property, in header order, named patch, material,
//                     region, label or physical gives the patch id (an integer value).
// A file without a face element, or with no faces, has no triangles; read_surface()
// refuses that with its own message.
#include <algorithm>
#include <cctype>
#include <string>

#include "io/surface_readers.h"

namespace bpm::detail {

namespace {

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool ply_type_from_name(std::string_view name, PlyType& type) {
    struct Entry {
        const char* name;
        PlyType type;
    };
    static const Entry entries[] = {
        {"char", PlyType::Int8},     {"int8", PlyType::Int8},      {"uchar", PlyType::UInt8},
        {"uint8", PlyType::UInt8},   {"short", PlyType::Int16},    {"int16", PlyType::Int16},
        {"ushort", PlyType::UInt16}, {"uint16", PlyType::UInt16},  {"int", PlyType::Int32},
        {"int32", PlyType::Int32},   {"uint", PlyType::UInt32},    {"uint32", PlyType::UInt32},
        {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64},
        {"float64", PlyType::Float64},
    };
    for (const Entry& e : entries) {
        if (name == e.name) {
            type = e.type;
            return true;
        }
    }
    return false;
}

size_t ply_type_size(PlyType t) {
    switch (t) {
        case PlyType::Int8:
        case PlyType::UInt8: return 1;
        case PlyType::Int16:
        case PlyType::UInt16: return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32: return 4;
        case PlyType::Float64: return 8;
    }
    return 8;
}

bool ply_type_is_integer(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64; }

void ply_type_range(PlyType t, int64_t& lo, int64_t& hi) {
    switch (t) {
        case PlyType::Int8: lo = -128, hi = 127; return;
        case PlyType::UInt8: lo = 0, hi = 255; return;
        case PlyType::Int16: lo = -32768, hi = 32767; return;
        case PlyType::UInt16: lo = 0, hi = 65535; return;
        case PlyType::Int32: lo = std::numeric_limits<int32_t>::min(), hi = std::numeric_limits<int32_t>::max(); return;
        case PlyType::UInt32: lo = 0, hi = std::numeric_limits<uint32_t>::max(); return;
        default: lo = std::numeric_limits<int64_t>::min(), hi = std::numeric_limits<int64_t>::max(); return;
    }
}

struct PlyProperty {
    std::string name;
    bool is_list = false;
    PlyType count_type = PlyType::UInt8;  // lists only
    PlyType type = PlyType::Float32;      // the value, or the list entries
};

struct PlyElement {
    std::string name;
    int64_t count = 0;
    size_t header_at = 0;  // offset of its `element` line
    std::vector<PlyProperty> properties;
};

enum class PlyEncoding { Ascii, BinaryLittle, BinaryBig };

std::vector<std::string_view> split_words(std::string_view line) {
    std::vector<std::string_view> words;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && is_space(line[i])) ++i;
        const size_t begin = i;
        while (i < line.size() && !is_space(line[i])) ++i;
        if (i > begin) words.push_back(line.substr(begin, i - begin));
    }
    return words;
}

// Reads the values of the data section, ASCII or binary, with the position of each for
// error messages.
class PlyValueReader {
public:
    PlyValueReader(InputCursor& in, PlyEncoding encoding) : in_(in), encoding_(encoding) {}

    bool binary() const { return encoding_ != PlyEncoding::Ascii; }

    // A value as a double (finite; ASCII refuses nan/inf tokens, binary NaN/Inf floats too).
    double real(PlyType type, const Label& what) {
        if (!binary()) {
            const std::string_view token = in_.next_token();
            if (ply_type_is_integer(type)) return static_cast<double>(integer_token(token, type, what));
            return in_.to_double(token, what);
        }
        const size_t at = in_.pos();
        const double value = binary_value(type, what);
        if (!std::isfinite(value)) in_.fail_offset(at, what.str() + " is " + (std::isnan(value) ? "NaN" : "infinite"));
        return value;
    }

    // A data value: like real(), but NaN and infinities (common in scanner properties
    // such as confidence) come back as NaN instead of failing; malformed numbers still fail.
    double data_value(PlyType type, const Label& what) {
        if (!binary()) {
            const std::string_view token = in_.next_token();
            if (ply_type_is_integer(type)) return static_cast<double>(integer_token(token, type, what));
            // Only a token starting with a letter can be NaN or an infinity: numbers take
            // the plain path without a copy.
            const std::string_view u = token.substr(token.size() > 0 && (token[0] == '-' || token[0] == '+') ? 1 : 0);
            if (!u.empty() && std::isalpha(static_cast<unsigned char>(u[0]))) {
                std::string t(u);
                for (char& c : t) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
                if (t == "nan" || t == "inf" || t == "infinity") return std::nan("");
            }
            return in_.to_double(token, what);
        }
        const double value = binary_value(type, what);
        return std::isfinite(value) ? value : std::nan("");
    }

    // A value that must be an integer (indices, counts, patch ids).
    int64_t integer(PlyType type, const Label& what) {
        if (!binary()) {
            const std::string_view token = in_.next_token();
            if (ply_type_is_integer(type)) return integer_token(token, type, what);
            const double v = in_.to_double(token, what);
            if (v != std::floor(v) || std::fabs(v) > 9e15) in_.fail_line(in_.offset_of(token), what.str() + " " + quote_token(token) + " is not an integer");
            return static_cast<int64_t>(v);
        }
        const size_t at = in_.pos();
        const double v = binary_value(type, what);
        if (!std::isfinite(v) || v != std::floor(v) || std::fabs(v) > 9e15) {
            in_.fail_offset(at, what.str() + " is not an integer");
        }
        return static_cast<int64_t>(v);
    }

    // Skips `n` values of `type` (unused properties are not interpreted).
    void skip(PlyType type, int64_t n, const Label& what) {
        if (binary()) {
            const size_t bytes = static_cast<size_t>(n) * ply_type_size(type);
            in_.require(bytes, what);
            in_.seek(in_.pos() + bytes);
            return;
        }
        for (int64_t i = 0; i < n; ++i) {
            const std::string_view token = in_.next_token();
            if (token.empty()) in_.fail_token(token, what);
        }
    }

    // Where the next value starts (for ASCII after the white space before it, so that
    // the line number of an error is the line of the value).
    size_t pos() {
        if (!binary()) in_.skip_space();
        return in_.pos();
    }

private:
    int64_t integer_token(std::string_view token, PlyType type, const Label& what) {
        const int64_t v = in_.to_int(token, what);
        int64_t lo, hi;
        ply_type_range(type, lo, hi);
        if (v < lo || v > hi) {
            in_.fail_line(in_.offset_of(token), what.str() + " " + quote_token(token) + " does not fit its declared type");
        }
        return v;
    }

    double binary_value(PlyType type, const Label& what) {
        const bool big = encoding_ == PlyEncoding::BinaryBig;
        switch (type) {
            case PlyType::Int8: return in_.read_binary<int8_t>(big, what);
            case PlyType::UInt8: return in_.read_binary<uint8_t>(big, what);
            case PlyType::Int16: return in_.read_binary<int16_t>(big, what);
            case PlyType::UInt16: return in_.read_binary<uint16_t>(big, what);
            case PlyType::Int32: return in_.read_binary<int32_t>(big, what);
            case PlyType::UInt32: return in_.read_binary<uint32_t>(big, what);
            case PlyType::Float32: return in_.read_binary<float>(big, what);
            case PlyType::Float64: return in_.read_binary<double>(big, what);
        }
        return 0;
    }

    InputCursor& in_;
    PlyEncoding encoding_;
};

}  // namespace

ReaderOutput read_ply(std::string_view bytes, const std::string& name, bool accept_polygons) {
    InputCursor in(bytes, name);
    ReaderOutput out;
    Surface& s = out.surface;
    if (bytes.empty()) in.fail("the file is empty");

    // ---- header ----
    {
        const std::string_view magic = in.rest_of_line();
        if (magic != "ply") in.fail_line(0, "not a PLY file: the first line must be 'ply', found " + quote_token(magic));
    }
    PlyEncoding encoding = PlyEncoding::Ascii;
    bool have_format = false;
    std::vector<PlyElement> elements;
    for (;;) {
        if (in.at_end()) in.fail_line(in.pos(), "the header has no 'end_header' line");
        const size_t line_at = in.pos();
        const std::string_view line = in.rest_of_line();
        const std::vector<std::string_view> w = split_words(line);
        if (w.empty()) continue;
        if (w[0] == "end_header") break;
        if (w[0] == "comment" || w[0] == "obj_info") continue;
        if (w[0] == "format") {
            if (w.size() != 3) in.fail_line(line_at, "expected 'format <encoding> 1.0', found " + quote_token(line));
            if (w[1] == "ascii") encoding = PlyEncoding::Ascii;
            else if (w[1] == "binary_little_endian") encoding = PlyEncoding::BinaryLittle;
            else if (w[1] == "binary_big_endian") encoding = PlyEncoding::BinaryBig;
            else in.fail_line(line_at, "unknown PLY encoding " + quote_token(w[1]));
            if (w[2] != "1.0" && w[2] != "1") in.fail_line(line_at, "unsupported PLY version " + quote_token(w[2]));
            have_format = true;
        } else if (w[0] == "element") {
            if (w.size() != 3) in.fail_line(line_at, "expected 'element <name> <count>', found " + quote_token(line));
            PlyElement e;
            e.name = std::string(w[1]);
            e.count = in.to_int(w[2], "the number of '" + e.name + "' elements");
            if (e.count < 0) in.fail_line(line_at, "negative number of '" + e.name + "' elements");
            e.header_at = line_at;
            elements.push_back(std::move(e));
        } else if (w[0] == "property") {
            if (elements.empty()) in.fail_line(line_at, "a property before any element");
            PlyProperty p;
            if (w.size() == 5 && w[1] == "list") {
                p.is_list = true;
                if (!ply_type_from_name(w[2], p.count_type)) in.fail_line(line_at, "unknown PLY type " + quote_token(w[2]));
                if (!ply_type_is_integer(p.count_type)) in.fail_line(line_at, "a list count must have an integer type");
                if (!ply_type_from_name(w[3], p.type)) in.fail_line(line_at, "unknown PLY type " + quote_token(w[3]));
                p.name = std::string(w[4]);
            } else if (w.size() == 3 && w[1] != "list") {
                if (!ply_type_from_name(w[1], p.type)) in.fail_line(line_at, "unknown PLY type " + quote_token(w[1]));
                p.name = std::string(w[2]);
            } else {
                in.fail_line(line_at, "expected 'property <type> <name>' or 'property list <count type> <type> <name>', found " +
                                          quote_token(line));
            }
            elements.back().properties.push_back(std::move(p));
        } else {
            in.fail_line(line_at, "unknown PLY header line " + quote_token(line));
        }
    }
    if (!have_format) in.fail("the PLY header has no 'format' line");

    // ---- data ----
    PlyValueReader values(in, encoding);
    const bool binary = values.binary();
    bool seen_vertex = false, seen_face = false;
    std::vector<std::array<int64_t, 3>> raw_faces;
    std::vector<size_t> face_offsets;
    std::vector<std::vector<int64_t>> raw_polygons;  // corners of out.polygons, checked at the end
    std::vector<int64_t> polygon_corners;
    for (const PlyElement& e : elements) {
        const bool is_vertex = e.name == "vertex" && !seen_vertex;
        const bool is_face = e.name == "face" && !seen_face;
        if (e.name == "vertex" && seen_vertex) in.fail_line(e.header_at, "a second 'vertex' element");
        if (e.name == "face" && seen_face) in.fail_line(e.header_at, "a second 'face' element");
        seen_vertex |= is_vertex;
        seen_face |= is_face;

        // Smallest size of one element: fixed sizes and list counts (binary), or two
        // characters per value (ASCII).
        double min_bytes = 0;
        for (const PlyProperty& p : e.properties) {
            min_bytes += binary ? static_cast<double>(ply_type_size(p.is_list ? p.count_type : p.type)) : 2.0;
        }
        if (binary) check_count(in, in.pos(), true, e.count, min_bytes, "'" + e.name + "' elements (element line " + std::to_string(in.line_of(e.header_at)) + ")");
        else check_count(in, e.header_at, false, e.count, min_bytes, "'" + e.name + "' elements");
        if (e.properties.empty()) {
            if (is_vertex || is_face) in.fail_line(e.header_at, "the '" + e.name + "' element has no properties");
            continue;  // nothing to read, however many there are
        }

        int coord[3] = {-1, -1, -1};
        int indices = -1, patch = -1;
        for (size_t i = 0; i < e.properties.size(); ++i) {
            const PlyProperty& p = e.properties[i];
            const int at = static_cast<int>(i);
            if (is_vertex && !p.is_list) {
                if (p.name == "x" && coord[0] < 0) coord[0] = at;
                if (p.name == "y" && coord[1] < 0) coord[1] = at;
                if (p.name == "z" && coord[2] < 0) coord[2] = at;
            }
            if (is_face && p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index") && indices < 0) indices = at;
            if (is_face && !p.is_list && patch < 0 &&
                (p.name == "patch" || p.name == "material" || p.name == "region" || p.name == "label" ||
                 p.name == "physical")) {
                patch = at;
            }
        }
        // Vertex data: (array, component) of every other scalar vertex property.
        std::vector<std::pair<int, int>> data_slot(e.properties.size(), {-1, -1});
        if (is_vertex) {
            for (int k = 0; k < 3; ++k) {
                if (coord[k] < 0) in.fail_line(e.header_at, std::string("the vertex element has no scalar property ") + "xyz"[k]);
            }
            s.vertices.resize(static_cast<size_t>(e.count));
            s.vertex_data.clear();
            // Known groups first (their components in this order), then single arrays.
            static const std::vector<std::pair<const char*, std::vector<std::vector<const char*>>>> groups = {
                {"normals", {{"nx", "ny", "nz"}}},
                {"colors", {{"red", "green", "blue", "alpha"}, {"red", "green", "blue"}, {"r", "g", "b"}}},
                {"texture_coordinates", {{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}}},
            };
            auto find_scalar = [&](const char* name) {
                for (size_t i = 0; i < e.properties.size(); ++i)
                    if (!e.properties[i].is_list && e.properties[i].name == name && data_slot[i].first < 0 &&
                        int(i) != coord[0] && int(i) != coord[1] && int(i) != coord[2])
                        return static_cast<int>(i);
                return -1;
            };
            for (const auto& [group, variants] : groups) {
                for (const auto& names : variants) {
                    std::vector<int> at;
                    for (const char* n : names) at.push_back(find_scalar(n));
                    if (std::find(at.begin(), at.end(), -1) != at.end()) continue;
                    const int array = static_cast<int>(s.vertex_data.size());
                    s.vertex_data.push_back({group, static_cast<int>(at.size()), {}});
                    for (size_t c = 0; c < at.size(); ++c) data_slot[static_cast<size_t>(at[c])] = {array, static_cast<int>(c)};
                    break;
                }
            }
            for (size_t i = 0; i < e.properties.size(); ++i) {
                const PlyProperty& p = e.properties[i];
                const int at = static_cast<int>(i);
                if (p.is_list || data_slot[i].first >= 0 || at == coord[0] || at == coord[1] || at == coord[2]) continue;
                std::string name = p.name;
                std::replace(name.begin(), name.end(), '/', '_');
                if (name.empty() || name == ".") name = "property_" + std::to_string(i);
                for (int suffix = 2;; ++suffix) {
                    bool taken = false;
                    for (const VertexArray& a : s.vertex_data) taken = taken || a.name == name;
                    if (!taken) break;
                    name = p.name + "_" + std::to_string(suffix);
                }
                data_slot[i] = {static_cast<int>(s.vertex_data.size()), 0};
                s.vertex_data.push_back({name, 1, {}});
            }
            for (VertexArray& a : s.vertex_data) a.values.assign(static_cast<size_t>(e.count) * static_cast<size_t>(a.components), 0.0);
        }
        if (is_face) {
            if (indices < 0) in.fail_line(e.header_at, "the face element has no list property 'vertex_indices'");
            raw_faces.reserve(static_cast<size_t>(e.count));
            face_offsets.reserve(static_cast<size_t>(e.count));
            s.patches.reserve(static_cast<size_t>(e.count));
        }

        const std::string element_prefix = e.name + " ";
        const char* ename = element_prefix.c_str();
        for (int64_t i = 0; i < e.count; ++i) {
            const size_t element_at = values.pos();
            // "<element> <i>" for messages, built only when one is needed
            auto label = [&]() { return e.name + " " + std::to_string(i); };
            std::array<int64_t, 3> face{};
            int32_t patch_id = 0;
            for (size_t pi = 0; pi < e.properties.size(); ++pi) {
                const PlyProperty& p = e.properties[pi];
                const int at = static_cast<int>(pi);
                if (p.is_list) {
                    const size_t count_at = values.pos();
                    const int64_t n = values.integer(p.count_type, Label(ename, i, ": the count of list ", p.name.c_str()));
                    if (n < 0) {
                        if (binary) in.fail_offset(count_at, label() + ": negative list count " + std::to_string(n));
                        in.fail_line(count_at, label() + ": negative list count " + std::to_string(n));
                    }
                    if (binary && static_cast<double>(n) * ply_type_size(p.type) > static_cast<double>(in.remaining())) {
                        in.fail_offset(count_at, label() + ": list '" + p.name + "' of " + std::to_string(n) +
                                                     " entries runs past the end of the file");
                    }
                    if (at == indices) {
                        if (n != 3 && !(n > 3 && accept_polygons)) {
                            const std::string message =
                                label() + " has " + std::to_string(n) + " corners; only triangles are accepted" +
                                (n > 3 ? " (the triangulate-polygons repair splits polygons into triangles)" : "");
                            if (binary) in.fail_offset(count_at, message);
                            in.fail_line(count_at, message);
                        }
                        if (n == 3) {
                            for (int k = 0; k < 3; ++k) face[k] = values.integer(p.type, Label(ename, i, ": a vertex index"));
                        } else {
                            // An ASCII index takes at least two bytes ("0 "), a binary one its size.
                            const double least = binary ? static_cast<double>(ply_type_size(p.type)) : 2.0;
                            if (static_cast<double>(n) * least > static_cast<double>(in.remaining()) + 1) {
                                const std::string message = label() + ": " + std::to_string(n) +
                                                            " corners announced, more than the rest of the file holds";
                                if (binary) in.fail_offset(count_at, message);
                                in.fail_line(count_at, message);
                            }
                            polygon_corners.clear();
                            for (int64_t k = 0; k < n; ++k)
                                polygon_corners.push_back(values.integer(p.type, Label(ename, i, ": a vertex index")));
                        }
                    } else {
                        values.skip(p.type, n, Label(ename, i, ": list ", p.name.c_str()));
                    }
                } else if (is_vertex && (at == coord[0] || at == coord[1] || at == coord[2])) {
                    const int k = at == coord[0] ? 0 : (at == coord[1] ? 1 : 2);
                    s.vertices[static_cast<size_t>(i)][k] = values.real(p.type, Label(ename, i, ": coordinate ", p.name.c_str()));
                } else if (is_vertex && data_slot[pi].first >= 0) {
                    VertexArray& a = s.vertex_data[static_cast<size_t>(data_slot[pi].first)];
                    a.values[static_cast<size_t>(i) * static_cast<size_t>(a.components) + static_cast<size_t>(data_slot[pi].second)] =
                        values.data_value(p.type, Label(ename, i, ": property ", p.name.c_str()));
                } else if (at == patch) {
                    const size_t value_at = values.pos();
                    const int64_t v = values.integer(p.type, Label(ename, i, ": patch id ", p.name.c_str()));
                    if (v < std::numeric_limits<int32_t>::min() || v > std::numeric_limits<int32_t>::max()) {
                        const std::string message = label() + ": patch id " + std::to_string(v) + " does not fit in 32 bits";
                        if (binary) in.fail_offset(value_at, message);
                        in.fail_line(value_at, message);
                    }
                    patch_id = static_cast<int32_t>(v);
                } else {
                    values.skip(p.type, 1, Label(ename, i, ": property ", p.name.c_str()));
                }
            }
            if (is_face && polygon_corners.empty()) {
                raw_faces.push_back(face);
                face_offsets.push_back(element_at);
                s.patches.push_back(patch_id);
            } else if (is_face) {
                PolygonFace polygon;
                polygon.position = raw_faces.size();
                polygon.face = i;
                polygon.offset = element_at;
                polygon.patch = patch_id;
                out.polygons.push_back(std::move(polygon));
                raw_polygons.push_back(polygon_corners);
                polygon_corners.clear();
            }
        }
    }
    if (binary) {
        if (!in.at_end()) {
            in.fail_offset(in.pos(), std::to_string(in.remaining()) +
                                         " bytes after the last element (wrong element counts in the header?)");
        }
    } else {
        const std::string_view extra = in.next_token();
        if (!extra.empty()) {
            in.fail_line(in.offset_of(extra),
                         "unexpected " + quote_token(extra) + " after the last element (wrong element counts in the header?)");
        }
    }
    if (!seen_vertex) in.fail("the PLY header declares no 'vertex' element");
    // Data arrays with values that are not numbers cannot be interpolated: left out, said.
    for (size_t i = 0; i < s.vertex_data.size();) {
        const VertexArray& a = s.vertex_data[i];
        const auto bad = std::find_if(a.values.begin(), a.values.end(), [](double x) { return !std::isfinite(x); });
        if (bad == a.values.end()) {
            ++i;
            continue;
        }
        out.notes.push_back("vertex data '" + a.name + "' left out: vertex " +
                            std::to_string((bad - a.values.begin()) / a.components) + " has a value that is not a finite number");
        s.vertex_data.erase(s.vertex_data.begin() + static_cast<std::ptrdiff_t>(i));
    }

    const int64_t nv = static_cast<int64_t>(s.vertices.size());
    s.triangles.reserve(raw_faces.size());
    for (size_t f = 0; f < raw_faces.size(); ++f) {
        Tri t;
        for (int k = 0; k < 3; ++k) {
            const int64_t index = raw_faces[f][k];
            if (index < 0 || index >= nv) {
                const std::string message = "face " + std::to_string(f) + ": vertex index " + std::to_string(index) +
                                            " is out of range (the file has " + std::to_string(nv) + " vertices)";
                if (binary) in.fail_offset(face_offsets[f], message);
                in.fail_line(face_offsets[f], message);
            }
            t[k] = static_cast<int32_t>(index);
        }
        s.triangles.push_back(t);
    }
    for (size_t i = 0; i < out.polygons.size(); ++i) {
        PolygonFace& polygon = out.polygons[i];
        for (const int64_t index : raw_polygons[i]) {
            if (index < 0 || index >= nv) {
                const std::string message = "face " + std::to_string(polygon.face) + ": vertex index " +
                                            std::to_string(index) + " is out of range (the file has " +
                                            std::to_string(nv) + " vertices)";
                if (binary) in.fail_offset(polygon.offset, message);
                in.fail_line(polygon.offset, message);
            }
            polygon.corners.push_back(static_cast<int32_t>(index));
        }
    }
    insert_polygons(in, binary, out);
    return out;
}

}  // namespace bpm::detail
