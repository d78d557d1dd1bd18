// VTK XML reader: PolyData (.vtp) and UnstructuredGrid (.vtu), as written by VTK's
// vtkXMLPolyDataWriter / vtkXMLUnstructuredGridWriter, ParaView and 3D Slicer.
//
// Understood:
//   <VTKFile type="PolyData"|"UnstructuredGrid" byte_order=... header_type="UInt32"|"UInt64"
//            compressor="vtkZLibDataCompressor"?>, one or more <Piece> (concatenated);
//   DataArray format="ascii", "binary" (inline base64) and "appended" (<AppendedData>
//   encoding "raw" or "base64"), uncompressed or zlib-compressed, types Int8 .. UInt64,
//   Float32, Float64, either byte order.
//   PolyData: <Polys> (triangles; polygons with accept_polygons), <Strips> (split into
//   triangles); <Verts>, <Lines> skipped with a note.
//   UnstructuredGrid: <Cells> of type 5 (triangle), 6 (strip), 7 (polygon), 8 (pixel),
//   9 (quad); points and lines skipped with a note; volume and higher-order cells skipped
//   with a note, or refused when there is no surface cell at all.
//   <PointData>: every numeric DataArray becomes Surface::vertex_data.
//   <CellData>: the first integer-valued array named patch / material / region / label /
//   physical / gmsh:physical / CellEntityIds / RegionId (any case), failing that the one
//   named "Scalars_" (VTK's name for unnamed scalars: vtkDiscreteMarchingCubes' labels),
//   gives the patch ids.
//
// The XML is read by a small scanner of its own (VTK XML has no DTD, no CDATA, no
// namespaces); the appended section is binary and is never scanned as XML: it starts
// after the '_' that follows <AppendedData ...>. Every count and offset is checked
// against the data present before anything is allocated for it, and zlib blocks may
// not claim more than the deflate limit (1032:1) of their compressed size.
//
// Errors: "line N: ..." of the element (or the token / base64 character) at fault.
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <string>

#include "core/number_text.h"
#include "io/surface_readers.h"
#include "io/vtk_types.h"

namespace bpm::detail {

namespace {

// The name vtkXMLWriter writes for an unnamed scalars array.
const std::string kUnnamedScalars = "Scalars_";

// ---- XML scanner -------------------------------------------------------------------

struct XmlElement {
    std::string name;
    std::vector<std::pair<std::string, std::string>> attributes;
    size_t at = 0;                 // offset of its '<'
    size_t content_begin = 0;      // after the start tag
    size_t content_end = 0;        // at the '<' of the end tag (content_begin for <x/>)
    std::vector<size_t> children;  // indices into XmlDocument::elements
    std::vector<std::pair<size_t, size_t>> children_spans;  // [begin, end) of each child in the file

