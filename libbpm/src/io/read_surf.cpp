// Amira / Avizo HyperSurface reader (.surf): "# HyperSurface 0.1 ASCII" and
// "# HyperSurface 0.1 BINARY", the surfaces of multi-material segmentations (SurfaceGen).
//
// Layout (keywords one per line; case-insensitive here, since writers differ, e.g.
// BoundaryID / BoundaryId):
//
//   # HyperSurface 0.1 ASCII
//   Parameters { Materials { Exterior { Id 1 } ... } Units { Coordinates "mm" } ... }
//   Vertices N                 then N points x y z
//   NBranchingPoints n         counts only, no values follow (they describe the first
//   NVerticesOnCurves m        vertices of the list: branching points, then curve vertices)
//   BoundaryCurves c           then c blocks { Vertices k  <k indices> }
//   Patches P                  then P blocks
//     { InnerRegion NAME  OuterRegion NAME  BoundaryID b  BranchingPoints n <n indices>
//       [BoundaryCurves k <k signed curve numbers>]  Triangles M  <M triples of vertex indices> }
//   Surfaces s                 then s blocks { Region NAME  Patches k <k signed patch numbers> }
//
// Vertex indices are one-based. In BINARY files the values after a count line start right
// after its line end: Vertices as big-endian float32 triples, Triangles as big-endian int32
// triples, and the index lists (BranchingPoints, a patch's BoundaryCurves, a curve's
// Vertices, a surface's Patches) as big-endian int32; all other text stays text.
// "BINARY-LITTLE-ENDIAN" (AmiraMesh's name for little-endian data) is read the same way
// with the other byte order.
//
// Read: Vertices, and each Patches entry as one patch id (0, 1, 2, ... in file order), with
// a note naming its regions and a PatchInfo (name "Inner|Outer", front = OuterRegion,
// back = InnerRegion: Amira's triangles face the outer region). Parsed and not used: Parameters (nested braces, quoted strings
// and comments skipped), the branching-point counts, BoundaryCurves, BoundaryID, Surfaces.
// ASCII only: an unknown key inside a block, or an unknown section, is skipped with its
// values (a `{ ... }` block, or the rest of its line and the lines of numbers after it),
// with a note; in a BINARY file it is refused, since how much binary data follows it
// cannot be known. Refused: another first line (AmiraMesh surfaces included), other
// versions than 0.1, Patches before Vertices, a patch without Triangles, indices outside
// 1..N, NaN/Inf, counts that do not fit the file, truncated data, unbalanced braces,
// content where a key belongs.
//
// Messages number vertices as the file does (from 1) and patches as bpm does (from 0: the
// patch id); text positions are lines in ASCII files and byte offsets in BINARY ones.
#include <algorithm>
#include <cctype>
#include <map>
#include <string>
#include <vector>

#include "io/surface_readers.h"

namespace bpm::detail {

namespace {

bool same_key(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i])))
            return false;
    return true;
}

// Whether a token starts like a number (a value line, not a key).
bool looks_numeric(std::string_view t) {
    if (t.empty()) return false;
    const char c = t[0];
    return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
    while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
    return s;
}

enum class Block { Patch, BoundaryCurve, Surface };

struct SurfPatch {
    std::string inner, outer;
    bool has_boundary_id = false;
    int64_t boundary_id = 0;
    int64_t triangles = -1;  // -1: no Triangles key
};

class SurfReader {
public:
    SurfReader(std::string_view bytes, const std::string& name) : in_(bytes, name, '#') {}

