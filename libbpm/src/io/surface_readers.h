#pragma once
// Internal to the surface readers (not public API): one function per format, each over
// a whole file already in memory, and the cursor they share.
//
// The readers only parse. They reject what they cannot represent (syntax, counts that do
// not fit the input, NaN/Inf, indices outside the vertex list) with the line or byte
// offset where it happens; everything that is a property of the finished surface
// (zero-area and duplicate triangles, unreferenced and duplicate vertices) is left to
// validate_surface(), called by read_surface() after the requested repairs.
//
// Polygons (faces with more than three corners; OFF, OBJ, PLY, VTK, VTP/VTU) are not
// rejected here: read_surface always passes accept_polygons = true, the reader
// triangulates them (insert_polygons) and notes where they were
// (ReaderOutput::triangulated_polygons), and finish_reading in surface_io.cpp then refuses
// the surface with InputNeedsRepair, listing SurfaceRepair::TriangulatePolygons together
// with every other repair the triangulated surface needs, unless the caller asked for
// SurfaceReadOptions::triangulate_polygons. So polygons are never triangulated silently,
// and one error names all repairs. Only a face that cannot be triangulated (not a simple
// polygon seen along its normal) is an error of the reader itself. accept_polygons =
// false (the default) makes the reader refuse the first polygon face, with its line or
// byte offset; no caller in libbpm uses that any more.
//
// Every error is a bpm::InputError whose `where` is the file name and whose message
// starts with the location: "line 12: ..." (text) or "byte offset 84: ..." (binary).

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "bpm/errors.h"
#include "bpm/patch_info.h"
#include "bpm/surface.h"
#include "bpm/surface_io.h"
#include "core/number_text.h"

