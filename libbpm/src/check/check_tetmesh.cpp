// check_tetmesh: what the .bpm reader does not verify about /tetmesh (spec/tetmesh.md §5
// leaves orientation, conformity and "the faces lie on S" to a checker). The reader has
// already checked sizes and index ranges (find_tetmesh_inconsistency); this checks the
// mesh as a mesh, with exact predicates wherever the answer is yes or no.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "bpm/check.h"
#include "bpm/predicates.h"
#include "bpm/tetmesh.h"
#include "check/check_internal.h"
#include "core/number_text.h"
#include "core/tetrahedron_quality.h"

namespace bpm {

namespace {

constexpr double kPi = 3.14159265358979323846;

// One face of one tetrahedron: its corners sorted, and whether the tetrahedron's outward
// orientation of the face is an even permutation of the sorted order. In a conforming,
// positively oriented mesh, two tetrahedra that share a face see it with opposite parity
// (they lie on opposite sides of it).
struct TetFace {
    int32_t v[3];
    int32_t tet;
    bool even;
};

// (a, b, c) sorted; `even` = the sorting permutation is even.
void sort3(int32_t a, int32_t b, int32_t c, int32_t out[3], bool& even) {
    out[0] = a, out[1] = b, out[2] = c;
    even = true;
    if (out[0] > out[1]) std::swap(out[0], out[1]), even = !even;
    if (out[1] > out[2]) std::swap(out[1], out[2]), even = !even;
    if (out[0] > out[1]) std::swap(out[0], out[1]), even = !even;
}

bool same_corners(const int32_t a[3], const int32_t b[3]) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }
bool corners_less(const int32_t a[3], const int32_t b[3]) {
    return std::lexicographical_compare(a, a + 3, b, b + 3);
}

// The barycentric coordinates, in coarse triangle `t`, of a parameter point given in
// any coarse triangle (a point on a shared edge or vertex may be given in a neighbour).
// False if the point is not in the closed triangle t.
bool barycentric_in(const Surface& coarse, int32_t t, const SurfacePoint& p, Vec3& out) {
    if (p.triangle == t) {
        out = p.barycentric;
        return true;
    }
    out = {0, 0, 0};
    const Tri& from = coarse.triangles[p.triangle];
    const Tri& to = coarse.triangles[t];
    for (int i = 0; i < 3; ++i) {
        if (p.barycentric[i] == 0) continue;
        int j = 0;
        while (j < 3 && to[j] != from[i]) ++j;
        if (j == 3) return false;
        out[j] = p.barycentric[i];
    }
    return true;
}

std::string vertex_words(int32_t a, int32_t b, int32_t c) {
    return "(" + std::to_string(a) + ", " + std::to_string(b) + ", " + std::to_string(c) + ")";
}

}  // namespace