    const std::string* attribute(std::string_view key) const {
        for (const auto& [k, v] : attributes)
            if (k == key) return &v;
        return nullptr;
    }
};

struct XmlDocument {
    std::vector<XmlElement> elements;  // [0] is the root
    bool has_appended = false;
    size_t appended_element = 0;  // index of <AppendedData>
    size_t appended_begin = 0;    // first byte after the '_'
};

bool is_name_char(char c) {
    return !is_space(c) && c != '/' && c != '>' && c != '=' && c != '<' && c != '"' && c != '\'';
}

std::string decode_entities(std::string_view raw) {
    std::string out;
    out.reserve(raw.size());
    for (size_t i = 0; i < raw.size(); ++i) {
        if (raw[i] != '&') {
            out += raw[i];
            continue;
        }
        struct Entity {
            const char* text;
            char c;
        };
        static const Entity entities[] = {{"&lt;", '<'}, {"&gt;", '>'}, {"&amp;", '&'}, {"&quot;", '"'}, {"&apos;", '\''}};
        bool done = false;
        for (const Entity& e : entities) {
            const size_t n = std::strlen(e.text);
            if (raw.substr(i, n) == e.text) {
                out += e.c;
                i += n - 1;
                done = true;
                break;
            }
        }
        if (!done) out += '&';  // numeric and unknown entities are kept as written
    }
    return out;
}

// Scans the markup into elements. Stops at <AppendedData>: what follows its '_' is
// binary. Nesting is limited so that a hostile file cannot exhaust anything.
XmlDocument scan_xml(const InputCursor& in) {
    const std::string_view b = in.bytes();
    XmlDocument doc;
    std::vector<size_t> open;
    size_t pos = 0;
    if (b.substr(0, 3) == "\xEF\xBB\xBF") pos = 3;
    bool root_closed = false;
    for (;;) {
        const size_t lt = b.find('<', pos);
        const size_t text_end = lt == std::string_view::npos ? b.size() : lt;
        if (open.empty()) {
            for (size_t i = pos; i < text_end; ++i) {
                if (!is_space(b[i])) {
                    in.fail_line(i, doc.elements.empty() ? "not an XML file: expected '<', found " + quote_token(b.substr(i, 16))
                                                         : "text after the end of the root element");
                }
            }
        }
        if (lt == std::string_view::npos) break;
        pos = lt;
        if (b.substr(pos, 4) == "<!--") {
            const size_t end = b.find("-->", pos + 4);
            if (end == std::string_view::npos) in.fail_line(pos, "the comment is never closed");
            // Not part of the element's text (DataArray values around it).
            if (!open.empty()) doc.elements[open.back()].children_spans.emplace_back(pos, end + 3);
            pos = end + 3;
            continue;
        }
        if (b.substr(pos, 2) == "<?") {
            const size_t end = b.find("?>", pos + 2);
            if (end == std::string_view::npos) in.fail_line(pos, "the processing instruction is never closed");
            if (!open.empty()) doc.elements[open.back()].children_spans.emplace_back(pos, end + 2);
            pos = end + 2;
            continue;
        }
        if (b.substr(pos, 2) == "<!") in.fail_line(pos, "DOCTYPE and CDATA sections are not supported in VTK XML files");
        if (b.substr(pos, 2) == "</") {
            size_t i = pos + 2;
            const size_t name_begin = i;
            while (i < b.size() && is_name_char(b[i])) ++i;
            const std::string_view name = b.substr(name_begin, i - name_begin);
            while (i < b.size() && is_space(b[i])) ++i;
            if (i >= b.size()) in.fail_line(pos, "the file ends inside a tag (truncated?)");
            if (b[i] != '>') in.fail_line(pos, "expected '>' after </" + std::string(name));
            if (open.empty()) in.fail_line(pos, "</" + std::string(name) + "> closes no element");
            XmlElement& e = doc.elements[open.back()];
            if (name != e.name) {
                in.fail_line(pos, "</" + std::string(name) + "> does not close <" + e.name + "> (opened at line " +
                                      std::to_string(in.line_of(e.at)) + ")");
            }
            e.content_end = pos;
            open.pop_back();
            if (!open.empty()) doc.elements[open.back()].children_spans.back().second = i + 1;
            if (open.empty()) root_closed = true;
            pos = i + 1;
            continue;
        }
        // A start tag.
        if (root_closed) in.fail_line(pos, "a second root element");
        XmlElement e;
        e.at = pos;
        size_t i = pos + 1;
        const size_t name_begin = i;
        while (i < b.size() && is_name_char(b[i])) ++i;
        e.name = std::string(b.substr(name_begin, i - name_begin));
        if (e.name.empty()) {
            in.fail_line(pos, i >= b.size() ? "the file ends inside a tag (truncated?)" : "expected an element name after '<'");
        }
        bool empty_tag = false;
        for (;;) {
            while (i < b.size() && is_space(b[i])) ++i;
            if (i >= b.size()) in.fail_line(pos, "the start tag <" + e.name + "> is never closed (truncated?)");
            if (b[i] == '>') {
                ++i;
                break;
            }
            if (b[i] == '/') {
                if (i + 1 >= b.size() || b[i + 1] != '>') in.fail_line(i, "expected '/>' in <" + e.name + ">");
                i += 2;
                empty_tag = true;
                break;
            }
            const size_t key_begin = i;
            while (i < b.size() && is_name_char(b[i])) ++i;
            if (i == key_begin) in.fail_line(i, "unexpected " + quote_token(b.substr(i, 1)) + " in <" + e.name + ">");
            const std::string key(b.substr(key_begin, i - key_begin));
            while (i < b.size() && is_space(b[i])) ++i;
            if (i >= b.size() || b[i] != '=') in.fail_line(i, "expected '=' after the attribute " + key + " of <" + e.name + ">");
            ++i;
            while (i < b.size() && is_space(b[i])) ++i;
            if (i >= b.size() || (b[i] != '"' && b[i] != '\'')) {
                in.fail_line(i, "the value of the attribute " + key + " of <" + e.name + "> must be in quotes");
            }
            const char quote = b[i];
            const size_t value_end = b.find(quote, i + 1);
            if (value_end == std::string_view::npos) in.fail_line(i, "the value of the attribute " + key + " is never closed");
            if (e.attribute(key) == nullptr) e.attributes.emplace_back(key, decode_entities(b.substr(i + 1, value_end - i - 1)));
            i = value_end + 1;
        }
        e.content_begin = e.content_end = i;
        const size_t index = doc.elements.size();
        if (!open.empty()) {
            doc.elements[open.back()].children.push_back(index);
            doc.elements[open.back()].children_spans.emplace_back(pos, i);
        }
        const bool appended = e.name == "AppendedData";
        doc.elements.push_back(std::move(e));
        if (appended) {
            // Binary from here on: never scanned as XML.
            if (empty_tag) in.fail_line(pos, "<AppendedData/> is empty: it must hold '_' and the data");
            size_t j = i;
            while (j < b.size() && is_space(b[j])) ++j;
            if (j >= b.size() || b[j] != '_') in.fail_line(j, "the data of <AppendedData> must start with '_'");
            doc.has_appended = true;
            doc.appended_element = index;
            doc.appended_begin = j + 1;
            return doc;
        }
        if (!empty_tag) {
            if (open.size() >= 64) in.fail_line(pos, "elements nested more than 64 deep");
            open.push_back(index);
        }
        pos = i;
    }
    if (doc.elements.empty()) in.fail(b.empty() ? "the file is empty" : "not an XML file: no element");
    if (!open.empty()) {
        const XmlElement& e = doc.elements[open.back()];
        in.fail_line(e.at, "<" + e.name + "> is never closed (the file ends first: truncated?)");
    }
    return doc;
}

// ---- values ----------------------------------------------------------------------


bool vtk_type_from_name(std::string_view name, VtkType& type) {
    struct Entry {
        const char* name;
        VtkType type;
    };
    // The names of VTK's XML files and the older C-style ones (vtkIdType is written as
    // Int32 or Int64, but "IdType" and "vtkIdType" have been seen from other writers).
    static const Entry entries[] = {
        {"Int8", VtkType::Int8},       {"Char", VtkType::Int8},         {"SignedChar", VtkType::Int8},
        {"UInt8", VtkType::UInt8},     {"UnsignedChar", VtkType::UInt8}, {"Int16", VtkType::Int16},
        {"Short", VtkType::Int16},     {"UInt16", VtkType::UInt16},     {"UnsignedShort", VtkType::UInt16},
        {"Int32", VtkType::Int32},     {"Int", VtkType::Int32},         {"UInt32", VtkType::UInt32},
        {"UnsignedInt", VtkType::UInt32}, {"Int64", VtkType::Int64},    {"Long", VtkType::Int64},
        {"LongLong", VtkType::Int64},  {"IdType", VtkType::Int64},      {"vtkIdType", VtkType::Int64},
        {"UInt64", VtkType::UInt64},   {"UnsignedLong", VtkType::UInt64}, {"UnsignedLongLong", VtkType::UInt64},
        {"Float32", VtkType::Float32}, {"Float", VtkType::Float32},     {"Float64", VtkType::Float64},
        {"Double", VtkType::Float64},
    };
    for (const Entry& e : entries) {
        if (name == e.name) {
            type = e.type;
            return true;
        }
    }
    return false;
}


template <class T>
double load(const char* p, bool swap) {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, p, sizeof(T));
    if (swap) std::reverse(raw, raw + sizeof(T));
    T value;
    std::memcpy(&value, raw, sizeof(T));
    return static_cast<double>(value);
}

double load_value(VtkType t, const char* p, bool swap) {
    switch (t) {
        case VtkType::Int8: return load<int8_t>(p, swap);
        case VtkType::UInt8: return load<uint8_t>(p, swap);
        case VtkType::Int16: return load<int16_t>(p, swap);
        case VtkType::UInt16: return load<uint16_t>(p, swap);
        case VtkType::Int32: return load<int32_t>(p, swap);
        case VtkType::UInt32: return load<uint32_t>(p, swap);
        case VtkType::Int64: return load<int64_t>(p, swap);
        case VtkType::UInt64: return load<uint64_t>(p, swap);
        case VtkType::Float32: return load<float>(p, swap);
        case VtkType::Float64: return load<double>(p, swap);
        case VtkType::Bit:
        case VtkType::String: break;  // legacy files only: vtk_type_from_name never gives them here
    }
    return 0;
}

// ---- binary data: raw bytes or base64 text -----------------------------------------

// The bytes of one array's binary data: raw (appended encoding="raw"), or decoded on the
// fly from base64 text spread over `ranges` of the file (inline: the element's text
// around its child elements; appended: from the array's offset on).
class ByteSource {
public:
    using Range = std::pair<size_t, size_t>;
    ByteSource(const InputCursor& in, std::vector<Range> ranges, bool base64)
        : in_(in), ranges_(std::move(ranges)), base64_(base64) {}

    // Appends n bytes to out; false (out holding what there was) if the data ends first.
    bool read(size_t n, std::string& out) {
        if (!base64_) {
            while (n > 0 && range_ < ranges_.size()) {
                const Range& r = ranges_[range_];
                const size_t take = std::min(n, r.second - (r.first + offset_));
                out.append(in_.bytes().data() + r.first + offset_, take);
                offset_ += take;
                n -= take;
                if (r.first + offset_ >= r.second) ++range_, offset_ = 0;
            }
            return n == 0;
        }
        while (n > 0) {
            if (pending_size_ == pending_used_ && !decode_group()) return false;
            while (n > 0 && pending_used_ < pending_size_) {
                out += static_cast<char>(pending_[pending_used_++]);
                --n;
            }
        }
        return true;
    }

