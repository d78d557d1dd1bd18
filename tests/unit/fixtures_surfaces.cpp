#include "fixtures_surfaces.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace bpm::fixtures {

namespace {
constexpr double kPi = 3.14159265358979323846;

void add(Surface& s, int32_t a, int32_t b, int32_t c, int32_t patch) {
    s.triangles.push_back({a, b, c});
    s.patches.push_back(patch);
}
}  // namespace

Surface tetrahedron() {
    Surface s;
    s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    add(s, 0, 2, 1, 0);
    add(s, 0, 1, 3, 0);
    add(s, 1, 2, 3, 0);
    add(s, 0, 3, 2, 0);
    return s;
}

Surface voxel_surface(int nx, int ny, int nz, const std::vector<int>& labels, int res) {
    const int n[3] = {nx, ny, nz};
    auto label = [&](int i, int j, int k) {
        if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return 0;
        return labels[(static_cast<size_t>(k) * ny + j) * nx + i];
    };
    Surface s;
    std::map<std::array<int, 3>, int32_t> index;
    auto vertex = [&](const std::array<int, 3>& g) {
        auto it = index.find(g);
        if (it != index.end()) return it->second;
        const int32_t id = static_cast<int32_t>(s.vertices.size());
        s.vertices.push_back({double(g[0]) / res, double(g[1]) / res, double(g[2]) / res});
        index.emplace(g, id);
        return id;
    };
    for (int d = 0; d < 3; ++d) {
        const int d1 = (d + 1) % 3, d2 = (d + 2) % 3;
        int c[3];
        for (c[d] = -1; c[d] < n[d]; ++c[d])
            for (c[d1] = 0; c[d1] < n[d1]; ++c[d1])
                for (c[d2] = 0; c[d2] < n[d2]; ++c[d2]) {
                    int e[3] = {c[0], c[1], c[2]};
                    e[d] += 1;
                    const int la = label(c[0], c[1], c[2]), lb = label(e[0], e[1], e[2]);
                    if (la == lb) continue;
                    const bool positive = la > lb;  // normal from the higher label to the lower
                    const int patch = std::min(la, lb) * 100 + std::max(la, lb);
                    for (int a = 0; a < res; ++a)
                        for (int b = 0; b < res; ++b) {
                            // corners in (d1, d2) grid units, counter-clockwise for normal +d
                            const int uv[4][2] = {{a, b}, {a + 1, b}, {a + 1, b + 1}, {a, b + 1}};
                            int32_t q[4];
                            for (int m = 0; m < 4; ++m) {
                                std::array<int, 3> g;
                                g[d] = (c[d] + 1) * res;
                                g[d1] = c[d1] * res + uv[m][0];
                                g[d2] = c[d2] * res + uv[m][1];
                                q[m] = vertex(g);
                            }
                            if (!positive) std::swap(q[1], q[3]);
                            add(s, q[0], q[1], q[2], patch);
                            add(s, q[0], q[2], q[3], patch);
                        }
                }
    }
    return s;
}

Surface cube(int res) { return voxel_surface(1, 1, 1, {1}, res); }

Surface torus(int n, int m) {
    Surface s;
    const double R = 3.0, r = 1.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) {
            const double th = 2 * kPi * i / n, ph = 2 * kPi * j / m;
            s.vertices.push_back({(R + r * std::cos(ph)) * std::cos(th), (R + r * std::cos(ph)) * std::sin(th), r * std::sin(ph)});
        }
    auto id = [&](int i, int j) { return static_cast<int32_t>((i % n) * m + (j % m)); };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) {
            add(s, id(i, j), id(i + 1, j), id(i + 1, j + 1), 0);
            add(s, id(i, j), id(i + 1, j + 1), id(i, j + 1), 0);
        }
    return s;
}

Surface double_torus(int res) {
    std::vector<int> labels(15, 1);
    labels[1 * 5 + 1] = 0;
    labels[1 * 5 + 3] = 0;
    return voxel_surface(5, 3, 1, labels, res);
}

