// OFF reader (Geomview Object File Format, ASCII).
//
// Accepted: the "OFF" keyword with the optional prefixes ST, C, N (texture coordinates,
// colours and normals follow the three coordinates of a vertex and are ignored); the
// counts on the keyword line or on the next non-comment line; '#' comments anywhere;
// colours after the indices of a face. Refused: 4OFF / nOFF (not 3-D), "OFF BINARY",
// faces with fewer than three corners, faces with more (polygons are not triangulated
// silently: only with accept_polygons, the triangulate-polygons repair), content after
// the announced faces (a sign of wrong counts).
//
// One vertex and one face per line, as every OFF writer does; this is what lets a
// wrong count surface as an error on the line where it happens.
#include <string>

#include "surface_readers.h"

namespace bpm::detail {

ReaderOutput read_off(std::string_view bytes, const std::string& name, bool accept_polygons) {
    InputCursor in(bytes, name, '#');
    ReaderOutput out;
    Surface& s = out.surface;

    // Skip a UTF-8 byte order mark; some Windows tools write one.
    if (bytes.substr(0, 3) == "\xEF\xBB\xBF") in.seek(3);
    const std::string_view keyword = in.next_token();
    if (keyword.empty()) in.fail("the file is empty (or holds only comments)");
    {
        std::string_view k = keyword;
        if (k.size() < 3 || k.substr(k.size() - 3) != "OFF") in.fail_token(keyword, "the keyword 'OFF' at the start of the file");
        if (k.size() >= 2 && k.substr(0, 2) == "ST") k.remove_prefix(2);
        if (!k.empty() && k[0] == 'C') k.remove_prefix(1);
        if (!k.empty() && k[0] == 'N') k.remove_prefix(1);
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

    s.vertices.reserve(static_cast<size_t>(nv));
    for (int64_t i = 0; i < nv; ++i) {
        in.skip_space();
        if (in.at_end()) {
            in.fail_line(in.pos(), "the file ends after " + std::to_string(i) + " of the " + std::to_string(nv) +
                                       " announced vertices");
        }
        Vec3 p;
        for (int k = 0; k < 3; ++k) p[k] = in.line_double(Label("coordinate of vertex ", i));
        in.skip_line();  // colour, normal or texture coordinates
        s.vertices.push_back(p);
    }

    s.triangles.reserve(static_cast<size_t>(nf));
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