    // An upper bound of the bytes still available, for checking sizes before allocating.
    size_t max_remaining() const {
        size_t chars = 0;
        for (size_t r = range_; r < ranges_.size(); ++r) chars += ranges_[r].second - ranges_[r].first - (r == range_ ? offset_ : 0);
        return base64_ ? chars / 4 * 3 + 3 + (pending_size_ - pending_used_) : chars;
    }

private:
    // Next character of the text that is not white space; false at the end of the data
    // (the end of the ranges or a '<').
    bool next_char(char& c, size_t& at) {
        while (range_ < ranges_.size()) {
            const Range& r = ranges_[range_];
            if (r.first + offset_ >= r.second) {
                ++range_, offset_ = 0;
                continue;
            }
            at = r.first + offset_;
            c = in_.bytes()[at];
            if (c == '<') {
                range_ = ranges_.size();
                return false;
            }
            ++offset_;
            if (!is_space(c)) return true;
        }
        return false;
    }

    static int sextet(char c) {
        if (c >= 'A' && c <= 'Z') return c - 'A';
        if (c >= 'a' && c <= 'z') return c - 'a' + 26;
        if (c >= '0' && c <= '9') return c - '0' + 52;
        if (c == '+') return 62;
        if (c == '/') return 63;
        return -1;
    }

    // Decodes the next group of four characters. VTK encodes headers and data as separate
    // base64 runs, so '=' padding may end any group, not just the last one.
    bool decode_group() {
        char c[4];
        size_t at[4] = {0, 0, 0, 0};
        int n = 0;
        while (n < 4 && next_char(c[n], at[n])) ++n;
        if (n == 0) return false;
        if (n < 4) in_.fail_line(at[n - 1], "the base64 data ends in the middle of a group of four characters");
        int v[4];
        for (int k = 0; k < 4; ++k) {
            v[k] = c[k] == '=' ? 0 : sextet(c[k]);
            if (v[k] < 0 || (c[k] == '=' && k < 2) || (k == 3 && c[2] == '=' && c[3] != '=')) {
                in_.fail_line(at[k], "invalid base64 character " + quote_token(std::string_view(&c[k], 1)));
            }
        }
        const uint32_t bits = static_cast<uint32_t>(v[0] << 18 | v[1] << 12 | v[2] << 6 | v[3]);
        pending_[0] = static_cast<unsigned char>(bits >> 16);
        pending_[1] = static_cast<unsigned char>(bits >> 8);
        pending_[2] = static_cast<unsigned char>(bits);
        pending_size_ = c[2] == '=' ? 1 : (c[3] == '=' ? 2 : 3);
        pending_used_ = 0;
        return true;
    }

    const InputCursor& in_;
    std::vector<Range> ranges_;
    bool base64_;
    size_t range_ = 0, offset_ = 0;
    unsigned char pending_[3] = {0, 0, 0};
    int pending_size_ = 0, pending_used_ = 0;
};

// ---- the file --------------------------------------------------------------------

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

struct ArrayValues {
    std::string name;
    VtkType type = VtkType::Float64;
    int components = 1;
    std::vector<double> values;
};

class VtkXmlReader {
public:
    VtkXmlReader(std::string_view bytes, const std::string& name, bool accept_polygons)
        : in_(bytes, name), accept_polygons_(accept_polygons) {}

    ReaderOutput read();

private:
    const XmlElement& el(size_t i) const { return doc_.elements[i]; }

    [[noreturn]] void fail_at(const XmlElement& e, const std::string& message) const { in_.fail_line(e.at, message); }

    std::string describe(const XmlElement& e, const char* parent) const {
        const std::string* n = e.attribute("Name");
        return "DataArray " + (n ? quote_token(*n) + " " : std::string()) + "of <" + parent + ">";
    }

    int64_t int_attribute(const XmlElement& e, const char* key, int64_t fallback, bool required) const {
        const std::string* v = e.attribute(key);
        if (!v) {
            if (required) fail_at(e, "<" + e.name + "> has no attribute " + key);
            return fallback;
        }
        std::string_view t = *v;
        while (!t.empty() && is_space(t.front())) t.remove_prefix(1);
        while (!t.empty() && is_space(t.back())) t.remove_suffix(1);
        int64_t x = 0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
        if (t.empty() || ec != std::errc() || end != t.data() + t.size() || x < 0) {
            fail_at(e, "the attribute " + std::string(key) + " of <" + e.name + "> must be a non-negative integer, not " +
                           quote_token(*v));
        }
        return x;
    }

    // Only the listed child elements may appear; anything else is an unknown element.
    void check_children(const XmlElement& e, std::initializer_list<const char*> allowed) const {
        for (size_t c : e.children) {
            const XmlElement& child = el(c);
            bool ok = false;
            for (const char* a : allowed) ok = ok || child.name == a;
            if (!ok) fail_at(child, "unknown element <" + child.name + "> in <" + e.name + ">");
        }
    }

    // The text of an element around its child elements (VTK puts <InformationKey> inside
    // DataArrays, before or after the data).
    static std::vector<ByteSource::Range> text_ranges(const XmlElement& e) {
        std::vector<ByteSource::Range> ranges;
        size_t from = e.content_begin;
        for (const auto& [b, end] : e.children_spans) {
            if (b > from) ranges.emplace_back(from, b);
            from = std::max(from, end);
        }
        if (e.content_end > from) ranges.emplace_back(from, e.content_end);
        return ranges;
    }

    // Reads a DataArray. `expected`: the number of values it must hold (-1: any).
    // `finite`: NaN/Inf are refused (coordinates, indices); else they become NaN.
    ArrayValues read_array(const XmlElement& e, const char* parent, int64_t expected, bool finite);
    void read_ascii(const XmlElement& e, const std::string& what, ArrayValues& a, bool finite) const;
    std::string read_payload(const XmlElement& e, const std::string& what, ByteSource& source, size_t type_size,
                             int64_t expected_bytes);
    uint64_t read_header_word(const XmlElement& e, const std::string& what, ByteSource& source) const;

    // Checks an index array read as doubles: whole numbers in [0, limit).
    void check_indices(const XmlElement& e, const std::string& what, const std::vector<double>& v, double limit,
                       const char* limit_what) const;

    void read_piece(const XmlElement& piece, bool polydata, size_t piece_number);

    InputCursor in_;
    bool accept_polygons_;
    XmlDocument doc_;
    bool big_endian_ = false;
    bool header64_ = false;
    bool zlib_ = false;
    bool appended_base64_ = false;
    uint64_t consumed_ = 0;  // binary bytes (compressed or not) decoded so far, all arrays
    ReaderOutput out_;