Surface disk(int n) {
    Surface s;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) s.vertices.push_back({double(i), double(j), 0.0});
    auto id = [&](int i, int j) { return static_cast<int32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            add(s, id(i, j), id(i + 1, j), id(i + 1, j + 1), 0);
            add(s, id(i, j), id(i + 1, j + 1), id(i, j + 1), 0);
        }
    return s;
}

Surface two_cubes(int res) { return voxel_surface(2, 1, 1, {1, 2}, res); }

Surface octants(int res) { return voxel_surface(2, 2, 2, {1, 2, 3, 4, 5, 6, 7, 8}, res); }

Surface cylinder_wedges(int n, int levels) {
    Surface s;
    const double radius = 2.0;
    auto axis = [&](int z) { return static_cast<int32_t>(z); };
    for (int z = 0; z <= levels; ++z) s.vertices.push_back({0.0, 0.0, double(z)});
    auto rim = [&](int j, int z) { return static_cast<int32_t>(levels + 1 + z * n + ((j % n) + n) % n); };
    for (int z = 0; z <= levels; ++z)
        for (int j = 0; j < n; ++j) {
            const double a = 2 * kPi * j / n;
            s.vertices.push_back({radius * std::cos(a), radius * std::sin(a), double(z)});
        }
    const int third = n / 3;
    auto wedge = [&](int j) { return (((j % n) + n) % n) / third + 1; };
    for (int j = 0; j < n; ++j) {
        const int w = wedge(j);
        for (int z = 0; z < levels; ++z) {
            add(s, rim(j, z), rim(j + 1, z), rim(j + 1, z + 1), w);
            add(s, rim(j, z), rim(j + 1, z + 1), rim(j, z + 1), w);
        }
        add(s, axis(levels), rim(j, levels), rim(j + 1, levels), w);
        add(s, axis(0), rim(j + 1, 0), rim(j, 0), w);
    }
    for (int k = 0; k < 3; ++k) {
        const int j = k * third;
        const int a = wedge(j - 1), b = wedge(j);
        const int patch = std::min(a, b) * 100 + std::max(a, b);
        for (int z = 0; z < levels; ++z) {
            add(s, axis(z), rim(j, z), rim(j, z + 1), patch);
            add(s, axis(z), rim(j, z + 1), axis(z + 1), patch);
        }
    }
    return s;
}

Surface hourglass(int n) {
    Surface s;
    s.vertices.push_back({0, 0, 0});   // apex
    s.vertices.push_back({0, 0, 1});   // upper base centre
    s.vertices.push_back({0, 0, -1});  // lower base centre
    for (int side = 0; side < 2; ++side)
        for (int j = 0; j < n; ++j) {
            const double a = 2 * kPi * j / n;
            s.vertices.push_back({std::cos(a), std::sin(a), side == 0 ? 1.0 : -1.0});
        }
    auto up = [&](int j) { return static_cast<int32_t>(3 + (j % n)); };
    auto down = [&](int j) { return static_cast<int32_t>(3 + n + (j % n)); };
    for (int j = 0; j < n; ++j) {
        add(s, 0, up(j + 1), up(j), 1);
        add(s, 1, up(j), up(j + 1), 1);
        add(s, 0, down(j), down(j + 1), 2);
        add(s, 2, down(j + 1), down(j), 2);
    }
    return s;
}

Surface moebius(int n) {
    Surface s;
    const double R = 2.0;
    for (int u = 0; u < n; ++u)
        for (int i = 0; i < 3; ++i) {
            const double th = 2 * kPi * u / n, w = (i - 1) * 0.5;
            s.vertices.push_back({(R + w * std::cos(th / 2)) * std::cos(th), (R + w * std::cos(th / 2)) * std::sin(th),
                                  w * std::sin(th / 2)});
        }
    auto id = [&](int u, int i) { return static_cast<int32_t>(u * 3 + i); };
    for (int u = 0; u < n; ++u)
        for (int i = 0; i < 2; ++i) {
            int32_t a = id(u, i), d = id(u, i + 1), b, c;
            if (u + 1 < n) {
                b = id(u + 1, i);
                c = id(u + 1, i + 1);
            } else {  // the half twist: row i meets row 2 - i
                b = id(0, 2 - i);
                c = id(0, 1 - i);
            }
            add(s, a, b, c, 0);
            add(s, a, c, d, 0);
        }
    return s;
}