CheckResult check_tetmesh(const BpmFile& file, const CheckOptions& options, const Context& context) {
    CheckResult r;
    r.name = "tetmesh";
    if (!file.tetmesh) {
        detail::refuse(r, "the file has no tetrahedral mesh (/tetmesh)");
        return r;
    }
    const TetMesh& m = *file.tetmesh;
    const Surface& coarse = file.param.coarse;
    if (auto why = detail::surface_unsafe(coarse)) {
        detail::refuse(r, "the coarse surface: " + *why);
        return r;
    }
    if (auto problem = find_tetmesh_inconsistency(m, coarse); !problem.empty()) {
        detail::refuse(r, problem);
        return r;
    }
    const int32_t nv = m.num_vertices(), nt = m.num_tetrahedra();
    const int64_t nf = static_cast<int64_t>(m.faces.size());
    r.add_count("vertices", nv);
    r.add_count("tetrahedra", nt);
    r.add_count("faces", nf);
    r.add_count("level", m.level);
    auto problem = [&](std::vector<std::pair<std::string, int64_t>> ids, std::string message) {
        r.add_problem({std::move(ids), std::move(message)}, options.max_problems);
    };

    // 1. Orientation (exact) and shape.
    context.report(0.0, "checking tetrahedra");
    int64_t inverted = 0;
    double min_dihedral = 180;
    int32_t min_dihedral_tet = -1;
    for (int32_t t = 0; t < nt; ++t) {
        const Tet& x = m.tetrahedra[t];
        const Vec3 p[4] = {m.vertices[x[0]], m.vertices[x[1]], m.vertices[x[2]], m.vertices[x[3]]};
        const int sign = orient3d(p[0], p[1], p[2], p[3]);
        if (sign != 1) {
            ++inverted;
            problem({{"tetrahedron", t}}, sign == 0 ? "is flat (its four corners are coplanar)"
                                                    : "is inverted (negatively oriented)");
        }
        double angles[6];
        detail::dihedral_angles(p[0], p[1], p[2], p[3], angles);
        for (double a : angles) {
            const double degrees = std::abs(a) * 180 / kPi;
            if (min_dihedral_tet < 0 || degrees < min_dihedral) min_dihedral = degrees, min_dihedral_tet = t;
        }
    }
    r.add_count("inverted", inverted);

    // 2. Conformity: every face of a tetrahedron is shared by at most one other, which
    // lies on its other side. Faces are sorted so that equal ones are adjacent.
    context.report(0.3, "checking that tetrahedra meet face to face");
    std::vector<TetFace> tet_faces(static_cast<size_t>(nt) * 4);
    // Outward faces of a positive tetrahedron (0, 1, 2, 3).
    static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    for (int32_t t = 0; t < nt; ++t)
        for (int f = 0; f < 4; ++f) {
            TetFace& tf = tet_faces[static_cast<size_t>(t) * 4 + f];
            const Tet& x = m.tetrahedra[t];
            sort3(x[kFace[f][0]], x[kFace[f][1]], x[kFace[f][2]], tf.v, tf.even);
            tf.tet = t;
        }
    std::sort(tet_faces.begin(), tet_faces.end(), [](const TetFace& a, const TetFace& b) {
        if (!same_corners(a.v, b.v)) return corners_less(a.v, b.v);
        return a.tet < b.tet;
    });

    // The faces on S, sorted the same way (the index into m.faces kept).
    struct SFace {
        int32_t v[3];
        int64_t index;
    };
    std::vector<SFace> s_faces(static_cast<size_t>(nf));
    for (int64_t f = 0; f < nf; ++f) {
        bool even;
        sort3(m.faces[f][0], m.faces[f][1], m.faces[f][2], s_faces[f].v, even);
        s_faces[f].index = f;
    }
    std::sort(s_faces.begin(), s_faces.end(), [](const SFace& a, const SFace& b) {
        if (!same_corners(a.v, b.v)) return corners_less(a.v, b.v);
        return a.index < b.index;
    });
    int64_t duplicate_faces = 0;
    for (size_t i = 1; i < s_faces.size(); ++i)
        if (same_corners(s_faces[i].v, s_faces[i - 1].v)) {
            ++duplicate_faces;
            problem({{"face", s_faces[i].index}}, "is listed twice in /tetmesh/faces (also as face " +
                                                      std::to_string(s_faces[i - 1].index) + ")");
        }

    int64_t nonconforming = 0, holes = 0, unlisted_interfaces = 0, faces_not_in_mesh = 0;
    std::vector<char> vertex_used(static_cast<size_t>(nv), 0);
    size_t s_at = 0;  // merge-walk of tet_faces and s_faces
    for (size_t i = 0; i < tet_faces.size();) {
        size_t j = i + 1;
        while (j < tet_faces.size() && same_corners(tet_faces[j].v, tet_faces[i].v)) ++j;
        const TetFace& a = tet_faces[i];
        for (int c = 0; c < 3; ++c) vertex_used[a.v[c]] = 1;
        while (s_at < s_faces.size() && corners_less(s_faces[s_at].v, a.v)) {
            ++faces_not_in_mesh;
            problem({{"face", s_faces[s_at].index}}, "is not a face of any tetrahedron");
            ++s_at;
        }
        bool on_s = false;
        while (s_at < s_faces.size() && same_corners(s_faces[s_at].v, a.v)) on_s = true, ++s_at;
        const std::string corners = vertex_words(a.v[0], a.v[1], a.v[2]);
        if (j - i > 2) {
            ++nonconforming;
            problem({{"tetrahedron", a.tet}}, "shares the face with vertices " + corners + " with " +
                                                  std::to_string(j - i - 1) + " other tetrahedra (at most one allowed)");
        } else if (j - i == 2) {
            const TetFace& b = tet_faces[i + 1];
            if (a.even == b.even) {
                ++nonconforming;
                problem({{"tetrahedron", a.tet}, {"tetrahedron", b.tet}},
                        "overlap: both lie on the same side of their shared face with vertices " + corners);
            } else if (!on_s && m.regions[a.tet] != m.regions[b.tet]) {
                ++unlisted_interfaces;
                problem({{"tetrahedron", a.tet}, {"tetrahedron", b.tet}},
                        "are in regions " + std::to_string(m.regions[a.tet]) + " and " +
                            std::to_string(m.regions[b.tet]) + " but their shared face with vertices " + corners +
                            " is not in /tetmesh/faces (regions are separated by S)");
            }
        } else if (!on_s) {
            ++holes;
            problem({{"tetrahedron", a.tet}}, "has the face with vertices " + corners +
                                                  " on the boundary of the mesh, but that face is not in "
                                                  "/tetmesh/faces (a hole: the mesh does not fill S's inside)");
        }
        i = j;
    }
    for (; s_at < s_faces.size(); ++s_at) {
        ++faces_not_in_mesh;
        problem({{"face", s_faces[s_at].index}}, "is not a face of any tetrahedron");
    }
    int64_t unused_vertices = 0;
    for (int32_t v = 0; v < nv; ++v)
        if (!vertex_used[v]) {
            ++unused_vertices;
            problem({{"vertex", v}}, "is a corner of no tetrahedron");
        }
    r.add_count("nonconforming", nonconforming);
    r.add_count("boundary_holes", holes);
    r.add_count("unlisted_interfaces", unlisted_interfaces);
    r.add_count("faces_not_in_mesh", faces_not_in_mesh + duplicate_faces);
    r.add_count("unused_vertices", unused_vertices);

    // 3. The faces on S: each lies in its coarse triangle (its corners' parameter points)
    // with the triangle's orientation, and together they cover the triangle.
    context.report(0.7, "checking the faces on S");
    const int32_t ntc = coarse.num_triangles();
    std::vector<double> covered(static_cast<size_t>(ntc), 0.0);
    std::vector<int64_t> faces_per_triangle(static_cast<size_t>(ntc), 0);
    int64_t misplaced_faces = 0;
    for (int64_t f = 0; f < nf; ++f) {
        const int32_t t = m.face_coarse_triangle[f];
        ++faces_per_triangle[t];
        Vec2 q[3];
        bool placed = true;
        for (int c = 0; c < 3 && placed; ++c) {
            const int32_t v = m.faces[f][c];
            const SurfacePoint& p = m.vertex_parameter_points[v];
            Vec3 b;
            if (!p.valid()) {
                problem({{"face", f}, {"vertex", v}}, "corner vertex " + std::to_string(v) +
                                                          " has no parameter position on S (vertex_parameter_triangle -1)");
                placed = false;
            } else if (!barycentric_in(coarse, t, p, b)) {
                problem({{"face", f}, {"vertex", v}},
                        "corner vertex " + std::to_string(v) + " has its parameter position in coarse triangle " +
                            std::to_string(p.triangle) + ", not on the face's coarse triangle " + std::to_string(t));
                placed = false;
            } else {
                q[c] = {b[1], b[2]};
            }
        }
        if (!placed) {
            ++misplaced_faces;
            continue;
        }
        const int sign = orient2d(q[0], q[1], q[2]);
        if (sign != 1) {
            ++misplaced_faces;
            problem({{"face", f}, {"coarse_triangle", t}},
                    sign == 0 ? "is degenerate in the parameter space of its coarse triangle"
                              : "is oriented against its coarse triangle");
            continue;
        }
        covered[t] += 0.5 * ((q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]));
    }
    // At level L every coarse triangle is covered by exactly 4^L faces (spec §3.3).
    const int64_t expected_faces = m.level <= 15 ? int64_t(1) << (2 * m.level) : -1;
    int64_t uncovered = 0;
    for (int32_t t = 0; t < ntc; ++t) {
        // The barycentric triangle has area 1/2; the faces' areas add up to it up to rounding.
        const bool count_wrong = expected_faces >= 0 && faces_per_triangle[t] != expected_faces;
        if (count_wrong || std::abs(covered[t] - 0.5) > 1e-9) {
            ++uncovered;
            problem({{"coarse_triangle", t}},
                    "is covered by " + std::to_string(faces_per_triangle[t]) + " faces of /tetmesh/faces" +
                        (expected_faces >= 0 ? " (" + std::to_string(expected_faces) + " expected at level " +
                                                   std::to_string(m.level) + ")"
                                             : std::string()) +
                        " covering " + detail::format_number(covered[t] / 0.5) + " of its area");
        }
    }
    r.add_count("misplaced_faces", misplaced_faces);
    r.add_count("uncovered_coarse_triangles", uncovered);

    // 4. Coarse vertices are where the coarse surface has them; at level 0 the first #Vc
    // vertices are the coarse vertices in order and the faces are the coarse triangles.
    int64_t moved = 0;
    for (int32_t v = 0; v < nv; ++v) {
        const int32_t c = m.vertex_coarse_vertex[v];
        if (c >= 0 && m.vertices[v] != coarse.vertices[c]) {
            ++moved;
            problem({{"vertex", v}}, "is coarse vertex " + std::to_string(c) + " but not at its position");
        }
    }
    if (m.level == 0) {
        const int32_t nvc = coarse.num_vertices();
        for (int32_t v = 0; v < nv; ++v) {
            const int32_t want = v < nvc ? v : -1;
            if (m.vertex_coarse_vertex[v] != want) {
                ++moved;
                problem({{"vertex", v}}, "has vertex_coarse_vertex " + std::to_string(m.vertex_coarse_vertex[v]) +
                                             ", expected " + std::to_string(want) +
                                             " at level 0 (the coarse vertices first, in order)");
            }
        }
        if (nf == ntc)
            for (int32_t t = 0; t < ntc; ++t)
                if (m.faces[t] != coarse.triangles[t] || m.face_coarse_triangle[t] != t) {
                    ++misplaced_faces;
                    problem({{"face", t}}, "is not coarse triangle " + std::to_string(t) +
                                               " (at level 0, face i is coarse triangle i)");
                }
    }
    r.add_count("misplaced_coarse_vertices", moved);

    if (nt > 0) r.worst = WorstValue{"min_dihedral_degrees", min_dihedral, {{"tetrahedron", min_dihedral_tet}}};
    r.summary = std::to_string(nt) + " tetrahedra at level " + std::to_string(m.level) + ", " +
                std::to_string(inverted) + " inverted, " +
                (nonconforming + holes + unlisted_interfaces + faces_not_in_mesh + duplicate_faces == 0
                     ? std::string("conforming")
                     : detail::count_text(nonconforming + holes + unlisted_interfaces + faces_not_in_mesh +
                                              duplicate_faces,
                                          "conformity problem")) +
                ", " + std::to_string(nf) + " faces on S" +
                (misplaced_faces + uncovered == 0 ? std::string(" covering it")
                                                  : " (" + detail::count_text(misplaced_faces + uncovered, "problem") + ")") +
                ", smallest dihedral angle " + detail::format_number(min_dihedral) + " degrees";
    context.report(1.0, "tetrahedral mesh checked");
    return r;
}

}  // namespace bpm