namespace bpm::detail {

// A face with more than three corners, kept when the caller accepts polygons (always, from
// read_surface); insert_polygons() replaces it by triangles.
struct PolygonFace {
    size_t position = 0;           // triangles read before it: its triangles go there
    int64_t face = 0;              // index of the face in the file, for messages
    size_t offset = 0;             // where it starts in the file, for messages
    int32_t patch = 0;
    std::vector<int32_t> corners;  // vertex indices, in range
};

// What a reader produced besides the surface.
struct ReaderOutput {
    Surface surface;
    int64_t skipped_elements = 0;    // MSH: elements that are not 3-node triangles; VTK: vertex, line, volume cells
    std::vector<std::string> notes;  // remarks for SurfaceReadReport::notes
    std::vector<PolygonFace> polygons;  // with accept_polygons only; in file order
    // After insert_polygons: where the first polygon face is and how many there were, e.g.
    // "line 22: face 0 has 4 corners (and 5 more polygon faces)"; empty if none.
    std::string triangulated_polygons;
    std::vector<PatchInfo> patch_info;  // what the file says about its patches (SURF, MSH), by patch id
    // Names of patches that say nothing about materials (OBJ groups such as "inlet"), by
    // patch id: finish_reading gives them to the patches' PatchInfo, whose materials
    // come from the file (apply_file_material), or alone when there are none.
    std::vector<std::pair<int32_t, std::string>> patch_names;
    // Label images: the anatomical frame of the coordinates (bpm/label_image.h).
    ImageFrame frame = ImageFrame::Unknown;
};

// `accept_polygons`: faces with more than three corners go to ReaderOutput::polygons
// and are triangulated before the reader returns, instead of being refused (read_surface
// decides afterwards whether the triangulate-polygons repair was asked for).
ReaderOutput read_off(std::string_view bytes, const std::string& name, bool accept_polygons = false);
ReaderOutput read_obj(std::string_view bytes, const std::string& name, bool accept_polygons = false);
ReaderOutput read_stl(std::string_view bytes, const std::string& name);
ReaderOutput read_ply(std::string_view bytes, const std::string& name, bool accept_polygons = false);
ReaderOutput read_msh(std::string_view bytes, const std::string& name);
ReaderOutput read_vtk(std::string_view bytes, const std::string& name, bool accept_polygons = false);
// VTK XML PolyData and UnstructuredGrid (either file type, whichever format was chosen).
ReaderOutput read_vtk_xml(std::string_view bytes, const std::string& name, bool accept_polygons = false);
// Parallel VTK XML (.pvtp / .pvtu): the Source of each <Piece> in file order (relative to
// the file's directory). Refuses ghost levels above 0.
std::vector<std::string> parallel_vtk_xml_sources(std::string_view bytes, const std::string& name);
// Amira / Avizo HyperSurface (.surf), ASCII and BINARY; one patch per Patches entry.
ReaderOutput read_surf(std::string_view bytes, const std::string& name);

// "OFF", "MSH", "HyperSurface", ...: a format as messages name it.
const char* surface_format_name(SurfaceFormat format);

// A token for an error message: quoted, shortened, non-printable bytes as \xNN, so that
// binary garbage never ends up raw in a terminal.
inline std::string quote_token(std::string_view token) {
    if (token.empty()) return "nothing";
    static const char* hex = "0123456789abcdef";
    std::string out = "'";
    const size_t limit = 40;
    for (size_t i = 0; i < token.size() && i < limit; ++i) {
        const unsigned char c = static_cast<unsigned char>(token[i]);
        if (c >= 0x20 && c < 0x7f && c != '\'') {
            out += static_cast<char>(c);
        } else {
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    if (token.size() > limit) out += "...";
    out += "'";
    return out;
}

// What is being read, for error messages only: kept as pieces and assembled only when an
// error is reported, so that the hot loops build no strings. Lives no longer than the
// call it is passed to (it may point to a temporary string).
class Label {
public:
    Label(const char* text) : a_(text) {}
    Label(const std::string& text) : s_(&text) {}
    // a + n + b + c, e.g. Label("vertex ", 17, ": coordinate ", "x")
    Label(const char* a, int64_t n, const char* b = "", const char* c = "") : a_(a), b_(b), c_(c), n_(n), has_n_(true) {}
    std::string str() const {
        std::string out = s_ ? *s_ : std::string(a_);
        if (has_n_) out += std::to_string(n_);
        return out + b_ + c_;
    }

private:
    const char* a_ = "";
    const char* b_ = "";
    const char* c_ = "";
    const std::string* s_ = nullptr;
    int64_t n_ = 0;
    bool has_n_ = false;
};

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }
inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// A position in one input file, for text tokens and binary values alike (MSH mixes the
// two). Line numbers are computed only when an error is reported, so that parsing does
// not pay for them.
class InputCursor {
public:
    // `comment`: character that starts a comment running to the end of the line (0: none).
    InputCursor(std::string_view bytes, std::string name, char comment = 0)
        : bytes_(bytes), name_(std::move(name)), comment_(comment) {}

    size_t pos() const { return pos_; }
    void seek(size_t pos) { pos_ = pos < bytes_.size() ? pos : bytes_.size(); }
    size_t size() const { return bytes_.size(); }
    size_t remaining() const { return bytes_.size() - pos_; }
    bool at_end() const { return pos_ >= bytes_.size(); }
    std::string_view bytes() const { return bytes_; }
    const std::string& name() const { return name_; }
    size_t offset_of(std::string_view token) const {
        return token.data() == nullptr ? pos_ : static_cast<size_t>(token.data() - bytes_.data());
    }

    // ---- errors -------------------------------------------------------------------
    int64_t line_of(size_t at) const {
        int64_t line = 1;
        const size_t end = at < bytes_.size() ? at : bytes_.size();
        for (size_t i = 0; i < end; ++i) line += bytes_[i] == '\n' ? 1 : 0;
        return line;
    }
    [[noreturn]] void fail(const std::string& message) const { throw InputError(name_, message); }
    [[noreturn]] void fail_line(size_t at, const std::string& message) const {
        throw InputError(name_, "line " + std::to_string(line_of(at)) + ": " + message);
    }
    [[noreturn]] void fail_offset(size_t at, const std::string& message) const {
        throw InputError(name_, "byte offset " + std::to_string(at) + ": " + message);
    }
    [[noreturn]] void fail_token(std::string_view token, const Label& expected) const {
        const size_t at = offset_of(token);
        std::string found;
        if (!token.empty()) found = quote_token(token);
        else if (at >= bytes_.size()) found = "the end of the file";
        else found = "the end of the line";
        fail_line(at, "expected " + expected.str() + ", found " + found);
    }

    // ---- text ---------------------------------------------------------------------
    // Skips blanks and a comment, but not the end of the line.
    void skip_blanks() {
        while (pos_ < bytes_.size()) {
            const char c = bytes_[pos_];
            if (is_blank(c)) {
                ++pos_;
            } else if (comment_ != 0 && c == comment_) {
                while (pos_ < bytes_.size() && bytes_[pos_] != '\n') ++pos_;
            } else {
                break;
            }
        }
    }
    // Skips whitespace, line ends and comments.
    void skip_space() {
        for (;;) {
            skip_blanks();
            if (pos_ < bytes_.size() && bytes_[pos_] == '\n') {
                ++pos_;
                continue;
            }
            return;
        }
    }
    bool at_line_end() {
        skip_blanks();
        return pos_ >= bytes_.size() || bytes_[pos_] == '\n';
    }
    // Next token of the current line; empty (pointing at the line end) if there is none.
    std::string_view token_on_line() {
        skip_blanks();
        return take_token();
    }
    // Next token anywhere; empty at the end of the input.
    std::string_view next_token() {
        skip_space();
        return take_token();
    }
    // Moves past the next line end.
    void skip_line() {
        while (pos_ < bytes_.size() && bytes_[pos_] != '\n') ++pos_;
        if (pos_ < bytes_.size()) ++pos_;
    }
    // The rest of the current line without the line end (which is consumed).
    std::string_view rest_of_line() {
        const size_t begin = pos_;
        while (pos_ < bytes_.size() && bytes_[pos_] != '\n') ++pos_;
        size_t end = pos_;
        if (pos_ < bytes_.size()) ++pos_;
        while (end > begin && bytes_[end - 1] == '\r') --end;
        return bytes_.substr(begin, end - begin);
    }
    // Fails unless only blanks (and a comment) remain on the line; then moves past it.
    void expect_line_end(const char* context) {
        const std::string_view extra = token_on_line();
        if (!extra.empty()) fail_line(offset_of(extra), std::string("unexpected ") + quote_token(extra) + " " + context);
        skip_line();
    }

    // Numbers: the whole token must be the number; NaN and infinities are refused.
    double to_double(std::string_view token, const Label& what) const {
        if (token.empty()) fail_token(token, what);
        std::string_view t = token;
        if (t.size() > 1 && t[0] == '+' && t[1] != '-' && t[1] != '+') t.remove_prefix(1);
        double value = 0;
        // Underflow becomes a tiny number or zero like strtod does; overflow (+-inf) is refused below.
        const auto [end, ec] = detail::parse_double(t.data(), t.data() + t.size(), value);
        if (end != t.data() + t.size() || ec != std::errc()) fail_token(token, what.str() + " (a number)");
        if (!std::isfinite(value)) {
            fail_line(offset_of(token), what.str() + " " + quote_token(token) + " is not a finite number");
        }
        return value;
    }
    // A number that is read only to be ignored (STL facet normals): NaN and Inf pass,
    // since exporters write them for degenerate facets.
    void check_number(std::string_view token, const Label& what) const {
        std::string_view t = token;
        if (t.size() > 1 && t[0] == '+') t.remove_prefix(1);
        double value = 0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
        if (t.empty() || end != t.data() + t.size() || (ec != std::errc() && ec != std::errc::result_out_of_range)) {
            fail_token(token, what.str() + " (a number)");
        }
    }
    int64_t to_int(std::string_view token, const Label& what) const {
        if (token.empty()) fail_token(token, what);
        std::string_view t = token;
        if (t.size() > 1 && t[0] == '+' && t[1] != '-' && t[1] != '+') t.remove_prefix(1);
        int64_t value = 0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
        if (ec == std::errc::result_out_of_range) {
            fail_line(offset_of(token), what.str() + " " + quote_token(token) + " is out of range");
        }
        if (ec != std::errc() || end != t.data() + t.size()) fail_token(token, what.str() + " (an integer)");
        return value;
    }
    double line_double(const Label& what) { return to_double(token_on_line(), what); }
    int64_t line_int(const Label& what) { return to_int(token_on_line(), what); }
    double any_double(const Label& what) { return to_double(next_token(), what); }
    int64_t any_int(const Label& what) { return to_int(next_token(), what); }

    // ---- binary -------------------------------------------------------------------
    void require(size_t n, const Label& what) const {
        if (n > remaining()) {
            fail_offset(pos_, "the file ends inside " + what.str() + " (" + std::to_string(n) + " bytes needed, " +
                                  std::to_string(remaining()) + " left)");
        }
    }
    template <class T>
    T read_binary(bool big_endian, const Label& what) {
        static_assert(std::is_arithmetic_v<T>);
        require(sizeof(T), what);
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, bytes_.data() + pos_, sizeof(T));
        if (big_endian != host_is_big_endian()) {
            for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
        }
        T value;
        std::memcpy(&value, raw, sizeof(T));
        pos_ += sizeof(T);
        return value;
    }
    static bool host_is_big_endian() {
        const uint16_t probe = 1;
        unsigned char first;
        std::memcpy(&first, &probe, 1);
        return first == 0;
    }

private:
    std::string_view take_token() {
        const size_t begin = pos_;
        while (pos_ < bytes_.size() && !is_space(bytes_[pos_]) && !(comment_ != 0 && bytes_[pos_] == comment_)) ++pos_;
        return bytes_.substr(begin, pos_ - begin);
    }

    std::string_view bytes_;
    std::string name_;
    char comment_ = 0;
    size_t pos_ = 0;
};

// Refuses a count from a header before anything is allocated for it: `count` elements of
// at least `min_bytes` bytes each must fit into what is left of the input, and the
// result must be indexable by int32 (bpm's index type).
inline void check_count(const InputCursor& in, size_t at, bool binary, int64_t count, double min_bytes,
                        const std::string& what) {
    auto fail = [&](const std::string& message) {
        if (binary) in.fail_offset(at, message);
        in.fail_line(at, message);
    };
    if (count < 0) fail("negative number of " + what + " (" + std::to_string(count) + ")");
    if (count > std::numeric_limits<int32_t>::max()) {
        fail(std::to_string(count) + " " + what + " announced; bpm supports at most " +
             std::to_string(std::numeric_limits<int32_t>::max()));
    }
    if (static_cast<double>(count) * min_bytes > static_cast<double>(in.remaining())) {
        fail(std::to_string(count) + " " + what + " announced, but the " + std::to_string(in.remaining()) +
             " bytes left in the file cannot hold that many (truncated, or wrong counts?)");
    }
}

// Replaces out.polygons by their triangles (polygon_triangulation.h), each at its place
// among the triangles and with its patch (out.surface.patches must be complete), and
// adds a note. A polygon that cannot be triangulated fails with its face index and line
// (text) or byte offset (binary).
void insert_polygons(const InputCursor& in, bool binary, ReaderOutput& out);

}  // namespace bpm::detail