    // Point data of the pieces so far, matched by name (and occurrence) across pieces.
    struct PendingArray {
        std::string name;
        int components = 1;
        std::vector<double> values;
        bool alive = true;
    };
    std::vector<PendingArray> point_data_;
    std::vector<std::string> point_data_notes_;
    std::vector<std::string> ignored_cell_arrays_;
    std::string patch_array_name_;
    size_t pieces_without_patches_ = 0;
    int64_t skipped_vertex_cells_ = 0, skipped_line_cells_ = 0, skipped_other_cells_ = 0;
    int64_t strip_degenerate_ = 0, strip_count_ = 0;
    std::map<int, int64_t> skipped_types_;
};

uint64_t VtkXmlReader::read_header_word(const XmlElement& e, const std::string& what, ByteSource& source) const {
    std::string raw;
    const size_t n = header64_ ? 8 : 4;
    if (!source.read(n, raw)) fail_at(e, what + ": the data ends inside its header (truncated?)");
    unsigned char b[8];
    std::memcpy(b, raw.data(), n);
    if (big_endian_ != InputCursor::host_is_big_endian()) std::reverse(b, b + n);
    if (header64_) {
        uint64_t v;
        std::memcpy(&v, b, 8);
        return v;
    }
    uint32_t v;
    std::memcpy(&v, b, 4);
    return v;
}

std::string VtkXmlReader::read_payload(const XmlElement& e, const std::string& what, ByteSource& source,
                                       size_t type_size, int64_t expected_bytes) {
    std::string data;
    // Arrays may not share binary data: with offsets pointing at the same bytes, a small
    // file could otherwise make every array decode (and allocate) all of it again.
    auto consume = [&](uint64_t n) {
        if (n > in_.size() || consumed_ + n > in_.size()) {
            fail_at(e, what + ": the binary data of the arrays add up to more bytes than the file holds "
                              "(arrays overlapping in the appended data?)");
        }
        consumed_ += n;
    };
    if (!zlib_) {
        const uint64_t n = read_header_word(e, what, source);
        if (n > source.max_remaining()) {
            fail_at(e, what + ": the header announces " + std::to_string(n) + " bytes, but at most " +
                           std::to_string(source.max_remaining()) + " follow (truncated?)");
        }
        consume(n);
        if (expected_bytes >= 0 && n != static_cast<uint64_t>(expected_bytes)) {
            fail_at(e, what + ": the header announces " + std::to_string(n) + " bytes, " +
                           std::to_string(expected_bytes) + " expected");
        }
        if (!source.read(static_cast<size_t>(n), data)) {
            fail_at(e, what + ": the data ends after " + std::to_string(data.size()) + " of the " + std::to_string(n) +
                           " announced bytes (truncated?)");
        }
    } else {
        // Header: number of blocks, uncompressed block size, uncompressed size of the last
        // block (0: a full block), then the compressed size of every block.
        const uint64_t blocks = read_header_word(e, what, source);
        const uint64_t block_size = read_header_word(e, what, source);
        const uint64_t last_size = read_header_word(e, what, source);
        const size_t word = header64_ ? 8 : 4;
        if (blocks > source.max_remaining() / word) {
            fail_at(e, what + ": " + std::to_string(blocks) + " compressed blocks announced, more than the data can hold");
        }
        std::vector<uint64_t> compressed(static_cast<size_t>(blocks));
        uint64_t compressed_total = 0;
        for (uint64_t& c : compressed) {
            c = read_header_word(e, what, source);
            if (c > source.max_remaining()) {
                fail_at(e, what + ": a compressed block of " + std::to_string(c) + " bytes announced, but at most " +
                               std::to_string(source.max_remaining()) + " follow (truncated?)");
            }
            compressed_total += c;
        }
        if (compressed_total > source.max_remaining()) {
            fail_at(e, what + ": " + std::to_string(compressed_total) + " compressed bytes announced, but at most " +
                           std::to_string(source.max_remaining()) + " follow (truncated?)");
        }
        consume(compressed_total);
        if (blocks > 0 && last_size > block_size) {
            fail_at(e, what + ": the last block (" + std::to_string(last_size) + " bytes) is larger than the block size (" +
                           std::to_string(block_size) + ")");
        }
        std::vector<uint64_t> sizes(compressed.size());
        uint64_t total = 0;
        for (size_t i = 0; i < sizes.size(); ++i) {
            sizes[i] = (i + 1 == sizes.size() && last_size != 0) ? last_size : block_size;
            // zlib cannot expand data more than 1032 times: a larger claim is corrupt, and
            // must not be allowed to allocate.
            if (sizes[i] > compressed[i] * 1032 + 64) {
                fail_at(e, what + ": block " + std::to_string(i) + " claims " + std::to_string(sizes[i]) +
                               " decompressed bytes from " + std::to_string(compressed[i]) +
                               " compressed ones, an absurd decompressed size (zlib expands at most 1032 times)");
            }
            total += sizes[i];
        }
        if (expected_bytes >= 0 && total != static_cast<uint64_t>(expected_bytes)) {
            fail_at(e, what + ": the compressed blocks hold " + std::to_string(total) + " bytes, " +
                           std::to_string(expected_bytes) + " expected");
        }
        data.resize(static_cast<size_t>(total));
        size_t at = 0;
        std::string block;
        for (size_t i = 0; i < sizes.size(); ++i) {
            block.clear();
            if (!source.read(static_cast<size_t>(compressed[i]), block)) {
                fail_at(e, what + ": the data ends inside compressed block " + std::to_string(i) + " (truncated?)");
            }
            if (sizes[i] == 0 && compressed[i] == 0) continue;
            unsigned char dummy = 0;
            uLongf produced = static_cast<uLongf>(sizes[i]);
            const int rc = uncompress(sizes[i] > 0 ? reinterpret_cast<Bytef*>(&data[at]) : &dummy, &produced,
                                      reinterpret_cast<const Bytef*>(block.data()), static_cast<uLong>(block.size()));
            if (rc != Z_OK || produced != sizes[i]) {
                const std::string why = rc == Z_BUF_ERROR ? "it holds more or less than the header says"
                                        : rc == Z_DATA_ERROR ? "not valid zlib data"
                                        : rc == Z_OK ? "it holds " + std::to_string(produced) + " bytes, the header says " + std::to_string(sizes[i])
                                                     : "zlib error " + std::to_string(rc);
                fail_at(e, what + ": compressed block " + std::to_string(i) + " cannot be decompressed (" + why + ")");
            }
            at += static_cast<size_t>(sizes[i]);
        }
    }
    if (data.size() % type_size != 0) {
        fail_at(e, what + ": " + std::to_string(data.size()) + " bytes are not a whole number of " +
                       std::to_string(type_size) + "-byte values");
    }
    return data;
}

void VtkXmlReader::read_ascii(const XmlElement& e, const std::string& what, ArrayValues& a, bool finite) const {
    const std::string_view b = in_.bytes();
    const bool integer = vtk_type_is_integer(a.type);
    for (const auto& [begin, end] : text_ranges(e)) {
        size_t i = begin;
        while (i < end) {
            while (i < end && is_space(b[i])) ++i;
            const size_t t0 = i;
            while (i < end && !is_space(b[i])) ++i;
            if (i == t0) break;
            std::string_view t = b.substr(t0, i - t0);
            const std::string_view token = t;
            if (t.size() > 1 && t[0] == '+' && t[1] != '-' && t[1] != '+') t.remove_prefix(1);
            double value = 0;
            if (integer) {
                int64_t x = 0;
                auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
                if (ec == std::errc() && p == t.data() + t.size()) {
                    value = static_cast<double>(x);
                } else {
                    uint64_t u = 0;
                    auto [q, ec2] = std::from_chars(t.data(), t.data() + t.size(), u);
                    if (ec2 != std::errc() || q != t.data() + t.size()) {
                        in_.fail_line(t0, what + ": expected an integer, found " + quote_token(token));
                    }
                    value = static_cast<double>(u);
                }
                double lo = 0, hi = 0;
                switch (a.type) {
                    case VtkType::Int8: lo = -128, hi = 127; break;
                    case VtkType::UInt8: lo = 0, hi = 255; break;
                    case VtkType::Int16: lo = -32768, hi = 32767; break;
                    case VtkType::UInt16: lo = 0, hi = 65535; break;
                    case VtkType::Int32: lo = -2147483648.0, hi = 2147483647.0; break;
                    case VtkType::UInt32: lo = 0, hi = 4294967295.0; break;
                    case VtkType::Int64: lo = -9223372036854775808.0, hi = 9223372036854775807.0; break;
                    default: lo = 0, hi = 18446744073709551615.0; break;
                }
                if (value < lo || value > hi) in_.fail_line(t0, what + ": " + quote_token(token) + " does not fit its type");
            } else {
                auto [p, ec] = detail::parse_double(t.data(), t.data() + t.size(), value);  // out of range: +-inf, +-0
                if (p != t.data() + t.size() || ec != std::errc()) {
                    in_.fail_line(t0, what + ": expected a number, found " + quote_token(token));
                }
                if (!std::isfinite(value)) {
                    if (finite) in_.fail_line(t0, what + ": " + quote_token(token) + " is not a finite number");
                    value = std::nan("");
                }
            }
            a.values.push_back(value);
        }
    }
}

ArrayValues VtkXmlReader::read_array(const XmlElement& e, const char* parent, int64_t expected, bool finite) {
    const std::string what = describe(e, parent);
    check_children(e, {"InformationKey"});
    ArrayValues a;
    if (const std::string* n = e.attribute("Name")) a.name = *n;
    const std::string* type = e.attribute("type");
    if (!type) fail_at(e, what + " has no attribute type");
    if (!vtk_type_from_name(*type, a.type)) fail_at(e, what + ": unsupported type " + quote_token(*type));
    const int64_t components = int_attribute(e, "NumberOfComponents", 1, false);
    if (components < 1 || components > 1000000) fail_at(e, what + ": NumberOfComponents must be 1 to 1000000");
    a.components = static_cast<int>(components);
    const std::string* format = e.attribute("format");
    const std::string f = format ? *format : "ascii";
    const size_t type_size = vtk_type_size(a.type);
    const int64_t expected_bytes = expected >= 0 ? expected * static_cast<int64_t>(type_size) : -1;
    std::string data;
    if (f == "ascii") {
        read_ascii(e, what, a, finite);
    } else if (f == "binary") {
        ByteSource source(in_, text_ranges(e), true);
        data = read_payload(e, what, source, type_size, expected_bytes);
    } else if (f == "appended") {
        if (!doc_.has_appended) fail_at(e, what + " has format 'appended', but the file has no <AppendedData>");
        const int64_t offset = int_attribute(e, "offset", 0, true);
        const size_t begin = doc_.appended_begin;
        if (static_cast<uint64_t>(offset) > in_.size() - begin) {
            fail_at(e, what + ": offset " + std::to_string(offset) + " is beyond the end of the appended data (" +
                           std::to_string(in_.size() - begin) + " bytes)");
        }
        ByteSource source(in_, {{begin + static_cast<size_t>(offset), in_.size()}}, appended_base64_);
        data = read_payload(e, what, source, type_size, expected_bytes);
    } else {
        fail_at(e, what + ": unknown format " + quote_token(f) + " (expected ascii, binary or appended)");
    }
    if (f != "ascii") {
        const bool swap = big_endian_ != InputCursor::host_is_big_endian();
        const size_t n = data.size() / type_size;
        a.values.resize(n);
        for (size_t i = 0; i < n; ++i) {
            double v = load_value(a.type, data.data() + i * type_size, swap);
            if (!std::isfinite(v)) {
                if (finite) fail_at(e, what + ": value " + std::to_string(i) + " is " + (std::isnan(v) ? "NaN" : "infinite"));
                v = std::nan("");
            }
            a.values[i] = v;
        }
    }
    if (expected >= 0 && static_cast<int64_t>(a.values.size()) != expected) {
        fail_at(e, what + " holds " + std::to_string(a.values.size()) + " values, " + std::to_string(expected) +
                       " expected");
    }
    if (a.values.size() % static_cast<size_t>(a.components) != 0) {
        fail_at(e, what + " holds " + std::to_string(a.values.size()) + " values, not a multiple of its " +
                       std::to_string(a.components) + " components");
    }
    return a;
}

void VtkXmlReader::check_indices(const XmlElement& e, const std::string& what, const std::vector<double>& v,
                                 double limit, const char* limit_what) const {
    for (size_t i = 0; i < v.size(); ++i) {
        if (!(v[i] >= 0 && v[i] < limit && v[i] == std::floor(v[i]))) {
            fail_at(e, what + ": entry " + std::to_string(i) + " (" + detail::round_trip_text(v[i]) +
                           ") is out of range (the piece has " + std::to_string(static_cast<int64_t>(limit)) + " " +
                           limit_what + ")");
        }
    }
}

// One cell list: `offsets` (end of each cell in `connectivity`), checked.
struct CellList {
    std::vector<double> connectivity;
    std::vector<int64_t> offsets;  // with a leading 0: cell c is [offsets[c], offsets[c + 1])
    const XmlElement* at = nullptr;
};

void VtkXmlReader::read_piece(const XmlElement& piece, bool polydata, size_t piece_number) {
    Surface& s = out_.surface;
    const int64_t np = int_attribute(piece, "NumberOfPoints", 0, true);
    if (np > std::numeric_limits<int32_t>::max() - static_cast<int64_t>(s.vertices.size())) {
        fail_at(piece, std::to_string(np) + " points announced; bpm supports at most " +
                           std::to_string(std::numeric_limits<int32_t>::max()));
    }
    if (polydata) check_children(piece, {"PointData", "CellData", "Points", "Verts", "Lines", "Strips", "Polys"});
    else check_children(piece, {"PointData", "CellData", "Points", "Cells"});
    std::map<std::string, const XmlElement*> parts;
    for (size_t c : piece.children) {
        const XmlElement& child = el(c);
        if (parts.count(child.name)) fail_at(child, "a second <" + child.name + "> in the <Piece>");
        parts[child.name] = &child;
    }
    auto part = [&](const char* n) -> const XmlElement* {
        const auto it = parts.find(n);
        return it == parts.end() ? nullptr : it->second;
    };

    // Points.
    const int32_t base = s.num_vertices();
    if (const XmlElement* points = part("Points")) {
        check_children(*points, {"DataArray"});
        if (points->children.empty()) {
            if (np > 0) fail_at(*points, "<Points> has no DataArray");
        } else {
            const XmlElement& d = el(points->children[0]);
            const ArrayValues a = read_array(d, "Points", np * 3, true);
            if (a.components != 3) fail_at(d, describe(d, "Points") + " must have NumberOfComponents=\"3\"");
            for (int64_t v = 0; v < np; ++v) {
                const size_t i = static_cast<size_t>(v) * 3;
                s.vertices.push_back({a.values[i], a.values[i + 1], a.values[i + 2]});
            }
        }
    } else if (np > 0) {
        fail_at(piece, "the <Piece> has " + std::to_string(np) + " points but no <Points>");
    }

    // Cells: (corner list, index in the cell data numbering, VTK cell type).
    auto read_cells = [&](const XmlElement& cells, const char* parent, int64_t count, bool with_types,
                          std::vector<double>* types) {
        check_children(cells, {"DataArray"});
        const XmlElement *conn = nullptr, *offs = nullptr, *typ = nullptr;
        for (size_t c : cells.children) {
            const XmlElement& d = el(c);
            const std::string* n = d.attribute("Name");
            if (!n) continue;
            if (*n == "connectivity" && !conn) conn = &d;
            if (*n == "offsets" && !offs) offs = &d;
            if (*n == "types" && !typ) typ = &d;
        }
        CellList list;
        list.at = &cells;
        list.offsets.push_back(0);
        if (count == 0 && !conn && !offs) return list;
        if (!conn || !offs) fail_at(cells, std::string("<") + parent + "> needs DataArrays named connectivity and offsets");
        if (with_types && !typ) fail_at(cells, std::string("<") + parent + "> needs a DataArray named types");
        const std::string offsets_what = describe(*offs, parent);
        const ArrayValues o = read_array(*offs, parent, count, true);
        double previous = 0;
        for (size_t i = 0; i < o.values.size(); ++i) {
            const double v = o.values[i];
            if (v != std::floor(v) || v < previous) {
                fail_at(*offs, offsets_what + ": entry " + std::to_string(i) + " is not an integer at least as large as the one before (offsets must not decrease)");
            }
            if (v > static_cast<double>(in_.size()) * 8 + 8) fail_at(*offs, offsets_what + ": entry " + std::to_string(i) + " is larger than the file can hold");
            previous = v;
            list.offsets.push_back(static_cast<int64_t>(v));
        }
        list.connectivity = read_array(*conn, parent, list.offsets.back(), true).values;
        check_indices(*conn, describe(*conn, parent), list.connectivity, static_cast<double>(np), "points");
        if (with_types) *types = read_array(*typ, parent, count, true).values;
        return list;
    };

    // Patches: the first integer-valued cell array with a patch-like name.
    int64_t total_cells = 0;
    int64_t nverts = 0, nlines = 0, nstrips = 0, npolys = 0;
    if (polydata) {
        nverts = int_attribute(piece, "NumberOfVerts", 0, false);
        nlines = int_attribute(piece, "NumberOfLines", 0, false);
        nstrips = int_attribute(piece, "NumberOfStrips", 0, false);
        npolys = int_attribute(piece, "NumberOfPolys", 0, false);
        const double sum = static_cast<double>(nverts) + static_cast<double>(nlines) + static_cast<double>(nstrips) + static_cast<double>(npolys);
        if (sum > static_cast<double>(in_.size())) fail_at(piece, "the <Piece> announces more cells than the file can hold");
        total_cells = nverts + nlines + nstrips + npolys;
    } else {
        total_cells = int_attribute(piece, "NumberOfCells", 0, true);
        if (static_cast<double>(total_cells) > static_cast<double>(in_.size())) fail_at(piece, "the <Piece> announces more cells than the file can hold");
    }
    std::vector<double> patch_values;
    bool have_patches = false;
    if (const XmlElement* cd = part("CellData")) {
        check_children(*cd, {"DataArray", "Array"});
        // Reads `d` as the patch ids if it is one integer-valued component per cell.
        const auto take_patches = [&](const XmlElement& d, const std::string& name) {
            VtkType t;
            const std::string* type = d.attribute("type");
            if (d.name != "DataArray" || !type || !vtk_type_from_name(*type, t)) return false;
            ArrayValues a = read_array(d, "CellData", -1, false);
            bool integral = a.components == 1;
            for (double v : a.values) integral = integral && v == std::floor(v) && v >= -2147483648.0 && v <= 2147483647.0;
            if (integral && static_cast<int64_t>(a.values.size()) != total_cells) {
                fail_at(d, describe(d, "CellData") + " holds " + std::to_string(a.values.size()) + " values for " +
                               std::to_string(total_cells) + " cells");
            }
            if (!integral) return false;
            patch_values = std::move(a.values);
            have_patches = true;
            if (patch_array_name_.empty()) patch_array_name_ = name;
            return true;
        };
        std::vector<std::string> ignored;
        const XmlElement* unnamed_scalars = nullptr;
        for (size_t c : cd->children) {
            const XmlElement& d = el(c);
            const std::string* n = d.attribute("Name");
            const std::string name = n ? *n : std::string();
            const std::string l = lower(name);
            const bool patch_name = l == "patch" || l == "material" || l == "region" || l == "label" ||
                                    l == "physical" || l == "gmsh:physical" || l == "cellentityids" || l == "regionid";
            if (!have_patches && patch_name && take_patches(d, name)) continue;
            // "Scalars_" is the name vtkXMLWriter gives unnamed scalars, such as the labels
            // vtkDiscreteMarchingCubes puts on its triangles (one closed surface per
            // label): the patch ids only if no array is named as patches.
            if (name == kUnnamedScalars && !unnamed_scalars) unnamed_scalars = &d;
            ignored.push_back(name);
        }
        if (!have_patches && unnamed_scalars && take_patches(*unnamed_scalars, kUnnamedScalars))
            ignored.erase(std::find(ignored.begin(), ignored.end(), std::string(kUnnamedScalars)));
        for (const std::string& name : ignored)
            if (std::find(ignored_cell_arrays_.begin(), ignored_cell_arrays_.end(), name) == ignored_cell_arrays_.end())
                ignored_cell_arrays_.push_back(name);
    }
    if (!have_patches) ++pieces_without_patches_;
    auto patch_of = [&](int64_t cell) {
        return have_patches ? static_cast<int32_t>(patch_values[static_cast<size_t>(cell)]) : 0;
    };

    // Triangles, strips and polygons, in file order.
    auto add_polygon = [&](const CellList& list, int64_t c, int64_t cell_index, const std::vector<int>* order,
                           const char* kind) {
        const int64_t b = list.offsets[static_cast<size_t>(c)], e = list.offsets[static_cast<size_t>(c) + 1];
        const int64_t n = e - b;
        if (n < 3) {
            fail_at(*list.at, std::string(kind) + " " + std::to_string(c) + " of <" + list.at->name + "> has " +
                                  std::to_string(n) + " corners");
        }
        if (n == 3) {
            Tri t;
            for (int k = 0; k < 3; ++k) t[k] = base + static_cast<int32_t>(list.connectivity[static_cast<size_t>(b + k)]);
            s.triangles.push_back(t);
            s.patches.push_back(patch_of(cell_index));
            return;
        }
        if (!accept_polygons_) {
            fail_at(*list.at, std::string(kind) + " " + std::to_string(c) + " of <" + list.at->name + "> has " +
                                  std::to_string(n) +
                                  " corners; only triangles are accepted (the triangulate-polygons repair splits "
                                  "polygons into triangles)");
        }
        PolygonFace polygon;
        polygon.position = s.triangles.size();
        polygon.face = cell_index;
        polygon.offset = list.at->at;
        polygon.patch = patch_of(cell_index);
        for (int64_t k = 0; k < n; ++k) {
            const int64_t from = order ? b + (*order)[static_cast<size_t>(k)] : b + k;
            polygon.corners.push_back(base + static_cast<int32_t>(list.connectivity[static_cast<size_t>(from)]));
        }
        out_.polygons.push_back(std::move(polygon));
    };
    auto add_strip = [&](const CellList& list, int64_t c, int64_t cell_index) {
        const int64_t b = list.offsets[static_cast<size_t>(c)], e = list.offsets[static_cast<size_t>(c) + 1];
        if (e - b < 3) {
            fail_at(*list.at, "triangle strip " + std::to_string(c) + " of <" + list.at->name + "> has " +
                                  std::to_string(e - b) + " points");
        }
        ++strip_count_;
        for (int64_t i = b; i + 2 < e; ++i) {
            // VTK's order: even triangles (i, i+1, i+2), odd ones (i+1, i, i+2), so that all
            // have the orientation of the first.
            const bool odd = ((i - b) & 1) != 0;
            Tri t;
            t[0] = base + static_cast<int32_t>(list.connectivity[static_cast<size_t>(odd ? i + 1 : i)]);
            t[1] = base + static_cast<int32_t>(list.connectivity[static_cast<size_t>(odd ? i : i + 1)]);
            t[2] = base + static_cast<int32_t>(list.connectivity[static_cast<size_t>(i + 2)]);
            // Strips repeat a point to turn or to join pieces; those triangles are no geometry.
            if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
                ++strip_degenerate_;
                continue;
            }
            s.triangles.push_back(t);
            s.patches.push_back(patch_of(cell_index));
        }
    };

