#include "fixtures_phi.h"

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>

#include "bpm/predicates.h"

namespace bpm::test {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void begin_triangle(Parametrization& p) {
    if (p.node_offsets.empty()) p.node_offsets.push_back(0);
    if (p.piece_offsets.empty()) p.piece_offsets.push_back(0);
}
void end_triangle(Parametrization& p) {
    p.node_offsets.push_back(p.num_nodes());
    p.piece_offsets.push_back(p.num_pieces());
}
void add_node(Parametrization& p, const Vec3& b, NodeKind kind, int32_t vertex, std::array<int32_t, 2> edge,
              double s) {
    p.node_barycentric.push_back(b);
    p.node_kind.push_back(kind);
    p.node_original_vertex.push_back(vertex);
    p.node_original_edge.push_back(edge);
    p.node_edge_parameter.push_back(s);
    p.node_image.push_back({0, 0, 0});
    p.node_image.back() = node_image_from_kind(p, p.num_nodes() - 1);
}
}  // namespace

// ---------------------------------------------------------------------------

Parametrization make_subdivided_octahedron(int levels, double bump) {
    if (levels < 0 || levels > 10) throw std::invalid_argument("make_subdivided_octahedron: levels out of range");
    const int N = 1 << levels;
    const std::array<int, 3> axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const Tri faces[8] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};

    Parametrization p;
    for (const auto& a : axes) p.coarse.vertices.push_back({double(a[0]), double(a[1]), double(a[2])});
    for (int f = 0; f < 8; ++f) {
        p.coarse.triangles.push_back(faces[f]);
        p.coarse.patches.push_back(f);
    }

    // Original vertices keyed by their exact lattice point N*x (shared between faces).
    std::map<std::array<int, 3>, int32_t> vertex_of;
    const auto vertex = [&](const std::array<int, 3>& key) {
        auto it = vertex_of.find(key);
        if (it != vertex_of.end()) return it->second;
        const Vec3 flat{double(key[0]) / N, double(key[1]) / N, double(key[2]) / N};
        Vec3 x = flat;
        const bool corner = std::abs(key[0]) + std::abs(key[1]) + std::abs(key[2]) == N &&
                            (std::abs(key[0]) == N || std::abs(key[1]) == N || std::abs(key[2]) == N);
        if (!corner) {
            const double r = 1 + bump * std::sin(5 * flat[0] + 1) * std::cos(4 * flat[1] - 2 * flat[2]);
            x = (r / norm(flat)) * flat;
        }
        const int32_t id = p.original.num_vertices();
        p.original.vertices.push_back(x);
        vertex_of.emplace(key, id);
        return id;
    };
    for (int v = 0; v < 6; ++v) p.coarse_vertex_origin.push_back(vertex({axes[v][0] * N, axes[v][1] * N, axes[v][2] * N}));

    for (int f = 0; f < 8; ++f) {
        begin_triangle(p);
        const Tri& face = faces[f];
        // Local node index of lattice point (a, b): a steps towards corner 1, b towards corner 2.
        std::map<std::pair<int, int>, int32_t> local;
        std::map<std::pair<int, int>, int32_t> global;
        for (int b = 0; b <= N; ++b)
            for (int a = 0; a + b <= N; ++a) {
                const int c = N - a - b;
                std::array<int, 3> key{};
                for (int k = 0; k < 3; ++k)
                    key[k] = c * axes[face[0]][k] + a * axes[face[1]][k] + b * axes[face[2]][k];
                const int32_t v = vertex(key);
                global[{a, b}] = v;
                local[{a, b}] = static_cast<int32_t>(p.num_nodes() - p.node_offsets.back());
                const bool corner = a == N || b == N || c == N;
                add_node(p, {double(c) / N, double(a) / N, double(b) / N},
                         corner ? NodeKind::CoarseCorner : NodeKind::OriginalVertex, v, {-1, -1}, kNaN);
            }
        const auto piece = [&](std::pair<int, int> i, std::pair<int, int> j, std::pair<int, int> k) {
            p.pieces.push_back({local[i], local[j], local[k]});
            p.piece_original_triangle.push_back(p.original.num_triangles());
            p.original.triangles.push_back({global[i], global[j], global[k]});
            p.original.patches.push_back(f);
        };
        for (int b = 0; b < N; ++b)
            for (int a = 0; a + b < N; ++a) {
                piece({a, b}, {a + 1, b}, {a, b + 1});
                if (a + b + 2 <= N) piece({a + 1, b}, {a + 1, b + 1}, {a, b + 1});
            }
        end_triangle(p);
    }
    return p;
}

// ---------------------------------------------------------------------------

double default_height(double x, double y) {
    return 0.15 * std::sin(3 * x + 1) * std::cos(2 * y) + 0.05 * std::sin(7 * x * y);
}