Surface ridged_lens(int segments, int rings, double crease_degrees, double noise) {
    Surface s;
    // The upper cap: a sphere of radius R about (0, 0, -c) through the unit circle, its
    // normal there beta from the vertical (the lower cap mirrored).
    const double beta = (90.0 - 0.5 * crease_degrees) * kPi / 180.0;
    const double R = 1.0 / std::sin(beta), c = R * std::cos(beta);
    // Latitudes from the top pole (k = 0) over the circle (k = rings) to the bottom pole.
    auto ring_point = [&](int k, int j) -> Vec3 {
        const double phi = beta * (k <= rings ? k : 2 * rings - k) / rings;
        const double th = 2 * kPi * j / segments;
        const double z = -c + R * std::cos(phi);
        return {R * std::sin(phi) * std::cos(th), R * std::sin(phi) * std::sin(th), k <= rings ? z : -z};
    };
    s.vertices.push_back(ring_point(0, 0));
    for (int k = 1; k < 2 * rings; ++k)
        for (int j = 0; j < segments; ++j) s.vertices.push_back(ring_point(k, j));
    s.vertices.push_back(ring_point(2 * rings, 0));
    const int32_t bottom = static_cast<int32_t>(s.vertices.size()) - 1;
    auto id = [&](int k, int j) { return static_cast<int32_t>(1 + (k - 1) * segments + j % segments); };
    for (int j = 0; j < segments; ++j) {
        add(s, 0, id(1, j), id(1, j + 1), 0);
        add(s, bottom, id(2 * rings - 1, j + 1), id(2 * rings - 1, j), 0);
        for (int k = 1; k + 1 < 2 * rings; ++k) {
            add(s, id(k, j), id(k + 1, j), id(k + 1, j + 1), 0);
            add(s, id(k, j), id(k + 1, j + 1), id(k, j + 1), 0);
        }
    }
    if (noise > 0) {
        uint64_t state = 0x9e3779b97f4a7c15ull;  // a fixed 64-bit LCG (Knuth's MMIX constants)
        for (Vec3& v : s.vertices) {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            const double u = double(state >> 11) / double(1ull << 53);  // [0, 1)
            const double f = 1.0 + noise * (2.0 * u - 1.0);
            v = {v[0] * f, v[1] * f, v[2] * f};
        }
    }
    return s;
}

Surface subdivide(const Surface& in) {
    Surface s;
    s.vertices = in.vertices;
    std::map<std::pair<int32_t, int32_t>, int32_t> mid;
    auto midpoint = [&](int32_t a, int32_t b) {
        const auto key = std::minmax(a, b);
        auto it = mid.find(key);
        if (it != mid.end()) return it->second;
        const int32_t id = static_cast<int32_t>(s.vertices.size());
        s.vertices.push_back(0.5 * (in.vertices[a] + in.vertices[b]));
        mid.emplace(key, id);
        return id;
    };
    for (int32_t t = 0; t < in.num_triangles(); ++t) {
        const Tri& c = in.triangles[t];
        const int32_t m0 = midpoint(c[0], c[1]), m1 = midpoint(c[1], c[2]), m2 = midpoint(c[2], c[0]);
        const int32_t patch = in.patches[t];
        add(s, c[0], m0, m2, patch);
        add(s, m0, c[1], m1, patch);
        add(s, m2, m1, c[2], patch);
        add(s, m0, m1, m2, patch);
    }
    return s;
}

void recompute_images(Parametrization& p) {
    p.node_image.resize(p.node_kind.size());
    for (size_t n = 0; n < p.node_kind.size(); ++n) {
        if (p.node_kind[n] == NodeKind::EdgeCrossing) {
            const auto& e = p.node_original_edge[n];
            const double s = p.node_edge_parameter[n];
            p.node_image[n] = (1.0 - s) * p.original.vertices[e[0]] + s * p.original.vertices[e[1]];
        } else {
            p.node_image[n] = p.original.vertices[p.node_original_vertex[n]];
        }
    }
}