    if (polydata) {
        skipped_vertex_cells_ += nverts;
        skipped_line_cells_ += nlines;
        // Verts and Lines are not read, but they must be valid elements.
        for (const char* n : {"Verts", "Lines"})
            if (const XmlElement* e = part(n)) check_children(*e, {"DataArray"});
        if (const XmlElement* polys = part("Polys")) {
            const CellList list = read_cells(*polys, "Polys", npolys, false, nullptr);
            for (int64_t c = 0; c < npolys; ++c) add_polygon(list, c, nverts + nlines + c, nullptr, "polygon");
        } else if (npolys > 0) {
            fail_at(piece, "the <Piece> announces " + std::to_string(npolys) + " polygons but has no <Polys>");
        }
        if (const XmlElement* strips = part("Strips")) {
            const CellList list = read_cells(*strips, "Strips", nstrips, false, nullptr);
            for (int64_t c = 0; c < nstrips; ++c) add_strip(list, c, nverts + nlines + npolys + c);
        } else if (nstrips > 0) {
            fail_at(piece, "the <Piece> announces " + std::to_string(nstrips) + " strips but has no <Strips>");
        }
    } else {
        const XmlElement* cells = part("Cells");
        if (!cells && total_cells > 0) fail_at(piece, "the <Piece> announces " + std::to_string(total_cells) + " cells but has no <Cells>");
        if (cells) {
            std::vector<double> types;
            const CellList list = read_cells(*cells, "Cells", total_cells, true, &types);
            static const std::vector<int> pixel_order = {0, 1, 3, 2};
            int64_t surface_cells = 0;
            for (int64_t c = 0; c < total_cells; ++c) {
                const double tv = types[static_cast<size_t>(c)];
                const int type = tv >= 0 && tv <= 255 && tv == std::floor(tv) ? static_cast<int>(tv) : -1;
                const int64_t n = list.offsets[static_cast<size_t>(c) + 1] - list.offsets[static_cast<size_t>(c)];
                auto need = [&](int64_t corners, const char* kind) {
                    if (n != corners) {
                        fail_at(*cells, std::string(kind) + " cell " + std::to_string(c) + " has " + std::to_string(n) +
                                            " points, " + std::to_string(corners) + " expected");
                    }
                };
                switch (type) {
                    case 5: need(3, "triangle"); add_polygon(list, c, c, nullptr, "cell"); ++surface_cells; break;
                    case 7: add_polygon(list, c, c, nullptr, "polygon cell"); ++surface_cells; break;
                    case 9: need(4, "quad"); add_polygon(list, c, c, nullptr, "quad cell"); ++surface_cells; break;
                    case 8: need(4, "pixel"); add_polygon(list, c, c, &pixel_order, "pixel cell"); ++surface_cells; break;
                    case 6: add_strip(list, c, c); ++surface_cells; break;
                    case 1:
                    case 2: ++skipped_vertex_cells_; break;
                    case 3:
                    case 4: ++skipped_line_cells_; break;
                    default: ++skipped_other_cells_; ++skipped_types_[type]; break;
                }
            }
            if (surface_cells == 0 && total_cells > 0 && skipped_other_cells_ > 0) {
                fail_at(*cells, "no surface cells (triangles, polygons, quads, strips), only " +
                                    std::to_string(skipped_other_cells_) +
                                    " volume or other cells; bpm reads surfaces; extract the boundary first (e.g. "
                                    "ParaView's Extract Surface)");
            }
        }
    }