    ReaderOutput read() {
        read_header();
        for (;;) {
            const std::string_view key = token(false);
            if (key.empty()) break;
            if (same_key(key, "Parameters")) {
                skip_block_after(key, "the Parameters block");
            } else if (same_key(key, "Vertices")) {
                read_vertices(key);
            } else if (same_key(key, "NBranchingPoints") || same_key(key, "NVerticesOnCurves")) {
                (void)count_on_line(key, 0, "");
                if (!binary_) skip_number_lines();
            } else if (same_key(key, "BoundaryCurves")) {
                const int64_t n = count_on_line(key, 2, "boundary curves");
                for (int64_t i = 0; i < n; ++i) read_block(Block::BoundaryCurve, i, nullptr);
            } else if (same_key(key, "Patches")) {
                if (have_patches_) fail_at(in_.offset_of(key), "a second Patches section");
                if (!have_vertices_) fail_at(in_.offset_of(key), "Patches before Vertices");
                have_patches_ = true;
                // Smallest patch: "{Triangles 0}".
                const int64_t n = count_on_line(key, 13, "patches");
                infos_.resize(static_cast<size_t>(n));
                for (int64_t p = 0; p < n; ++p) read_block(Block::Patch, p, &infos_[static_cast<size_t>(p)]);
            } else if (same_key(key, "Surfaces")) {
                const int64_t n = count_on_line(key, 2, "surfaces");
                for (int64_t i = 0; i < n; ++i) read_block(Block::Surface, i, nullptr);
            } else if (key == "{" || key == "}" || looks_numeric(key)) {
                fail_expected(key, "a section keyword such as Vertices or Patches",
                              looks_numeric(key) ? " (more values than a count announced?)" : "");
            } else {
                skip_unknown(key, "at the top level");
            }
        }
        if (!have_vertices_) in_.fail("no Vertices section");
        if (!have_patches_) in_.fail("no Patches section (the file holds no triangles)");
        return finish();
    }

private:
    // ---- locations ------------------------------------------------------------------
    [[noreturn]] void fail_at(size_t at, const std::string& message) const {
        if (binary_) in_.fail_offset(at, message);
        in_.fail_line(at, message);
    }
    [[noreturn]] void fail_expected(std::string_view token, const std::string& expected, const char* hint = "") const {
        const size_t at = in_.offset_of(token);
        std::string found;
        if (!token.empty())
            found = quote_token(token);
        else if (at >= in_.size())
            found = "the end of the file";
        else
            found = "the end of the line";
        fail_at(at, "expected " + expected + ", found " + found + hint);
    }

    // ---- text -----------------------------------------------------------------------
    // The next token (on the current line only, or anywhere); braces are tokens of their
    // own. Empty at the end of the line / input.
    std::string_view token(bool on_line) {
        on_line ? in_.skip_blanks() : in_.skip_space();
        const std::string_view b = in_.bytes();
        const size_t begin = in_.pos();
        size_t end = begin;
        if (end < b.size() && (b[end] == '{' || b[end] == '}')) {
            ++end;
        } else {
            while (end < b.size() && !is_space(b[end]) && b[end] != '{' && b[end] != '}' && b[end] != '#') ++end;
        }
        in_.seek(end);
        return b.substr(begin, end - begin);
    }
    std::string_view peek(bool on_line) {
        const size_t at = in_.pos();
        const std::string_view t = token(on_line);
        in_.seek(at);
        return t;
    }

    int64_t integer(std::string_view token, const Label& what) const {
        if (!binary_) return in_.to_int(token, what);
        std::string_view t = token;
        if (t.size() > 1 && t[0] == '+') t.remove_prefix(1);
        int64_t value = 0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
        if (token.empty()) fail_expected(token, what.str());
        if (ec != std::errc() || end != t.data() + t.size()) fail_expected(token, what.str() + " (an integer)");
        return value;
    }

    // The count after `key` on its line, checked against what is left of the file
    // (`ascii_bytes` per element, 4 or 12 in binary; 0: no check, nothing is allocated).
    int64_t count_on_line(std::string_view key, double ascii_bytes, const std::string& what, double binary_bytes = 0) {
        const std::string_view t = token(true);
        const int64_t n = integer(t, "a count after '" + std::string(key) + "'");
        if (n < 0)
            fail_at(in_.offset_of(t), "negative count " + std::to_string(n) + " after '" + std::string(key) + "'");
        if (ascii_bytes > 0) {
            const double bytes = binary_ && binary_bytes > 0 ? binary_bytes : ascii_bytes;
            check_count(in_, in_.offset_of(t), binary_, n, bytes, what);
        }
        return n;
    }

    // Binary values start right after the line end of their count line.
    void begin_binary_data(std::string_view count_token, const char* what) {
        in_.skip_blanks();
        const size_t at = in_.pos();
        if (at >= in_.size()) return;  // reading the values reports the truncation
        if (in_.bytes()[at] != '\n') {
            const std::string_view extra = token(true);
            fail_at(at, "unexpected " + quote_token(extra.empty() ? in_.bytes().substr(at, 1) : extra) +
                            " after the count " + quote_token(count_token) + (*what ? " of " : "") + what +
                            " (the binary values start on the next line)");
        }
        in_.seek(at + 1);
    }

