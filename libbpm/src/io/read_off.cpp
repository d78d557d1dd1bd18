// OFF reader (Geomview Object File Format, ASCII).
//
// Accepted: the "OFF" keyword with the optional prefixes ST, C, N (normals, colours and
// texture coordinates follow the three coordinates of a vertex, in that order, and become
// the vertex data arrays "normals", "colors" (3 or 4 values) and "texture_coordinates";
// vertex lines that do not fit that layout leave the data out, with a note); the
// counts on the keyword line or on the next non-comment line; '#' comments anywhere;
// colours after the indices of a face. Refused: 4OFF / nOFF (not 3-D), "OFF BINARY",
// faces with fewer than three corners, faces with more (polygons are not triangulated
// silently: only with accept_polygons, the triangulate-polygons repair), content after
// the announced faces (a sign of wrong counts).
//
// One vertex and one face per line, as every OFF writer does; this is what lets a
// wrong count surface as an error on the line where it happens.
#include <charconv>
#include <cmath>
#include <string>
#include <vector>

#include "core/huge_pages.h"
#include "io/surface_readers.h"

namespace bpm::detail {

ReaderOutput read_off(std::string_view bytes, const std::string& name, bool accept_polygons) {
    InputCursor in(bytes, name, '#');
    ReaderOutput out;
    Surface& s = out.surface;

    // Skip a UTF-8 byte order mark; some Windows tools write one.
    if (bytes.substr(0, 3) == "\xEF\xBB\xBF") in.seek(3);
    const std::string_view keyword = in.next_token();
    if (keyword.empty()) in.fail("the file is empty (or holds only comments)");
    bool has_st = false, has_c = false, has_n = false;
    {
        std::string_view k = keyword;
        if (k.size() < 3 || k.substr(k.size() - 3) != "OFF") in.fail_token(keyword, "the keyword 'OFF' at the start of the file");
        if (k.size() >= 2 && k.substr(0, 2) == "ST") k.remove_prefix(2), has_st = true;
        if (!k.empty() && k[0] == 'C') k.remove_prefix(1), has_c = true;
        if (!k.empty() && k[0] == 'N') k.remove_prefix(1), has_n = true;
        if (!k.empty() && (k[0] == '4' || k[0] == 'n')) {
            in.fail_line(in.offset_of(keyword), quote_token(keyword) + ": only 3-D OFF files are supported");
        }
        if (k != "OFF") in.fail_token(keyword, "the keyword 'OFF' at the start of the file");
    }
    {
        const std::string_view next = in.token_on_line();
        if (next == "BINARY") in.fail_line(in.offset_of(next), "binary OFF is not supported; use ASCII OFF");
        in.seek(in.offset_of(next));  // the counts may follow on the same line
    }

    const size_t counts_at = (in.skip_space(), in.pos());
    const int64_t nv = in.line_int("the number of vertices");
    const int64_t nf = in.line_int("the number of faces");
    // The edge count is optional and unused.
    if (!in.at_line_end()) (void)in.line_int("the number of edges");
    in.expect_line_end("after the vertex, face and edge counts");
    // Smallest possible records: "0 0 0\n" and "3 0 1 2\n".
    check_count(in, counts_at, false, nv, 6, "vertices");
    check_count(in, counts_at, false, nf, 8, "faces");
    if (static_cast<double>(nv) * 6 + static_cast<double>(nf) * 8 > static_cast<double>(in.remaining()) + 1) {
        in.fail_line(counts_at, std::to_string(nv) + " vertices and " + std::to_string(nf) +
                                    " faces announced, but the rest of the file is only " +
                                    std::to_string(in.remaining()) + " bytes (truncated, or wrong counts?)");
    }

    reserve_huge_pages(s.vertices, static_cast<size_t>(nv));
    // Vertex data after the coordinates: normals (3), colour (3 or 4), texture (2).
    const bool with_data = has_n || has_c || has_st;
    std::vector<double> normals, colors, texture;
    int color_components = -1;  // from the first vertex
    std::string data_problem;   // why the data is left out, if it is
    std::vector<double> values_after;
    auto read_extra = [&](int64_t i) {
        std::vector<double>& extra = values_after;
        extra.clear();
        for (std::string_view t = in.token_on_line(); !t.empty(); t = in.token_on_line()) {
            double value = 0;
            std::string_view u = t.size() > 1 && t[0] == '+' ? t.substr(1) : t;
            const auto [end, ec] = std::from_chars(u.data(), u.data() + u.size(), value);
            if (ec != std::errc() || end != u.data() + u.size() || !std::isfinite(value)) {
                if (data_problem.empty())
                    data_problem = "vertex " + std::to_string(i) + " has " + quote_token(t) + " where a number belongs";
                return;
            }
            extra.push_back(value);
        }
        const int rest = static_cast<int>(extra.size()) - (has_n ? 3 : 0) - (has_st ? 2 : 0);
        const int c = has_c ? rest : 0;
        if (color_components < 0) color_components = c;
        if (rest < 0 || (has_c && c != 3 && c != 4) || (!has_c && rest != 0) || c != color_components) {
            if (data_problem.empty())
                data_problem = "vertex " + std::to_string(i) + " has " + std::to_string(extra.size()) +
                               " values after its coordinates, which does not fit the keyword's layout";
            return;
        }
        size_t at = 0;
        if (has_n) normals.insert(normals.end(), extra.begin(), extra.begin() + 3), at = 3;
        if (has_c) colors.insert(colors.end(), extra.begin() + long(at), extra.begin() + long(at) + c), at += size_t(c);
        if (has_st) texture.insert(texture.end(), extra.begin() + long(at), extra.begin() + long(at) + 2);
    };
    for (int64_t i = 0; i < nv; ++i) {
        in.skip_space();
        if (in.at_end()) {
            in.fail_line(in.pos(), "the file ends after " + std::to_string(i) + " of the " + std::to_string(nv) +
                                       " announced vertices");
        }
        Vec3 p;
        for (int k = 0; k < 3; ++k) p[k] = in.line_double(Label("coordinate of vertex ", i));
        if (with_data && data_problem.empty()) read_extra(i);
        in.skip_line();
        s.vertices.push_back(p);
    }
    if (with_data && data_problem.empty()) {
        if (has_n) s.vertex_data.push_back({"normals", 3, std::move(normals)});
        if (has_c && color_components > 0) s.vertex_data.push_back({"colors", color_components, std::move(colors)});
        if (has_st) s.vertex_data.push_back({"texture_coordinates", 2, std::move(texture)});
    } else if (with_data) {
        out.notes.push_back("vertex data of the " + std::string(keyword) + " file left out: " + data_problem);
    }

    reserve_huge_pages(s.triangles, static_cast<size_t>(nf));
    for (int64_t f = 0; f < nf; ++f) {
        in.skip_space();
        if (in.at_end()) {
            in.fail_line(in.pos(), "the file ends after " + std::to_string(f) + " of the " + std::to_string(nf) +
                                       " announced faces");
        }
        const std::string_view count_token = in.token_on_line();
        const int64_t corners = in.to_int(count_token, Label("the corner count of face ", f));
        const bool polygon = corners > 3 && accept_polygons;
        if (corners != 3 && !polygon) {
            in.fail_line(in.offset_of(count_token),
                         "face " + std::to_string(f) + " has " + std::to_string(corners) +
                             " corners; only triangles are accepted" +
                             (corners > 3 ? " (the triangulate-polygons repair splits polygons into triangles)" : ""));
        }
        // At least two bytes per corner: a polygon cannot announce more corners than that.
        if (polygon && static_cast<double>(corners) * 2 > static_cast<double>(in.remaining()) + 1) {
            in.fail_line(in.offset_of(count_token), "face " + std::to_string(f) + " announces " +
                                                        std::to_string(corners) + " corners, more than the rest of the file holds");
        }
        PolygonFace face;
        Tri t;
        for (int64_t k = 0; k < corners; ++k) {
            const std::string_view token = in.token_on_line();
            const int64_t index = in.to_int(token, Label("a vertex index of face ", f));
            if (index < 0 || index >= nv) {
                in.fail_line(in.offset_of(token), "face " + std::to_string(f) + ": vertex index " +
                                                      std::to_string(index) + " is out of range (the file has " +
                                                      std::to_string(nv) + " vertices)");
            }
            if (polygon) face.corners.push_back(static_cast<int32_t>(index));
            else t[k] = static_cast<int32_t>(index);
        }
        in.skip_line();  // an optional colour
        if (polygon) {
            face.position = s.triangles.size();
            face.face = f;
            face.offset = in.offset_of(count_token);
            out.polygons.push_back(std::move(face));
        } else {
            s.triangles.push_back(t);
        }
    }
    const std::string_view extra = in.next_token();
    if (!extra.empty()) {
        in.fail_line(in.offset_of(extra), "unexpected " + quote_token(extra) + " after the last of the " +
                                              std::to_string(nf) + " announced faces (wrong counts in the header?)");
    }
    s.patches.assign(s.triangles.size(), 0);
    insert_polygons(in, false, out);
    return out;
}

}  // namespace bpm::detail
