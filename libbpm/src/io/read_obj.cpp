// OBJ reader (Wavefront, ASCII).
//
// Read: `v x y z [w | r g b]` (extra values ignored), `f` with corners written `v`,
// `v/vt`, `v/vt/vn` or `v//vn`, 1-based or negative (relative to the last vertex read)
// indices, `g` and `usemtl`, and '\' line continuations. Ignored: vt, vn, vp, o, s,
// mtllib, and any other statement (counted in a note). Refused: faces with fewer than
// three corners, faces with more (polygons are not triangulated silently: only with
// accept_polygons, the triangulate-polygons repair), index 0, indices outside the
// vertex list.
//
// Patch ids. Each face belongs to the pair (current `g` names, current `usemtl` name);
// the distinct pairs get patch ids 0, 1, 2, ... in the order in which faces first use
// them. One exception, so that bpm's own OBJ output reads back unchanged: when there is
// no `usemtl` and every face is under a group named `patch_<integer>`, that integer is
// the patch id.
//
// Materials. A group named by the convention of Gmsh's physical names, `A|B`, `pair_A_B`
// or `interface_A_B` (materials_from_patch_name), separates materials A and B, in no known order:
// then every patch gets a PatchInfo with its group's name, and the materials where the
// name gives them. Only then: a file whose groups are just names ("Cube", "inlet") says
// nothing about materials and still encloses the file's own (apply_file_material); the
// names are kept as the patches' names (ReaderOutput::patch_names).
#include <algorithm>
#include <map>
#include <string>
#include <utility>

#include "io/surface_readers.h"