    // Point data.
    std::vector<ArrayValues> arrays;
    if (const XmlElement* pd = part("PointData")) {
        check_children(*pd, {"DataArray", "Array"});
        for (size_t c : pd->children) {
            const XmlElement& d = el(c);
            const std::string* n = d.attribute("Name");
            const std::string* type = d.attribute("type");
            VtkType t;
            if (d.name != "DataArray" || !type || !vtk_type_from_name(*type, t)) {
                point_data_notes_.push_back("point data " + quote_token(n ? *n : "") + " left out: its type " +
                                            quote_token(type ? *type : "") + " is not numeric");
                continue;
            }
            const int64_t comps = int_attribute(d, "NumberOfComponents", 1, false);
            if (comps < 1 || comps > 1000000) fail_at(d, describe(d, "PointData") + ": NumberOfComponents must be 1 to 1000000");
            arrays.push_back(read_array(d, "PointData", np * comps, false));
        }
    }
    if (piece_number == 0) {
        for (ArrayValues& a : arrays) point_data_.push_back({a.name, a.components, std::move(a.values), true});
    } else {
        std::vector<bool> used(arrays.size(), false);
        for (PendingArray& p : point_data_) {
            if (!p.alive) continue;
            bool found = false;
            for (size_t i = 0; i < arrays.size() && !found; ++i) {
                if (used[i] || arrays[i].name != p.name || arrays[i].components != p.components) continue;
                used[i] = found = true;
                p.values.insert(p.values.end(), arrays[i].values.begin(), arrays[i].values.end());
            }
            if (!found) {
                p.alive = false;
                p.values.clear();
                point_data_notes_.push_back("point data " + quote_token(p.name) + " left out: piece " +
                                            std::to_string(piece_number) + " has no such array");
            }
        }
        for (size_t i = 0; i < arrays.size(); ++i) {
            if (!used[i]) {
                point_data_notes_.push_back("point data " + quote_token(arrays[i].name) + " of piece " +
                                            std::to_string(piece_number) + " left out: the first piece has no such array");
            }
        }
    }
    // Arrays of the first piece that are missing in this one (found above) are dead;
    // arrays of a piece without points need no values.
}