    // Moves past the `{ ... }` block whose '{' follows `key` (nested braces, "quoted
    // strings" that may hold braces, and '#' comments).
    void skip_block_after(std::string_view key, const std::string& what) {
        const std::string_view open = token(false);
        if (open != "{") fail_expected(open, "'{' after " + quote_token(key));
        skip_block(in_.offset_of(open), what);
    }
    void skip_block(size_t open_at, const std::string& what) {
        const std::string_view b = in_.bytes();
        size_t i = open_at + 1;
        int depth = 1;
        while (i < b.size()) {
            const char c = b[i];
            if (c == '"') {
                const size_t quote = i++;
                while (i < b.size() && b[i] != '"') i += b[i] == '\\' ? 2 : 1;
                if (i >= b.size()) fail_at(quote, "a quoted string in " + what + " is not closed");
            } else if (c == '#') {
                while (i < b.size() && b[i] != '\n') ++i;
                continue;
            } else if (c == '{') {
                ++depth;
            } else if (c == '}' && --depth == 0) {
                in_.seek(i + 1);
                return;
            }
            ++i;
        }
        fail_at(open_at, "the '{' of " + what + " is never closed (unbalanced braces, or a truncated file)");
    }

    // ASCII: the rest of the line, then every following line that starts with a number.
    void skip_number_lines() {
        in_.skip_line();
        while (looks_numeric(peek(false))) {
            (void)token(false);
            in_.skip_line();
        }
    }

    // An unknown key or section: skipped in ASCII files (with a note), refused in binary ones.
    void skip_unknown(std::string_view key, const std::string& where) {
        if (binary_) {
            fail_at(in_.offset_of(key), "unknown key " + quote_token(key) + " " + where +
                                            ": in a BINARY file its values cannot be skipped safely");
        }
        const std::string name(key);
        if (skipped_.find(name) == skipped_.end()) skipped_order_.push_back(name);
        SkippedKey& s = skipped_[name];
        if (s.count++ == 0) s.first_where = where;
        if (peek(false) == "{") {
            const std::string_view open = token(false);
            skip_block(in_.offset_of(open), "the block of " + quote_token(key));
        } else {
            skip_number_lines();
        }
    }

    // ---- values -----------------------------------------------------------------------
    // One vertex index (ASCII token or binary int32), not range-checked.
    int64_t read_index(const Label& what, size_t& at) {
        if (binary_) {
            at = in_.pos();
            return in_.read_binary<int32_t>(big_endian_, what);
        }
        const std::string_view t = token(false);
        at = in_.offset_of(t);
        return in_.to_int(t, what);
    }

    // A count and that many integers (ignored), after `key`.
    void skip_index_list(std::string_view key, const std::string& where) {
        const std::string_view count_token = peek(true);
        const int64_t n = count_on_line(key, 2, "values of " + quote_token(key) + " " + where, 4);
        if (binary_) begin_binary_data(count_token, "");
        const std::string what = "a value of " + quote_token(key) + " " + where;
        size_t at = 0;
        for (int64_t i = 0; i < n; ++i) (void)read_index(what, at);
    }

    // ---- sections ---------------------------------------------------------------------
    void read_header() {
        if (in_.size() == 0) in_.fail("the file is empty");
        const std::string_view line = in_.rest_of_line();
        std::vector<std::string_view> words;
        for (size_t i = 0; i < line.size();) {
            while (i < line.size() && is_space(line[i])) ++i;
            const size_t begin = i;
            while (i < line.size() && !is_space(line[i])) ++i;
            if (i > begin) words.push_back(line.substr(begin, i - begin));
        }
        // "#HyperSurface" or "# HyperSurface".
        if (!words.empty() && words[0].size() > 1 && words[0][0] == '#') {
            words.insert(words.begin() + 1, words[0].substr(1));
            words[0] = words[0].substr(0, 1);
        }
        const std::string expected = "'# HyperSurface 0.1 ASCII' or '# HyperSurface 0.1 BINARY'";
        if (words.size() >= 2 && words[0] == "#" && words[1] == "AmiraMesh") {
            in_.fail_line(0, "an AmiraMesh file, not a HyperSurface surface: save the surface as HyperSurface (.surf, " +
                                 expected + ")");
        }
        if (words.size() < 2 || words[0] != "#" || words[1] != "HyperSurface") {
            in_.fail_line(
                0, "not a HyperSurface file: the first line must be " + expected + ", found " + quote_token(line));
        }
        if (words.size() < 4) in_.fail_line(0, "the first line must be " + expected + ", found " + quote_token(line));
        if (words[2] != "0.1") {
            in_.fail_line(0, "HyperSurface version " + quote_token(words[2]) + " is not supported (only 0.1)");
        }
        if (words[3] == "ASCII") {
            binary_ = false;
        } else if (words[3] == "BINARY") {
            binary_ = true;
            big_endian_ = true;
        } else if (words[3] == "BINARY-LITTLE-ENDIAN") {
            binary_ = true;
            big_endian_ = false;
        } else {
            in_.fail_line(0, "unknown HyperSurface encoding " + quote_token(words[3]) +
                                 " (expected ASCII, BINARY or BINARY-LITTLE-ENDIAN)");
        }
        if (words.size() > 4)
            in_.fail_line(0, "unexpected " + quote_token(words[4]) + " after the encoding on the first line");
    }