namespace {
// Appends one node of coarse triangle (CSR offsets are fixed up by the caller).
void push_node(Parametrization& p, NodeKind kind, const Vec3& b, int32_t vertex, std::array<int32_t, 2> edge = {-1, -1},
               double s = std::nan("")) {
    p.node_kind.push_back(kind);
    p.node_barycentric.push_back(b);
    p.node_original_vertex.push_back(vertex);
    p.node_original_edge.push_back(edge);
    p.node_edge_parameter.push_back(s);
}
}  // namespace

Parametrization identity_parametrization(const Surface& surface) {
    Parametrization p;
    p.original = surface;
    p.coarse = surface;
    for (int32_t v = 0; v < surface.num_vertices(); ++v) p.coarse_vertex_origin.push_back(v);
    p.node_offsets.push_back(0);
    p.piece_offsets.push_back(0);
    for (int32_t t = 0; t < surface.num_triangles(); ++t) {
        const Tri& c = surface.triangles[t];
        push_node(p, NodeKind::CoarseCorner, {1, 0, 0}, c[0]);
        push_node(p, NodeKind::CoarseCorner, {0, 1, 0}, c[1]);
        push_node(p, NodeKind::CoarseCorner, {0, 0, 1}, c[2]);
        p.pieces.push_back({0, 1, 2});
        p.piece_original_triangle.push_back(t);
        p.node_offsets.push_back(p.num_nodes());
        p.piece_offsets.push_back(p.num_pieces());
    }
    recompute_images(p);
    return p;
}

Parametrization refined_parametrization(const Surface& coarse) {
    Parametrization p;
    p.coarse = coarse;
    Surface& o = p.original;
    o.vertices = coarse.vertices;
    for (int32_t v = 0; v < coarse.num_vertices(); ++v) p.coarse_vertex_origin.push_back(v);
    std::map<std::pair<int32_t, int32_t>, int32_t> mid;
    auto midpoint = [&](int32_t a, int32_t b) {
        const auto key = std::minmax(a, b);
        auto it = mid.find(key);
        if (it != mid.end()) return it->second;
        const int32_t id = static_cast<int32_t>(o.vertices.size());
        o.vertices.push_back(0.5 * (coarse.vertices[a] + coarse.vertices[b]));
        mid.emplace(key, id);
        return id;
    };
    const Vec3 interior{0.375, 0.25, 0.375};
    p.node_offsets.push_back(0);
    p.piece_offsets.push_back(0);
    for (int32_t t = 0; t < coarse.num_triangles(); ++t) {
        const Tri& c = coarse.triangles[t];
        const int32_t m0 = midpoint(c[0], c[1]), m1 = midpoint(c[1], c[2]), m2 = midpoint(c[2], c[0]);
        const int32_t q = static_cast<int32_t>(o.vertices.size());
        o.vertices.push_back(barycentric_point(coarse.vertices[c[0]], coarse.vertices[c[1]], coarse.vertices[c[2]], interior));
        const int32_t ids[7] = {c[0], c[1], c[2], m0, m1, m2, q};
        push_node(p, NodeKind::CoarseCorner, {1, 0, 0}, c[0]);
        push_node(p, NodeKind::CoarseCorner, {0, 1, 0}, c[1]);
        push_node(p, NodeKind::CoarseCorner, {0, 0, 1}, c[2]);
        push_node(p, NodeKind::OriginalVertex, {0.5, 0.5, 0}, m0);
        push_node(p, NodeKind::OriginalVertex, {0, 0.5, 0.5}, m1);
        push_node(p, NodeKind::OriginalVertex, {0.5, 0, 0.5}, m2);
        push_node(p, NodeKind::OriginalVertex, interior, q);
        const Tri pieces[6] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 6}, {4, 5, 6}, {5, 3, 6}};
        for (const Tri& pc : pieces) {
            p.piece_original_triangle.push_back(o.num_triangles());
            p.pieces.push_back(pc);
            add(o, ids[pc[0]], ids[pc[1]], ids[pc[2]], coarse.patches[t]);
        }
        p.node_offsets.push_back(p.num_nodes());
        p.piece_offsets.push_back(p.num_pieces());
    }
    recompute_images(p);
    return p;
}

