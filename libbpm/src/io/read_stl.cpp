// STL reader, ASCII and binary.
//
// STL stores every triangle with its own three corner positions; vertices are shared by
// merging exactly equal positions (-0 and +0 are equal), numbered in order of first
// appearance. Facet normals (which may be NaN for degenerate facets) and the binary
// attribute word are ignored.
//
// Binary or ASCII: a binary file is 84 + 50 * n bytes for the n in bytes 80..83, and
// many binary files start with "solid" too; so a file whose size matches is binary
// unless it is plain ASCII text that reads like an ASCII STL.
//
// ASCII files may hold several `solid ... endsolid` blocks; each block is one patch
// (0, 1, ... in file order). Binary files give patch 0.
#include <string>
#include <unordered_map>

#include "io/surface_readers.h"

namespace bpm::detail {

namespace {

struct PositionHash {
    size_t operator()(const Vec3& p) const {
        size_t h = 1469598103934665603ull;
        for (double x : p) {
            uint64_t bits;
            std::memcpy(&bits, &x, sizeof bits);
            h = (h ^ bits) * 1099511628211ull;
            h ^= h >> 29;
        }
        return h;
    }
};

// Shares corners at identical positions.
class VertexMerger {
public:
    explicit VertexMerger(Surface& s) : s_(s) {}
    int32_t add(Vec3 p) {
        for (double& x : p) x += 0.0;  // -0 -> +0, so both land in one bucket
        const auto [it, inserted] = index_.emplace(p, static_cast<int32_t>(s_.vertices.size()));
        if (inserted) s_.vertices.push_back(p);
        return it->second;
    }
    void reserve(size_t n) { index_.reserve(n); }

private:
    Surface& s_;
    std::unordered_map<Vec3, int32_t, PositionHash> index_;
};

bool starts_with_solid(std::string_view bytes) {
    size_t i = 0;
    while (i < bytes.size() && is_space(bytes[i])) ++i;
    return bytes.substr(i, 5) == "solid";
}

bool is_text(std::string_view bytes) {
    for (char c : bytes) {
        const unsigned char u = static_cast<unsigned char>(c);
        if (u >= 0x7f || (u < 0x20 && !is_space(c))) return false;
    }
    return true;
}

bool looks_like_ascii_stl(std::string_view bytes) {
    return is_text(bytes) && (bytes.find("facet") != std::string_view::npos || bytes.find("endsolid") != std::string_view::npos);
}

ReaderOutput read_binary_stl(std::string_view bytes, const std::string& name) {
    InputCursor in(bytes, name);
    ReaderOutput out;
    Surface& s = out.surface;
    in.seek(80);
    const uint32_t n = in.read_binary<uint32_t>(false, "the triangle count");
    if (n > static_cast<uint32_t>(std::numeric_limits<int32_t>::max())) {
        in.fail_offset(80, std::to_string(n) + " triangles announced; bpm supports at most 2^31-1");
    }
    VertexMerger merger(s);
    merger.reserve(n / 2 + 1);
    s.triangles.reserve(n);
    for (uint32_t f = 0; f < n; ++f) {
        const size_t record = in.pos();
        in.seek(record + 12);  // normal
        Tri t;
        for (int k = 0; k < 3; ++k) {
            Vec3 p;
            for (int c = 0; c < 3; ++c) {
                const size_t at = in.pos();
                const float x = in.read_binary<float>(false, Label("triangle ", f));
                if (!std::isfinite(x)) {
                    in.fail_offset(at, "triangle " + std::to_string(f) + ": coordinate is " +
                                           (std::isnan(x) ? "NaN" : "infinite"));
                }
                p[c] = static_cast<double>(x);
            }
            t[k] = merger.add(p);
        }
        in.seek(record + 50);  // attribute byte count
        s.triangles.push_back(t);
    }
    s.patches.assign(s.triangles.size(), 0);
    return out;
}

ReaderOutput read_ascii_stl(std::string_view bytes, const std::string& name) {
    InputCursor in(bytes, name);
    ReaderOutput out;
    Surface& s = out.surface;
    VertexMerger merger(s);
    auto expect = [&](std::string_view word) {
        const std::string_view t = in.next_token();
        if (t != word) in.fail_token(t, "'" + std::string(word) + "'");
    };

    int32_t solid = -1;
    for (;;) {
        const std::string_view t = in.next_token();
        if (t.empty()) break;
        if (t != "solid") in.fail_token(t, solid < 0 ? "'solid' at the start of the file" : "'solid' or the end of the file");
        ++solid;
        in.skip_line();  // the name may contain anything
        for (;;) {
            const std::string_view keyword = in.next_token();
            if (keyword == "endsolid") {
                in.skip_line();
                break;
            }
            if (keyword != "facet") in.fail_token(keyword, "'facet' or 'endsolid'");
            const size_t facet_at = in.offset_of(keyword);
            expect("normal");
            for (int c = 0; c < 3; ++c) in.check_number(in.next_token(), "a normal component");
            expect("outer");
            expect("loop");
            Tri t;
            for (int k = 0; k < 3; ++k) {
                expect("vertex");
                Vec3 p;
                for (int c = 0; c < 3; ++c) p[c] = in.any_double("a vertex coordinate");
                t[k] = merger.add(p);
            }
            const std::string_view end_loop = in.next_token();
            if (end_loop == "vertex") {
                in.fail_line(in.offset_of(end_loop),
                             "a facet with more than 3 vertices; only triangles are accepted");
            }
            if (end_loop != "endloop") in.fail_token(end_loop, "'endloop'");
            expect("endfacet");
            if (s.triangles.size() >= static_cast<size_t>(std::numeric_limits<int32_t>::max())) {
                in.fail_line(facet_at, "too many facets for bpm (at most 2^31-1)");
            }
            s.triangles.push_back(t);
            s.patches.push_back(solid);
        }
    }
    if (solid < 0) in.fail("the file is empty");
    return out;
}

}  // namespace

ReaderOutput read_stl(std::string_view bytes, const std::string& name) {
    if (bytes.empty()) throw InputError(name, "the file is empty");
    const bool solid = starts_with_solid(bytes);
    if (bytes.size() >= 84) {
        uint32_t n;
        std::memcpy(&n, bytes.data() + 80, 4);
        if (InputCursor::host_is_big_endian()) n = __builtin_bswap32(n);
        const uint64_t expected = 84 + 50 * static_cast<uint64_t>(n);
        if (expected == bytes.size() && !(solid && looks_like_ascii_stl(bytes))) return read_binary_stl(bytes, name);
        if (!solid) {
            throw InputError(name, "byte offset 80: binary STL announces " + std::to_string(n) + " triangles, which needs " +
                                       std::to_string(expected) + " bytes, but the file has " +
                                       std::to_string(bytes.size()) +
                                       " (truncated or not an STL file; an ASCII STL starts with 'solid')");
        }
        if (!is_text(bytes)) {
            throw InputError(name, "starts with 'solid' like an ASCII STL but holds binary data, and its size (" +
                                       std::to_string(bytes.size()) + " bytes) does not match the " +
                                       std::to_string(n) + " triangles announced at byte offset 80 (" +
                                       std::to_string(expected) + " bytes): a truncated or damaged binary STL?");
        }
    } else if (!solid) {
        throw InputError(name, "only " + std::to_string(bytes.size()) +
                                   " bytes: too short for a binary STL (84 bytes at least), and not an ASCII STL "
                                   "(which starts with 'solid')");
    }
    return read_ascii_stl(bytes, name);
}

}  // namespace bpm::detail