    void read_vertices(std::string_view key) {
        if (have_vertices_) fail_at(in_.offset_of(key), "a second Vertices section");
        have_vertices_ = true;
        const std::string_view count_token = peek(true);
        const int64_t n = count_on_line(key, 6, "vertices", 12);  // "0 0 0\n" / 3 float32
        if (binary_) begin_binary_data(count_token, "vertices");
        vertices_.reserve(static_cast<size_t>(n));
        for (int64_t i = 0; i < n; ++i) {
            Vec3 p;
            if (binary_) {
                const size_t at = in_.pos();
                for (int k = 0; k < 3; ++k) {
                    p[k] = in_.read_binary<float>(big_endian_, Label("the coordinates of vertex ", i + 1));
                    if (!std::isfinite(p[k])) {
                        in_.fail_offset(at + 4 * static_cast<size_t>(k), "vertex " + std::to_string(i + 1) +
                                                                             ": coordinate " + "xyz"[k] + " is " +
                                                                             (std::isnan(p[k]) ? "NaN" : "infinite"));
                    }
                }
            } else {
                for (int k = 0; k < 3; ++k) p[k] = in_.to_double(token(false), Label("a coordinate of vertex ", i + 1));
            }
            vertices_.push_back(p);
        }
    }

    void read_triangles(std::string_view key, int64_t patch, SurfPatch& info) {
        const std::string where = "patch " + std::to_string(patch);
        if (info.triangles >= 0) fail_at(in_.offset_of(key), "a second 'Triangles' in " + where);
        const std::string_view count_token = peek(true);
        const int64_t m = count_on_line(key, 6, "triangles in " + where, 12);  // "1 2 3\n" / 3 int32
        if (static_cast<double>(triangles_.size()) + static_cast<double>(m) > std::numeric_limits<int32_t>::max())
            fail_at(in_.offset_of(count_token), "too many triangles for bpm (at most 2^31-1)");
        if (binary_) begin_binary_data(count_token, "triangles");
        info.triangles = m;
        const int64_t nv = static_cast<int64_t>(vertices_.size());
        const std::string of_patch = " of " + where;
        triangles_.reserve(triangles_.size() + static_cast<size_t>(m));
        for (int64_t t = 0; t < m; ++t) {
            Tri tri;
            for (int k = 0; k < 3; ++k) {
                size_t at = 0;
                const int64_t index = read_index(Label("a vertex index of triangle ", t, of_patch.c_str()), at);
                if (index < 1 || index > nv) {
                    fail_at(at, where + ", triangle " + std::to_string(t) + ": vertex index " + std::to_string(index) +
                                    " is out of range (the file has " + std::to_string(nv) +
                                    " vertices, numbered from 1)");
                }
                tri[k] = static_cast<int32_t>(index - 1);
            }
            triangles_.push_back(tri);
            patches_.push_back(static_cast<int32_t>(patch));
        }
    }