ReaderOutput VtkXmlReader::read() {
    if (in_.size() == 0) in_.fail("the file is empty");
    doc_ = scan_xml(in_);
    const XmlElement& root = el(0);
    if (root.name != "VTKFile") fail_at(root, "the root element is <" + root.name + ">, not <VTKFile>: not a VTK XML file");
    const std::string* type = root.attribute("type");
    if (!type) fail_at(root, "<VTKFile> has no attribute type");
    const bool polydata = *type == "PolyData";
    if (!polydata && *type != "UnstructuredGrid") {
        fail_at(root, "VTKFile type " + quote_token(*type) +
                          " is not supported; bpm reads PolyData (.vtp) and UnstructuredGrid (.vtu) surfaces" +
                          (type->size() > 1 && (*type)[0] == 'P'
                               ? " (a parallel file: bpm reads its pieces when given its path, not its bytes alone)"
                               : ""));
    }
    if (const std::string* order = root.attribute("byte_order")) {
        if (*order == "BigEndian") big_endian_ = true;
        else if (*order != "LittleEndian") fail_at(root, "unknown byte_order " + quote_token(*order));
    }
    if (const std::string* header = root.attribute("header_type")) {
        if (*header == "UInt64") header64_ = true;
        else if (*header != "UInt32") fail_at(root, "unknown header_type " + quote_token(*header) + " (expected UInt32 or UInt64)");
    }
    if (const std::string* compressor = root.attribute("compressor")) {
        if (*compressor == "vtkZLibDataCompressor") zlib_ = true;
        else if (!compressor->empty()) {
            fail_at(root, "compressor " + quote_token(*compressor) +
                              " is not supported (only vtkZLibDataCompressor); save the file with zlib or without compression");
        }
    }
    check_children(root, {type->c_str(), "AppendedData"});
    if (doc_.has_appended) {
        const XmlElement& appended = el(doc_.appended_element);
        const std::string* encoding = appended.attribute("encoding");
        if (!encoding || *encoding == "base64") appended_base64_ = true;
        else if (*encoding != "raw") fail_at(appended, "unknown AppendedData encoding " + quote_token(*encoding));
    }
    const XmlElement* dataset = nullptr;
    for (size_t c : root.children) {
        if (el(c).name == *type) {
            if (dataset) fail_at(el(c), "a second <" + *type + ">");
            dataset = &el(c);
        }
    }
    if (!dataset) fail_at(root, "<VTKFile type=\"" + *type + "\"> has no <" + *type + "> element");
    check_children(*dataset, {"Piece", "FieldData"});
    size_t pieces = 0;
    for (size_t c : dataset->children) {
        if (el(c).name != "Piece") continue;
        read_piece(el(c), polydata, pieces++);
    }

    Surface& s = out_.surface;
    // Point data: names made storable and unique, non-finite arrays left out.
    for (PendingArray& p : point_data_) {
        if (!p.alive) continue;
        std::string name = p.name;
        std::replace(name.begin(), name.end(), '/', '_');
        if (name.empty() || name == ".") name = "point_data_" + std::to_string(s.vertex_data.size());
        const std::string stem = name;
        for (int suffix = 2;; ++suffix) {
            bool taken = false;
            for (const VertexArray& a : s.vertex_data) taken = taken || a.name == name;
            if (!taken) break;
            name = stem + "_" + std::to_string(suffix);
        }
        const auto bad = std::find_if(p.values.begin(), p.values.end(), [](double x) { return !std::isfinite(x); });
        if (bad != p.values.end()) {
            out_.notes.push_back("vertex data " + quote_token(p.name) + " left out: vertex " +
                                 std::to_string((bad - p.values.begin()) / p.components) +
                                 " has a value that is not a finite number");
            continue;
        }
        if (name != p.name) out_.notes.push_back("point data " + quote_token(p.name) + " stored as " + quote_token(name));
        s.vertex_data.push_back({name, p.components, std::move(p.values)});
    }
    for (std::string& note : point_data_notes_) out_.notes.push_back(std::move(note));
    if (!patch_array_name_.empty()) {
        out_.notes.push_back("patch ids from the cell data array " + quote_token(patch_array_name_) +
                             (patch_array_name_ == kUnnamedScalars ? " (VTK's name for unnamed cell scalars, such as "
                                                                     "the labels of vtkDiscreteMarchingCubes)"
                                                                   : "") +
                             (pieces_without_patches_ > 0 ? " (0 in the " + std::to_string(pieces_without_patches_) +
                                                                " pieces without it)"
                                                          : ""));
    }
    if (!ignored_cell_arrays_.empty()) {
        std::string list;
        for (size_t i = 0; i < ignored_cell_arrays_.size() && i < 8; ++i) list += (i ? ", " : "") + quote_token(ignored_cell_arrays_[i]);
        if (ignored_cell_arrays_.size() > 8) list += ", ...";
        out_.notes.push_back("cell data arrays ignored (bpm keeps only a patch id per triangle): " + list);
    }
    if (skipped_vertex_cells_ > 0 || skipped_line_cells_ > 0) {
        out_.notes.push_back("skipped " + std::to_string(skipped_vertex_cells_) + " vertex and " +
                             std::to_string(skipped_line_cells_) + " line cells (bpm reads surfaces)");
    }
    if (skipped_other_cells_ > 0) {
        std::string types;
        for (const auto& [t, n] : skipped_types_) types += (types.empty() ? "" : ", ") + std::to_string(n) + " of type " + std::to_string(t);
        out_.notes.push_back("skipped " + std::to_string(skipped_other_cells_) + " volume or higher-order cells (" +
                             types + ")");
    }
    if (strip_count_ > 0) {
        out_.notes.push_back("split " + std::to_string(strip_count_) + " triangle strips into triangles" +
                             (strip_degenerate_ > 0 ? " (" + std::to_string(strip_degenerate_) +
                                                          " degenerate strip triangles left out)"
                                                    : ""));
    }
    insert_polygons(in_, false, out_);
    return std::move(out_);
}

}  // namespace