namespace bpm::detail {

namespace {

// "patch_12" -> 12; false for any other name.
bool parse_patch_name(const std::string& name, int32_t& id) {
    const std::string prefix = "patch_";
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return false;
    const char* begin = name.data() + prefix.size();
    const char* end = name.data() + name.size();
    const auto [ptr, ec] = std::from_chars(begin, end, id);
    return ec == std::errc() && ptr == end;
}

}  // namespace

ReaderOutput read_obj(std::string_view bytes, const std::string& name, bool accept_polygons) {
    InputCursor in(bytes, name, '#');
    ReaderOutput out;
    Surface& s = out.surface;

    if (bytes.substr(0, 3) == "\xEF\xBB\xBF") in.seek(3);
    // Faces may name vertices defined further down, so indices are resolved at the end;
    // the offset of each face is kept for the error message.
    std::vector<std::array<int64_t, 3>> raw_faces;
    std::vector<size_t> face_offsets;
    std::vector<int32_t> face_keys;
    std::vector<std::vector<int64_t>> raw_polygons;  // corners of out.polygons, resolved at the end
    std::vector<int64_t> face_corners;
    std::map<std::pair<std::string, std::string>, int32_t> key_ids;  // (group, material) -> key
    std::vector<std::pair<std::string, std::string>> keys;
    std::string group, material;
    bool saw_material = false;
    std::map<std::string, int64_t> ignored;
    int32_t current_key = -1;

    // Next token of the statement, following '\' continuations onto the next line.
    auto statement_token = [&]() {
        for (;;) {
            std::string_view t = in.token_on_line();
            if (t == "\\" && in.at_line_end()) {
                in.skip_line();
                continue;
            }
            return t;
        }
    };
    auto rest_of_statement = [&]() {
        std::string text;
        for (std::string_view t = statement_token(); !t.empty(); t = statement_token()) {
            if (!text.empty()) text += ' ';
            text += t;
        }
        return text;
    };

    for (;;) {
        in.skip_space();
        if (in.at_end()) break;
        const std::string_view keyword = in.token_on_line();
        if (keyword == "v") {
            Vec3 p;
            for (int k = 0; k < 3; ++k) p[k] = in.to_double(statement_token(), "a vertex coordinate");
            // w or a colour may follow; they must still be numbers.
            for (std::string_view t = statement_token(); !t.empty(); t = statement_token()) (void)in.to_double(t, "a number");
            if (s.vertices.size() >= static_cast<size_t>(std::numeric_limits<int32_t>::max())) {
                in.fail_line(in.offset_of(keyword), "too many vertices for bpm (at most 2^31-1)");
            }
            s.vertices.push_back(p);
        } else if (keyword == "f") {
            const size_t at = in.offset_of(keyword);
            face_corners.clear();
            int64_t count = 0;
            for (std::string_view t = statement_token(); !t.empty(); t = statement_token()) {
                if (count == 3 && !accept_polygons) {
                    int total = 4;
                    while (!statement_token().empty()) ++total;
                    in.fail_line(at, "a face with " + std::to_string(total) +
                                         " corners; only triangles are accepted (the triangulate-polygons repair "
                                         "splits polygons into triangles)");
                }
                // Only the vertex index matters; texture and normal indices must still be integers.
                const size_t slash = t.find('/');
                const std::string_view v = t.substr(0, slash);
                const int64_t index = in.to_int(v.empty() ? t : v, "a vertex index");
                if (slash != std::string_view::npos) {
                    std::string_view rest = t.substr(slash + 1);
                    for (int part = 0; part < 2 && !rest.empty(); ++part) {
                        const size_t next = rest.find('/');
                        const std::string_view field = rest.substr(0, next);
                        if (!field.empty()) (void)in.to_int(field, "a texture or normal index");
                        if (next == std::string_view::npos) {
                            rest = {};
                        } else {
                            rest = rest.substr(next + 1);
                            if (part == 1 || rest.empty()) in.fail_token(t, "a face corner v, v/vt, v/vt/vn or v//vn");
                        }
                    }
                }
                if (index == 0) in.fail_line(in.offset_of(t), "vertex index 0 (OBJ indices start at 1)");
                int64_t resolved = index;
                if (index < 0) {
                    // Relative: -1 is the last vertex read so far.
                    resolved = static_cast<int64_t>(s.vertices.size()) + index + 1;
                    if (resolved < 1) {
                        in.fail_line(in.offset_of(t), "relative vertex index " + std::to_string(index) +
                                                          " points before the first vertex (only " +
                                                          std::to_string(s.vertices.size()) + " read so far)");
                    }
                }
                face_corners.push_back(resolved - 1);
                ++count;
            }
            if (count < 3) in.fail_line(at, "a face with " + std::to_string(count) + " corners; a triangle needs 3");
            if (current_key < 0) {
                const auto key = std::make_pair(group, material);
                auto it = key_ids.find(key);
                if (it == key_ids.end()) {
                    it = key_ids.emplace(key, static_cast<int32_t>(keys.size())).first;
                    keys.push_back(key);
                }
                current_key = it->second;
            }
            if (raw_faces.size() >= static_cast<size_t>(std::numeric_limits<int32_t>::max())) {
                in.fail_line(at, "too many faces for bpm (at most 2^31-1)");
            }
            if (count > 3) {
                PolygonFace polygon;
                polygon.position = raw_faces.size();
                polygon.face = static_cast<int64_t>(raw_faces.size() + out.polygons.size());
                polygon.offset = at;
                polygon.patch = current_key;  // a key until the patch ids are known
                out.polygons.push_back(std::move(polygon));
                raw_polygons.push_back(face_corners);
            } else {
                raw_faces.push_back({face_corners[0], face_corners[1], face_corners[2]});
                face_offsets.push_back(at);
                face_keys.push_back(current_key);
            }
        } else if (keyword == "g") {
            group = rest_of_statement();
            if (group == "default") group.clear();
            current_key = -1;
        } else if (keyword == "usemtl") {
            material = rest_of_statement();
            saw_material = true;
            current_key = -1;
        } else if (keyword == "vt" || keyword == "vn" || keyword == "vp" || keyword == "o" || keyword == "s" ||
                   keyword == "mtllib") {
            (void)rest_of_statement();
        } else {
            // Points, lines, free-form geometry, or something that is not OBJ at all:
            // refuse what cannot be a statement name, remember the rest for a note.
            for (char c : keyword) {
                const unsigned char u = static_cast<unsigned char>(c);
                if (u < 0x21 || u > 0x7e) in.fail_line(in.offset_of(keyword), "not an OBJ statement: " + quote_token(keyword));
            }
            ++ignored[std::string(keyword)];
            (void)rest_of_statement();
        }
        in.skip_line();
    }

    if (s.vertices.empty() && raw_faces.empty() && raw_polygons.empty()) {
        if (ignored.empty()) in.fail("the file is empty (no vertices and no faces)");
        in.fail("no 'v' or 'f' statements found: this does not look like an OBJ file");
    }

    const int64_t nv = static_cast<int64_t>(s.vertices.size());
    s.triangles.reserve(raw_faces.size());
    for (size_t f = 0; f < raw_faces.size(); ++f) {
        Tri t;
        for (int k = 0; k < 3; ++k) {
            const int64_t index = raw_faces[f][k];
            if (index < 0 || index >= nv) {
                in.fail_line(face_offsets[f], "face " + std::to_string(f) + ": vertex index " +
                                                  std::to_string(index + 1) + " is out of range (the file has " +
                                                  std::to_string(nv) + " vertices)");
            }
            t[k] = static_cast<int32_t>(index);
        }
        s.triangles.push_back(t);
    }

    // Patch ids: bpm's own `patch_N` names, or order of first use.
    std::vector<int32_t> key_patch(keys.size());
    bool own_names = !saw_material && !keys.empty();
    for (size_t k = 0; k < keys.size() && own_names; ++k) own_names = parse_patch_name(keys[k].first, key_patch[k]);
    if (!own_names) {
        for (size_t k = 0; k < keys.size(); ++k) key_patch[k] = static_cast<int32_t>(k);
    }
    s.patches.reserve(face_keys.size());
    for (int32_t key : face_keys) s.patches.push_back(key_patch[static_cast<size_t>(key)]);
    bool names_materials = false;
    for (const auto& key : keys) names_materials = names_materials || materials_from_patch_name(key.first);
    if (names_materials) {
        for (size_t k = 0; k < keys.size(); ++k) {
            PatchInfo info{key_patch[k], keys[k].first, {}, {}, true};
            if (const auto pair = materials_from_patch_name(keys[k].first)) {
                info.front = pair->first;
                info.back = pair->second;
                info.oriented = false;  // a name does not say which side is which
            }
            out.patch_info.push_back(std::move(info));
        }
        std::sort(out.patch_info.begin(), out.patch_info.end(),
                  [](const PatchInfo& a, const PatchInfo& b) { return a.patch < b.patch; });
    } else if (!own_names) {
        // Names alone ("inlet", "wall"): kept as the patches' names, so that they reach
        // /patch_info and the physical names of MSH outputs; the group name, else the
        // usemtl name, else both.
        for (size_t k = 0; k < keys.size(); ++k) {
            const auto& [g, m] = keys[k];
            std::string patch_name = g.empty() ? m : m.empty() ? g : g + " (" + m + ")";
            if (!patch_name.empty()) out.patch_names.push_back({key_patch[k], std::move(patch_name)});
        }
    }
    for (size_t i = 0; i < out.polygons.size(); ++i) {
        PolygonFace& polygon = out.polygons[i];
        polygon.patch = key_patch[static_cast<size_t>(polygon.patch)];
        for (const int64_t index : raw_polygons[i]) {
            if (index < 0 || index >= nv) {
                in.fail_line(polygon.offset, "face " + std::to_string(polygon.face) + ": vertex index " +
                                                 std::to_string(index + 1) + " is out of range (the file has " +
                                                 std::to_string(nv) + " vertices)");
            }
            polygon.corners.push_back(static_cast<int32_t>(index));
        }
    }
    insert_polygons(in, false, out);

    for (const auto& [keyword, count] : ignored) {
        out.notes.push_back("ignored " + std::to_string(count) + " OBJ '" + keyword + "' statement" +
                            (count == 1 ? "" : "s"));
    }
    return out;
}

}  // namespace bpm::detail