Parametrization flipped_diagonal_parametrization(const Surface& quads) {
    Parametrization p;
    p.original = quads;
    p.coarse.vertices = quads.vertices;
    for (int32_t v = 0; v < quads.num_vertices(); ++v) p.coarse_vertex_origin.push_back(v);
    p.node_offsets.push_back(0);
    p.piece_offsets.push_back(0);
    for (int32_t i = 0; i + 1 < quads.num_triangles(); i += 2) {
        const int32_t a = quads.triangles[i][0], b = quads.triangles[i][1], c = quads.triangles[i][2],
                      d = quads.triangles[i + 1][2];
        const int32_t patch = quads.patches[i];
        const std::array<int32_t, 2> ac{std::min(a, c), std::max(a, c)};
        // coarse triangle (a, b, d): the crossing is on local edge 1 (b -> d)
        add(p.coarse, a, b, d, patch);
        push_node(p, NodeKind::CoarseCorner, {1, 0, 0}, a);
        push_node(p, NodeKind::CoarseCorner, {0, 1, 0}, b);
        push_node(p, NodeKind::CoarseCorner, {0, 0, 1}, d);
        push_node(p, NodeKind::EdgeCrossing, {0, 0.5, 0.5}, -1, ac, 0.5);
        p.pieces.push_back({0, 1, 3});
        p.piece_original_triangle.push_back(i);
        p.pieces.push_back({0, 3, 2});
        p.piece_original_triangle.push_back(i + 1);
        p.node_offsets.push_back(p.num_nodes());
        p.piece_offsets.push_back(p.num_pieces());
        // coarse triangle (b, c, d): the crossing is on local edge 2 (d -> b)
        add(p.coarse, b, c, d, patch);
        push_node(p, NodeKind::CoarseCorner, {1, 0, 0}, b);
        push_node(p, NodeKind::CoarseCorner, {0, 1, 0}, c);
        push_node(p, NodeKind::CoarseCorner, {0, 0, 1}, d);
        push_node(p, NodeKind::EdgeCrossing, {0.5, 0, 0.5}, -1, ac, 0.5);
        p.pieces.push_back({0, 1, 3});
        p.piece_original_triangle.push_back(i);
        p.pieces.push_back({3, 1, 2});
        p.piece_original_triangle.push_back(i + 1);
        p.node_offsets.push_back(p.num_nodes());
        p.piece_offsets.push_back(p.num_pieces());
    }
    recompute_images(p);
    return p;
}

Surface load_off(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot open " + path);
    std::vector<std::string> tokens;
    std::string line;
    while (std::getline(in, line)) {
        const auto hash = line.find('#');
        if (hash != std::string::npos) line.erase(hash);
        std::istringstream ls(line);
        std::string tok;
        while (ls >> tok) tokens.push_back(tok);
    }
    size_t i = 0;
    if (i < tokens.size() && tokens[i] == "OFF") ++i;
    const long nv = std::stol(tokens.at(i++)), nf = std::stol(tokens.at(i++));
    ++i;  // edge count
    Surface s;
    for (long v = 0; v < nv; ++v) {
        Vec3 x;
        for (int d = 0; d < 3; ++d) x[d] = std::stod(tokens.at(i++));
        s.vertices.push_back(x);
    }
    for (long f = 0; f < nf; ++f) {
        const int k = std::stoi(tokens.at(i++));
        std::vector<int32_t> poly;
        for (int j = 0; j < k; ++j) poly.push_back(std::stoi(tokens.at(i++)));
        // skip optional colour values up to the next face: OFF files from the CGAL
        // data set put them on the same line, which we cannot see any more; the meshes
        // used here have none.
        for (int j = 1; j + 1 < k; ++j) add(s, poly[0], poly[j], poly[j + 1], 0);
    }
    return s;
}

}  // namespace bpm::fixtures