ReaderOutput read_vtk_xml(std::string_view bytes, const std::string& name, bool accept_polygons) {
    VtkXmlReader reader(bytes, name, accept_polygons);
    return reader.read();
}

std::vector<std::string> parallel_vtk_xml_sources(std::string_view bytes, const std::string& name) {
    const InputCursor in(bytes, name);
    if (in.size() == 0) in.fail("the file is empty");
    const XmlDocument doc = scan_xml(in);
    const XmlElement& root = doc.elements[0];
    if (root.name != "VTKFile") in.fail_line(root.at, "the root element is <" + root.name + ">, not <VTKFile>: not a VTK XML file");
    const std::string* type = root.attribute("type");
    if (!type || (*type != "PPolyData" && *type != "PUnstructuredGrid"))
        in.fail_line(root.at, "not a parallel VTK XML file (VTKFile type PPolyData or PUnstructuredGrid)");
    const XmlElement* dataset = nullptr;
    for (size_t c : root.children)
        if (doc.elements[c].name == *type) dataset = &doc.elements[c];
    if (!dataset) in.fail_line(root.at, "<VTKFile type=\"" + *type + "\"> has no <" + *type + "> element");
    if (const std::string* ghosts = dataset->attribute("GhostLevel"); ghosts && *ghosts != "0") {
        // Ghost cells are copies of the neighbouring pieces' cells: the union would hold
        // every border triangle twice.
        in.fail_line(dataset->at, "GhostLevel " + quote_token(*ghosts) +
                              ": pieces with ghost cells are not supported; write the file with ghost level 0");
    }
    std::vector<std::string> sources;
    for (size_t c : dataset->children) {
        const XmlElement& piece = doc.elements[c];
        if (piece.name != "Piece") continue;
        const std::string* source = piece.attribute("Source");
        if (!source || source->empty()) in.fail_line(piece.at, "<Piece> has no attribute Source (the file of the piece)");
        sources.push_back(*source);
    }
    if (sources.empty()) in.fail_line(dataset->at, "<" + *type + "> lists no <Piece Source=...>: no piece files to read");
    return sources;
}

}  // namespace bpm::detail