    // One `{ key value ... }` block of Patches (into `info`), BoundaryCurves or Surfaces.
    void read_block(Block kind, int64_t index, SurfPatch* info) {
        const char* kind_name = kind == Block::Patch           ? "patch "
                                : kind == Block::BoundaryCurve ? "boundary curve "
                                                               : "surface ";
        const std::string where = kind_name + std::to_string(index);
        const std::string_view open = token(false);
        if (open != "{") fail_expected(open, "'{' opening " + where);
        for (;;) {
            const std::string_view key = token(false);
            if (key.empty()) fail_at(in_.offset_of(open), "the '{' of " + where + " is never closed (truncated file?)");
            if (key == "}") break;
            if (key == "{" || looks_numeric(key)) {
                fail_expected(key, "a key or '}' in " + where,
                              looks_numeric(key) ? " (more values than a count announced?)" : "");
            }
            const bool patch = kind == Block::Patch;
            if ((patch && (same_key(key, "InnerRegion") || same_key(key, "OuterRegion"))) ||
                (kind == Block::Surface && same_key(key, "Region"))) {
                const std::string name = read_name(key);
                if (patch) (same_key(key, "InnerRegion") ? info->inner : info->outer) = name;
            } else if (patch && same_key(key, "BoundaryID")) {
                const std::string_view t = token(true);
                info->boundary_id = integer(t, "the boundary id after " + quote_token(key));
                info->has_boundary_id = true;
            } else if (patch && same_key(key, "Triangles")) {
                read_triangles(key, index, *info);
            } else if ((patch && (same_key(key, "BranchingPoints") || same_key(key, "BoundaryCurves"))) ||
                       (kind == Block::BoundaryCurve && same_key(key, "Vertices")) ||
                       (kind == Block::Surface && same_key(key, "Patches"))) {
                skip_index_list(key, "in " + where);
            } else {
                skip_unknown(key, "in " + where);
            }
        }
        if (info && info->triangles < 0) fail_at(in_.offset_of(open), where + " has no 'Triangles'");
    }

    // A region name: the rest of the line (names may hold blanks), up to a brace.
    std::string read_name(std::string_view key) {
        in_.skip_blanks();
        const size_t begin = in_.pos();
        std::string_view rest = in_.rest_of_line();
        const size_t brace = rest.find_first_of("{}");
        if (brace != std::string_view::npos) {
            rest = rest.substr(0, brace);
            in_.seek(begin + brace);
        }
        rest = trim(rest);
        if (rest.empty())
            fail_expected(std::string_view(in_.bytes().data() + begin, 0), "a name after " + quote_token(key));
        return std::string(rest);
    }

    ReaderOutput finish() {
        ReaderOutput out;
        Surface& s = out.surface;
        s.vertices = std::move(vertices_);
        s.triangles = std::move(triangles_);
        s.patches = std::move(patches_);
        // Amira orients a patch's triangles from its inner to its outer region.
        for (size_t p = 0; p < infos_.size(); ++p) {
            const SurfPatch& i = infos_[p];
            if (i.inner.empty() && i.outer.empty()) continue;
            out.patch_info.push_back(
                bpm::PatchInfo{static_cast<int32_t>(p), i.inner + "|" + i.outer, i.outer, i.inner, true});
        }
        const size_t shown = infos_.size() <= 24 ? infos_.size() : 20;
        for (size_t p = 0; p < shown; ++p) {
            const SurfPatch& i = infos_[p];
            std::string regions;
            if (!i.inner.empty()) regions += "InnerRegion " + i.inner;
            if (!i.outer.empty()) regions += (regions.empty() ? "" : " / ") + ("OuterRegion " + i.outer);
            if (regions.empty()) regions = "no region names";
            if (i.has_boundary_id && i.boundary_id != 0) regions += ", BoundaryID " + std::to_string(i.boundary_id);
            out.notes.push_back("patch " + std::to_string(p) + " = " + regions + " (" + std::to_string(i.triangles) +
                                " triangle" + (i.triangles == 1 ? "" : "s") + ")");
        }
        if (shown < infos_.size()) {
            int64_t rest = 0;
            for (size_t p = shown; p < infos_.size(); ++p) rest += infos_[p].triangles;
            out.notes.push_back("patches " + std::to_string(shown) + " to " + std::to_string(infos_.size() - 1) +
                                " = " + std::to_string(infos_.size() - shown) + " more HyperSurface patches (" +
                                std::to_string(rest) + " triangles)");
        }
        for (const std::string& key : skipped_order_) {
            const SkippedKey& k = skipped_.at(key);
            out.notes.push_back("skipped the unknown HyperSurface key " + quote_token(key) + " " + k.first_where +
                                (k.count > 1 ? " (and " + std::to_string(k.count - 1) + " more times)" : ""));
        }
        return out;
    }

    struct SkippedKey {
        int64_t count = 0;
        std::string first_where;
    };

    InputCursor in_;
    bool binary_ = false;
    bool big_endian_ = true;
    bool have_vertices_ = false;
    bool have_patches_ = false;
    std::vector<Vec3> vertices_;
    std::vector<Tri> triangles_;
    std::vector<int32_t> patches_;
    std::vector<SurfPatch> infos_;
    std::map<std::string, SkippedKey> skipped_;
    std::vector<std::string> skipped_order_;
};

}  // namespace

ReaderOutput read_surf(std::string_view bytes, const std::string& name) { return SurfReader(bytes, name).read(); }

}  // namespace bpm::detail