namespace {

// A polygon corner during clipping: an original vertex, or the crossing of original
// edge (u, w) with the coarse edge (ca, cb) (coarse vertex ids, ca < cb).
struct Tagged {
    Vec2 xy;
    bool crossing = false;
    int32_t v = -1;
    int32_t u = -1, w = -1;
    int32_t ca = -1, cb = -1;
    double s = kNaN;
    auto key() const { return std::make_tuple(crossing, v, u, w, ca, cb); }
};

double orient_value(const Vec2& a, const Vec2& b, const Vec2& c) { return cross(b - a, c - a); }

}  // namespace

Parametrization make_height_field(int n, int m, const HeightFunction& height) {
    if (n <= 0 || m <= 0 || n % m != 0) throw std::invalid_argument("make_height_field: need n % m == 0");
    const int r = n / m;
    Parametrization p;
    const auto vid = [n](int i, int j) { return static_cast<int32_t>(j * (n + 1) + i); };
    std::vector<Vec2> xy;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double x = double(i) / n, y = double(j) / n;
            // Clipping works in integer grid units, where the coordinates are exact and
            // a grid vertex on a coarse diagonal is exactly on it (orient2d == 0).
            xy.push_back({double(i), double(j)});
            p.original.vertices.push_back({x, y, height(x, y)});
        }
    // Original triangles, indexed by cell so that clipping can find them.
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int32_t patch = 1 + (i / r) % 3;
            p.original.triangles.push_back({vid(i, j), vid(i + 1, j), vid(i, j + 1)});
            p.original.triangles.push_back({vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)});
            p.original.patches.push_back(patch);
            p.original.patches.push_back(patch);
        }
    const auto cid = [m](int I, int J) { return static_cast<int32_t>(J * (m + 1) + I); };
    for (int J = 0; J <= m; ++J)
        for (int I = 0; I <= m; ++I) {
            const int32_t v = vid(I * r, J * r);
            p.coarse.vertices.push_back(p.original.vertices[static_cast<size_t>(v)]);
            p.coarse_vertex_origin.push_back(v);
        }
    for (int J = 0; J < m; ++J)
        for (int I = 0; I < m; ++I) {
            p.coarse.triangles.push_back({cid(I, J), cid(I + 1, J), cid(I + 1, J + 1)});
            p.coarse.triangles.push_back({cid(I, J), cid(I + 1, J + 1), cid(I, J + 1)});
            p.coarse.patches.push_back(1 + I % 3);
            p.coarse.patches.push_back(1 + I % 3);
        }

    for (int32_t t = 0; t < p.coarse.num_triangles(); ++t) {
        begin_triangle(p);
        const Tri& ct = p.coarse.triangles[static_cast<size_t>(t)];
        Vec2 C[3];
        for (int k = 0; k < 3; ++k) C[k] = xy[static_cast<size_t>(p.coarse_vertex_origin[static_cast<size_t>(ct[k])])];
        const int cell = t / 2;
        const int I = cell % m, J = cell / m;

        std::map<decltype(Tagged().key()), int32_t> local;
        // Coarse barycentrics of a point on coarse edge k at fraction `t_canon` from the
        // edge's lower-numbered vertex: both triangles sharing the edge get the same numbers.
        const auto on_edge = [&](int k, double t_canon) {
            Vec3 b{0, 0, 0};
            const bool forward = ct[k] < ct[(k + 1) % 3];
            b[k] = forward ? 1 - t_canon : t_canon;
            b[(k + 1) % 3] = forward ? t_canon : 1 - t_canon;
            return b;
        };
        const auto edge_fraction = [&](int k, const Vec2& x) {
            const bool forward = ct[k] < ct[(k + 1) % 3];
            const Vec2 a = forward ? C[k] : C[(k + 1) % 3], b = forward ? C[(k + 1) % 3] : C[k];
            return dot(x - a, b - a) / dot(b - a, b - a);
        };
        const auto node_of = [&](const Tagged& q) -> int32_t {
            auto it = local.find(q.key());
            if (it != local.end()) return it->second;
            const int32_t id = static_cast<int32_t>(p.num_nodes() - p.node_offsets.back());
            local.emplace(q.key(), id);
            if (q.crossing) {
                int k = -1;
                for (int e = 0; e < 3; ++e)
                    if (std::min(ct[e], ct[(e + 1) % 3]) == q.ca && std::max(ct[e], ct[(e + 1) % 3]) == q.cb) k = e;
                if (k < 0) throw std::logic_error("make_height_field: crossing on a foreign coarse edge");
                add_node(p, on_edge(k, edge_fraction(k, q.xy)), NodeKind::EdgeCrossing, -1, {q.u, q.w}, q.s);
                return id;
            }
            for (int k = 0; k < 3; ++k)
                if (p.coarse_vertex_origin[static_cast<size_t>(ct[k])] == q.v) {
                    Vec3 b{0, 0, 0};
                    b[k] = 1;
                    add_node(p, b, NodeKind::CoarseCorner, q.v, {-1, -1}, kNaN);
                    return id;
                }
            for (int k = 0; k < 3; ++k)
                if (orient2d(C[k], C[(k + 1) % 3], q.xy) == 0) {
                    add_node(p, on_edge(k, edge_fraction(k, q.xy)), NodeKind::OriginalVertex, q.v, {-1, -1}, kNaN);
                    return id;
                }
            const double area = orient_value(C[0], C[1], C[2]);
            const double b1 = orient_value(C[2], C[0], q.xy) / area, b2 = orient_value(C[0], C[1], q.xy) / area;
            add_node(p, {1 - b1 - b2, b1, b2}, NodeKind::OriginalVertex, q.v, {-1, -1}, kNaN);
            return id;
        };

        for (int j = J * r; j < (J + 1) * r; ++j)
            for (int i = I * r; i < (I + 1) * r; ++i)
                for (int half = 0; half < 2; ++half) {
                    const int32_t ot = 2 * (j * n + i) + half;
                    const Tri& tri = p.original.triangles[static_cast<size_t>(ot)];
                    std::vector<Tagged> poly;
                    for (int k = 0; k < 3; ++k) {
                        Tagged q;
                        q.xy = xy[static_cast<size_t>(tri[k])];
                        q.v = tri[k];
                        poly.push_back(q);
                    }
                    // Sutherland-Hodgman against the three edges of the coarse triangle.
                    for (int k = 0; k < 3 && poly.size() >= 3; ++k) {
                        const int32_t a = ct[k], b = ct[(k + 1) % 3];
                        const int32_t ca = std::min(a, b), cb = std::max(a, b);
                        const Vec2 A = xy[static_cast<size_t>(p.coarse_vertex_origin[static_cast<size_t>(ca)])];
                        const Vec2 B = xy[static_cast<size_t>(p.coarse_vertex_origin[static_cast<size_t>(cb)])];
                        const double flip = a == ca ? 1 : -1;  // inside = left of a->b
                        const auto side = [&](const Tagged& q) -> int {
                            if (q.crossing) {
                                if (q.ca == ca && q.cb == cb) return 0;
                                const double d = flip * orient_value(A, B, q.xy);
                                return d > 0 ? 1 : (d < 0 ? -1 : 0);
                            }
                            return int(flip) * orient2d(A, B, q.xy);
                        };
                        std::vector<Tagged> out;
                        for (size_t e = 0; e < poly.size(); ++e) {
                            const Tagged& P = poly[e];
                            const Tagged& Q = poly[(e + 1) % poly.size()];
                            const int sp = side(P), sq = side(Q);
                            if (sp >= 0) out.push_back(P);
                            if ((sp > 0 && sq < 0) || (sp < 0 && sq > 0)) {
                                // P-Q lies on an original edge of this triangle.
                                int32_t u = -1, w = -1;
                                const auto endpoints = [](const Tagged& x) {
                                    return x.crossing ? std::array<int32_t, 2>{x.u, x.w}
                                                      : std::array<int32_t, 2>{x.v, x.v};
                                };
                                const auto ep = endpoints(P), eq = endpoints(Q);
                                u = std::min({ep[0], ep[1], eq[0], eq[1]});
                                w = std::max({ep[0], ep[1], eq[0], eq[1]});
                                if (P.crossing && Q.crossing && ep != eq)
                                    throw std::logic_error("make_height_field: segment not on an original edge");
                                const Vec2 xu = xy[static_cast<size_t>(u)], xw = xy[static_cast<size_t>(w)];
                                const double du = orient_value(A, B, xu), dw = orient_value(A, B, xw);
                                Tagged x;
                                x.crossing = true;
                                x.u = u;
                                x.w = w;
                                x.ca = ca;
                                x.cb = cb;
                                x.s = du / (du - dw);
                                x.xy = (1 - x.s) * xu + x.s * xw;
                                out.push_back(x);
                            }
                        }
                        poly = out;
                    }
                    if (poly.size() < 3) continue;
                    double area = 0;
                    for (size_t e = 0; e < poly.size(); ++e) area += cross(poly[e].xy, poly[(e + 1) % poly.size()].xy);
                    if (!(area > 1e-9)) continue;  // in grid units: a sliver touching an edge
                    std::vector<int32_t> ids;
                    for (const auto& q : poly) ids.push_back(node_of(q));
                    for (size_t e = 1; e + 1 < ids.size(); ++e) {
                        p.pieces.push_back({ids[0], ids[e], ids[e + 1]});
                        p.piece_original_triangle.push_back(ot);
                    }
                }
        end_triangle(p);
    }
    return p;
}

BpmFile make_two_triangles_example() {
    BpmFile f;
    f.param = make_height_field(1, 1, [](double x, double y) { return 0.3 * (x + y - 2 * x * y); });
    // One optional item of format 1.2: a scalar field x + y + z at the original vertices.
    VertexArray temperature{"temperature", 1, {}};
    for (const Vec3& x : f.param.original.vertices) temperature.values.push_back(x[0] + x[1] + x[2]);
    f.param.original.vertex_data.push_back(std::move(temperature));
    f.units = "mm";
    f.provenance.push_back({"bpm-make-example", "1", "bpm-make-example two_triangles", ""});
    return f;
}

}  // namespace bpm::test
