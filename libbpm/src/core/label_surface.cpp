// Multi-label surface nets (bpm/label_image.h).
//
// Based on: S. F. Frisken Gibson, "Constrained elastic SurfaceNets: generating smooth
// surfaces from binary segmented data", MICCAI 1998; the multi-label form and the smoothing
// stencils along junction lines as VTK's vtkSurfaceNets3D documents them (W. Schroeder et
// al., "SurfaceNets for multi-label segmentations with preservation of sharp boundaries",
// JCGT 2022). Written from those descriptions.
//
// Index space: voxel (i, j, k) has its centre at (i, j, k). Cube (a, b, c), a in [0, nx],
// has the voxels (a-1+dx, b-1+dy, c-1+dz), dx, dy, dz in {0, 1}, as corners (outside the
// image: label 0), and its vertices live in [a-1, a] x [b-1, b] x [c-1, c].
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <unordered_set>

#include "bpm/check.h"
#include "bpm/errors.h"
#include "bpm/geometry.h"
#include "bpm/label_image.h"
#include "bpm/predicates.h"

namespace bpm {

namespace {

// The 12 edges of a cube between its corner voxels v = dx + 2 dy + 4 dz: 0-3 along x, 4-7
// along y, 8-11 along z.
constexpr int kEdgeEnds[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                  {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

// The edge of the cube from corner `v` one step along `axis` (v has 0 on that axis).
int edge_from(int v, int axis) {
    for (int e = 4 * axis; e < 4 * axis + 4; ++e)
        if (kEdgeEnds[e][0] == v) return e;
    return -1;
}

// The 6 faces of a cube: their 4 corners in cyclic order.
constexpr int kFaceCycle[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                  {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};

int edge_between(int u, int v) {
    if (u > v) std::swap(u, v);
    for (int e = 0; e < 12; ++e)
        if (kEdgeEnds[e][0] == u && kEdgeEnds[e][1] == v) return e;
    return -1;
}

struct UnionFind12 {
    int parent[12];
    UnionFind12() {
        for (int i = 0; i < 12; ++i) parent[i] = i;
    }
    int find(int i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    }
    void unite(int a, int b) {
        a = find(a), b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

// The sheets of the surface through one face of a cube (4 voxel labels in cyclic order):
// groups of the face's edges (between consecutive corners) whose quads share one edge of
// the surface. Normally one group of all edges with differing labels; where one label
// holds a diagonal and the two other corners differ from it, that label is taken as
// connected across the diagonal (of a checkerboard of two labels, the larger one) and
// the two other corners are cut off, each with its own edge of the surface. The decision
// depends only on the face, so both cubes that share it agree. After
// resolve_edge_contacts no face has such a diagonal (unless it reported some left): there,
// the two edges may join the same two vertices, an edge in four triangles of one label.
// Returns the number of groups (0-2); group g's face-edge positions (i = the edge from
// corner i to corner i+1) as a bit mask in masks[g].
int face_groups(const int32_t l[4], int masks[2]) {
    int active = 0;
    for (int i = 0; i < 4; ++i)
        if (l[i] != l[(i + 1) % 4]) active |= 1 << i;
    if (active == 0) return 0;
    const bool diag02 = l[0] == l[2] && l[1] != l[0] && l[3] != l[0];
    const bool diag13 = l[1] == l[3] && l[0] != l[1] && l[2] != l[1];
    int cut = -1;  // 0: corners 1 and 3 are cut off (0-2 joined); 1: corners 0 and 2 are cut off
    if (diag02 && diag13) cut = l[0] > l[1] ? 0 : 1;
    else if (diag02) cut = 0;
    else if (diag13) cut = 1;
    if (cut < 0) {
        masks[0] = active;
        return 1;
    }
    // Corner c touches the edges c-1 -> c (position c-1) and c -> c+1 (position c).
    const int c0 = cut == 0 ? 1 : 0, c1 = c0 + 2;
    masks[0] = (1 << ((c0 + 3) % 4)) | (1 << c0);
    masks[1] = (1 << ((c1 + 3) % 4)) | (1 << c1);
    return 2;
}

struct CubeRecord {
    int64_t key;            // linear cube index
    int32_t first_vertex;   // its vertices are first_vertex + component
    uint8_t component[12];  // per edge: the component (vertex) of the edge, 255 if inactive
};

// Labels as their positions among the image's distinct labels (LabelImage's compact form):
// the order, and so every comparison below, is that of the labels themselves.
template <class Index>
struct Grid {
    int64_t nx, ny, nz;
    const Index* labels;
    int32_t outside;  // the position of label 0
    int32_t at(int64_t i, int64_t j, int64_t k) const {
        if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return outside;
        return labels[i + nx * (j + ny * k)];
    }
    int64_t cube_key(int64_t a, int64_t b, int64_t c) const { return a + (nx + 1) * (b + (ny + 1) * c); }
};

bool finite_all(const double* x, int n) {
    for (int i = 0; i < n; ++i)
        if (!std::isfinite(x[i])) return false;
    return true;
}

double det3(const std::array<double, 9>& m) {
    return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) + m[2] * (m[3] * m[7] - m[4] * m[6]);
}

// Where one label holds two diagonal voxels around a voxel edge and the two other voxels
// have other labels (a checkerboard seen along the edge), the label touches itself only
// along that edge: its surface would be pinched there, and surface nets would give two
// sheets through the one edge between the two cubes. The image is changed instead, always
// raising one voxel's label so that the repetition ends (a change can make another such
// edge nearby; every voxel can only rise through the labels): an off-diagonal voxel with a
// smaller label than the diagonal's gets the diagonal's label (so the larger label is
// face-connected there, as in a two-label checkerboard), else a diagonal voxel gets the
// larger off-diagonal label. Only voxels inside the image change (outside is background).
// Returns the number of voxels changed; `unresolved` counts the edges left, 0 unless the
// passes ran out (they do not, but the loop is bounded).
template <class Index>
int64_t resolve_edge_contacts(const LabelImage& image, Index* labels, int32_t outside, int64_t& unresolved,
                              const Context& context) {
    const int64_t n[3] = {image.size[0], image.size[1], image.size[2]};
    const auto index = [&](const int64_t* p) -> int64_t {
        for (int d = 0; d < 3; ++d)
            if (p[d] < 0 || p[d] >= n[d]) return -1;
        return p[0] + n[0] * (p[1] + n[1] * p[2]);
    };
    int64_t changed = 0;
    unresolved = 0;
    for (int pass = 0; pass < 1000; ++pass) {
        int64_t found = 0, left = 0;
        for (int d = 0; d < 3; ++d) {
            const int d1 = (d + 1) % 3, d2 = (d + 2) % 3;
            // The edge along d at (u, w) in the (d1, d2) plane has the voxels (u-1..u, w-1..w).
            for (int64_t t = 0; t < n[d]; ++t) {
                for (int64_t w = 0; w <= n[d2]; ++w)
                    for (int64_t u = 0; u <= n[d1]; ++u) {
                        static constexpr int kCycle[4][2] = {{-1, -1}, {0, -1}, {0, 0}, {-1, 0}};
                        int64_t at[4];
                        int32_t l[4];
                        for (int c = 0; c < 4; ++c) {
                            int64_t p[3];
                            p[d] = t, p[d1] = u + kCycle[c][0], p[d2] = w + kCycle[c][1];
                            at[c] = index(p);
                            l[c] = at[c] < 0 ? outside : labels[at[c]];
                        }
                        const bool diag02 = l[0] == l[2] && l[1] != l[0] && l[3] != l[0];
                        const bool diag13 = l[1] == l[3] && l[0] != l[1] && l[2] != l[1];
                        if (!diag02 && !diag13) continue;
                        ++found;
                        // The diagonal to keep connected: of two, the larger label's.
                        const int keep = diag02 && diag13 ? (l[0] > l[1] ? 0 : 1) : diag02 ? 0 : 1;
                        const int32_t label = l[keep];
                        int target = -1;
                        int32_t to = 0;
                        for (const int c : {(keep + 1) % 4, (keep + 3) % 4})
                            if (target < 0 && at[c] >= 0 && l[c] < label) target = c, to = label;
                        if (target < 0) {
                            const int32_t larger = std::max(l[(keep + 1) % 4], l[(keep + 3) % 4]);
                            for (const int c : {keep, keep + 2})
                                if (target < 0 && at[c] >= 0 && label < larger) target = c, to = larger;
                        }
                        if (target < 0) {
                            ++left;
                            continue;
                        }
                        labels[at[target]] = Index(to);
                        ++changed;
                    }
            }
        }
        unresolved = left;
        if (found == left) return changed;
        context.report(0.05 * (1.0 - 1.0 / (pass + 2)), "label image: voxels touching along an edge");
    }
    return changed;
}

}  // namespace

const char* image_frame_name(ImageFrame frame) {
    switch (frame) {
        case ImageFrame::Lps: return "LPS";
        case ImageFrame::Ras: return "RAS";
        case ImageFrame::Unknown: break;
    }
    return "";
}

std::string label_material_name(const LabelImage& image, int32_t label) {
    for (const auto& [l, name] : image.names)
        if (l == label && !name.empty()) return name;
    if (label == 0) return kExteriorMaterial;
    return "label_" + std::to_string(label);
}

std::string label_image_problem(const LabelImage& image) {
    for (int d = 0; d < 3; ++d)
        if (image.size[d] < 1) return "the size along axis " + std::to_string(d) + " is " + std::to_string(image.size[d]) + " (must be >= 1)";
    // Cubes and so vertices: up to (n+1)^3; indices are int32.
    const double cubes = double(image.size[0] + 1) * double(image.size[1] + 1) * double(image.size[2] + 1);
    if (cubes > double(std::numeric_limits<int32_t>::max()) / 2 || double(image.num_voxels()) > 1e10)
        return "the image is too large (" + std::to_string(image.size[0]) + " x " + std::to_string(image.size[1]) + " x " +
               std::to_string(image.size[2]) + " voxels; bpm's indices are 32-bit)";
    if (image.compact()) {
        const std::vector<int32_t>& values = image.label_values;
        if (values.size() > 65536) return std::to_string(values.size()) + " label values (at most 65536)";
        for (size_t i = 1; i < values.size(); ++i)
            if (!(values[i - 1] < values[i])) return "the label values are not in increasing order";
        if (!std::binary_search(values.begin(), values.end(), 0)) return "the label values do not include 0 (the background)";
        const bool small = values.size() <= 256;
        const size_t n = small ? image.label_index8.size() : image.label_index16.size();
        if (int64_t(n) != image.num_voxels())
            return std::to_string(n) + " label indices (" + (small ? "label_index8" : "label_index16") + ") for " +
                   std::to_string(image.num_voxels()) + " voxels";
        size_t largest = 0;
        if (small)
            for (const uint8_t i : image.label_index8) largest = std::max<size_t>(largest, i);
        else
            for (const uint16_t i : image.label_index16) largest = std::max<size_t>(largest, i);
        if (largest >= values.size())
            return "a label index is " + std::to_string(largest) + ", beyond the " + std::to_string(values.size()) +
                   " label values";
    } else if (int64_t(image.labels.size()) != image.num_voxels()) {
        return std::to_string(image.labels.size()) + " labels for " + std::to_string(image.num_voxels()) + " voxels";
    }
    for (int d = 0; d < 3; ++d)
        if (!(image.spacing[d] > 0) || !std::isfinite(image.spacing[d]))
            return "the spacing along axis " + std::to_string(d) + " is not a positive finite number";
    if (!finite_all(image.origin.data(), 3)) return "the origin is not finite";
    if (!finite_all(image.direction.data(), 9)) return "the direction matrix is not finite";
    if (!(std::abs(det3(image.direction)) > 1e-12)) return "the direction matrix is not invertible (its axes are parallel or zero)";
    return {};
}

namespace {

// label_image_surface on the compact labels `idx` (positions in image.label_values).
template <class Index>
LabelSurface extract(LabelImage& image, Index* idx, const LabelSurfaceOptions& options, const Context& context) {
    const std::vector<int32_t>& values = image.label_values;
    const int32_t outside = int32_t(std::lower_bound(values.begin(), values.end(), 0) - values.begin());
    LabelSurface out;
    out.frame = image.frame;
    if (image.frame != ImageFrame::Unknown && options.frame != ImageFrame::Unknown && image.frame != options.frame) {
        // LPS <-> RAS: x and y negated, a rotation about z (det(direction) is kept, so the
        // triangles face the smaller label as before).
        for (int r = 0; r < 2; ++r) {
            image.origin[size_t(r)] = -image.origin[size_t(r)];
            for (int c = 0; c < 3; ++c) image.direction[3 * size_t(r) + size_t(c)] = -image.direction[3 * size_t(r) + size_t(c)];
        }
        out.frame = options.frame;
    }
    out.changed_voxels = resolve_edge_contacts(image, idx, outside, out.unresolved_contacts, context);
    const Grid<Index> g{image.size[0], image.size[1], image.size[2], idx, outside};
    // The distinct labels left (the background is there whenever the image touches its
    // border, which every image does: outside is background).
    {
        std::vector<uint8_t> seen(values.size(), 0);
        seen[size_t(outside)] = 1;
        const int64_t voxels = image.num_voxels();
        for (int64_t v = 0; v < voxels; ++v) seen[idx[v]] = 1;
        for (size_t i = 0; i < values.size(); ++i)
            if (seen[i]) out.labels.push_back(values[i]);
    }

    // ---- Pass 1: the cubes with more than one label, their sheets and vertices.
    std::vector<CubeRecord> cubes;
    std::vector<Vec3> position;   // index space
    std::vector<std::array<double, 6>> box;  // the cube each vertex must stay in: lo xyz, hi xyz
    const double m = options.margin;
    for (int64_t c = 0; c <= g.nz; ++c) {
        if ((c & 15) == 0) context.report(0.5 * double(c) / double(g.nz + 1), "label image: surface nets");
        for (int64_t b = 0; b <= g.ny; ++b)
            for (int64_t a = 0; a <= g.nx; ++a) {
                int32_t l[8];
                bool uniform = true;
                for (int v = 0; v < 8; ++v) {
                    l[v] = g.at(a - 1 + (v & 1), b - 1 + ((v >> 1) & 1), c - 1 + ((v >> 2) & 1));
                    uniform = uniform && l[v] == l[0];
                }
                if (uniform) continue;
                UnionFind12 uf;
                bool active[12];
                for (int e = 0; e < 12; ++e) active[e] = l[kEdgeEnds[e][0]] != l[kEdgeEnds[e][1]];
                for (int f = 0; f < 6; ++f) {
                    const int* cyc = kFaceCycle[f];
                    const int32_t fl[4] = {l[cyc[0]], l[cyc[1]], l[cyc[2]], l[cyc[3]]};
                    int masks[2];
                    const int ng = face_groups(fl, masks);
                    for (int gi = 0; gi < ng; ++gi) {
                        int first = -1;
                        for (int i = 0; i < 4; ++i) {
                            if (!(masks[gi] & (1 << i))) continue;
                            const int e = edge_between(cyc[i], cyc[(i + 1) % 4]);
                            if (first < 0) first = e;
                            else uf.unite(first, e);
                        }
                    }
                }
                CubeRecord rec;
                rec.key = g.cube_key(a, b, c);
                rec.first_vertex = static_cast<int32_t>(position.size());
                int root_component[12];
                int components = 0;
                for (int e = 0; e < 12; ++e) root_component[e] = -1;
                for (int e = 0; e < 12; ++e) {
                    rec.component[e] = 255;
                    if (!active[e]) continue;
                    const int r = uf.find(e);
                    if (root_component[r] < 0) root_component[r] = components++;
                    rec.component[e] = static_cast<uint8_t>(root_component[r]);
                }
                if (components > 1) ++out.split_vertices;
                // Each vertex starts at the mean of its edges' midpoints (the voxel faces it
                // stands for), which keeps the sheets of a split cube apart.
                const size_t first = position.size();
                position.resize(first + size_t(components), Vec3{0, 0, 0});
                std::vector<int> count(size_t(components), 0);
                for (int e = 0; e < 12; ++e) {
                    if (rec.component[e] == 255) continue;
                    const int u = kEdgeEnds[e][0], v = kEdgeEnds[e][1];
                    Vec3& p = position[first + rec.component[e]];
                    p[0] += double(a - 1) + 0.5 * ((u & 1) + (v & 1));
                    p[1] += double(b - 1) + 0.5 * (((u >> 1) & 1) + ((v >> 1) & 1));
                    p[2] += double(c - 1) + 0.5 * (((u >> 2) & 1) + ((v >> 2) & 1));
                    ++count[size_t(rec.component[e])];
                }
                for (int k = 0; k < components; ++k) {
                    Vec3& p = position[first + size_t(k)];
                    for (int d = 0; d < 3; ++d) p[d] /= count[size_t(k)];
                    box.push_back({double(a - 1) + m, double(b - 1) + m, double(c - 1) + m, double(a) - m,
                                   double(b) - m, double(c) - m});
                    for (int d = 0; d < 3; ++d) p[d] = std::clamp(p[d], box.back()[d], box.back()[d + 3]);
                }
                cubes.push_back(rec);
            }
    }
    if (position.empty()) return out;  // one label only: no interface
    const auto vertex_of = [&](int64_t a, int64_t b, int64_t c, int edge) -> int32_t {
        const int64_t key = g.cube_key(a, b, c);
        const auto it = std::lower_bound(cubes.begin(), cubes.end(), key,
                                         [](const CubeRecord& r, int64_t k) { return r.key < k; });
        if (it == cubes.end() || it->key != key || it->component[edge] == 255)
            throw Error("label_image_surface: internal error (a quad without its cube vertex)");
        return it->first_vertex + it->component[edge];
    };

    // ---- Pass 2: a quad for every face between voxels of different labels.
    struct Quad {
        int32_t v[4];  // counter-clockwise seen from the smaller label's side
        int32_t patch; // provisional id (order of first use)
    };
    std::vector<Quad> quads;
    std::unordered_map<int64_t, int32_t> pair_id;
    std::vector<std::array<int32_t, 2>> pairs;
    const int64_t n[3] = {g.nx, g.ny, g.nz};
    for (int d = 0; d < 3; ++d) {
        const int d1 = (d + 1) % 3, d2 = (d + 2) % 3;
        for (int64_t k = (d == 2 ? -1 : 0); k < n[2]; ++k) {
            if ((k & 15) == 0) context.report(0.5 + 0.2 * (d + double(k + 1) / double(n[2] + 1)) / 3, "label image: surface nets");
            for (int64_t j = (d == 1 ? -1 : 0); j < n[1]; ++j)
                for (int64_t i = (d == 0 ? -1 : 0); i < n[0]; ++i) {
                    const int64_t p[3] = {i, j, k};
                    int64_t q[3] = {i, j, k};
                    ++q[d];
                    const int32_t lp = g.at(p[0], p[1], p[2]), lq = g.at(q[0], q[1], q[2]);
                    if (lp == lq) continue;
                    const int32_t lo = std::min(lp, lq), hi = std::max(lp, lq);
                    const int64_t pk = (int64_t(uint32_t(lo)) << 32) | int64_t(uint32_t(hi));
                    auto [it, added] = pair_id.emplace(pk, int32_t(pairs.size()));
                    if (added) pairs.push_back({lo, hi});
                    Quad quad;
                    quad.patch = it->second;
                    // The 4 cubes around the edge p-q, counter-clockwise seen from +d.
                    static constexpr int kOffsets[4][2] = {{-1, -1}, {0, -1}, {0, 0}, {-1, 0}};
                    for (int s = 0; s < 4; ++s) {
                        int64_t cube_min[3];
                        cube_min[d] = p[d];
                        cube_min[d1] = p[d1] + kOffsets[s][0];
                        cube_min[d2] = p[d2] + kOffsets[s][1];
                        int local[3];
                        local[d] = 0;
                        local[d1] = int(p[d1] - cube_min[d1]);
                        local[d2] = int(p[d2] - cube_min[d2]);
                        const int v = local[0] + 2 * local[1] + 4 * local[2];
                        quad.v[s] = vertex_of(cube_min[0] + 1, cube_min[1] + 1, cube_min[2] + 1, edge_from(v, d));
                    }
                    // Normal +d points from p to q: right when q has the smaller label.
                    if (lq > lp) std::swap(quad.v[1], quad.v[3]);
                    quads.push_back(quad);
                }
        }
    }
    cubes.clear();
    cubes.shrink_to_fit();

    // Patches numbered by increasing label pair.
    std::vector<int32_t> order(pairs.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = int32_t(i);
    std::sort(order.begin(), order.end(), [&](int32_t x, int32_t y) { return pairs[size_t(x)] < pairs[size_t(y)]; });
    std::vector<int32_t> patch_of(pairs.size());
    for (size_t r = 0; r < order.size(); ++r) patch_of[size_t(order[r])] = int32_t(r);
    for (Quad& quad : quads) quad.patch = patch_of[size_t(quad.patch)];
    for (size_t r = 0; r < order.size(); ++r) {
        const int32_t lo = values[size_t(pairs[size_t(order[r])][0])], hi = values[size_t(pairs[size_t(order[r])][1])];
        out.patch_labels.push_back({lo, hi});
        PatchInfo info;
        info.patch = int32_t(r);
        info.front = label_material_name(image, lo);
        info.back = label_material_name(image, hi);
        info.name = info.back + "|" + info.front;
        info.oriented = true;
        out.patch_info.push_back(info);
    }

    // ---- Smoothing stencils: the edges of the quads, junction edges (3+ quads) apart.
    const size_t nv = position.size();
    std::vector<uint64_t> edges;
    edges.reserve(quads.size() * 4);
    for (const Quad& quad : quads)
        for (int s = 0; s < 4; ++s) {
            const uint32_t u = uint32_t(quad.v[s]), w = uint32_t(quad.v[(s + 1) % 4]);
            edges.push_back((uint64_t(std::min(u, w)) << 32) | std::max(u, w));
        }
    std::sort(edges.begin(), edges.end());
    std::vector<int64_t> offset(nv + 1, 0);
    std::vector<int32_t> neighbour;
    std::vector<uint8_t> junction_edge;
    {
        // (vertex, neighbour, junction) triples, both directions.
        std::vector<std::pair<uint64_t, uint8_t>> half;
        for (size_t i = 0; i < edges.size();) {
            size_t j = i;
            while (j < edges.size() && edges[j] == edges[i]) ++j;
            const uint8_t junction = j - i >= 3 ? 1 : 0;
            const uint64_t u = edges[i] >> 32, w = edges[i] & 0xffffffffu;
            half.push_back({(u << 32) | w, junction});
            half.push_back({(w << 32) | u, junction});
            i = j;
        }
        std::vector<uint64_t>().swap(edges);
        std::sort(half.begin(), half.end());
        neighbour.resize(half.size());
        junction_edge.resize(half.size());
        for (size_t h = 0; h < half.size(); ++h) {
            ++offset[(half[h].first >> 32) + 1];
            neighbour[h] = int32_t(half[h].first & 0xffffffffu);
            junction_edge[h] = half[h].second;
        }
        for (size_t v = 0; v < nv; ++v) offset[v + 1] += offset[v];
    }
    // Per vertex: 0 = all neighbours, 1 = its two junction neighbours, 2 = fixed.
    std::vector<uint8_t> stencil(nv, 0);
    for (size_t v = 0; v < nv; ++v) {
        int junctions = 0;
        for (int64_t h = offset[v]; h < offset[v + 1]; ++h) junctions += junction_edge[size_t(h)];
        if (junctions > 0) {
            ++out.junction_vertices;
            stencil[v] = junctions == 2 ? 1 : 2;
        }
    }
    const std::vector<Vec3> unsmoothed(position);
    std::vector<Vec3> next(position);
    for (int it = 0; it < options.smoothing_iterations; ++it) {
        context.report(0.7 + 0.25 * double(it) / options.smoothing_iterations, "label image: smoothing");
        for (size_t v = 0; v < nv; ++v) {
            if (stencil[v] == 2) continue;
            Vec3 sum{0, 0, 0};
            int count = 0;
            for (int64_t h = offset[v]; h < offset[v + 1]; ++h) {
                if (stencil[v] == 1 && !junction_edge[size_t(h)]) continue;
                const Vec3& x = position[size_t(neighbour[size_t(h)])];
                sum[0] += x[0], sum[1] += x[1], sum[2] += x[2];
                ++count;
            }
            if (count == 0) continue;
            for (int d = 0; d < 3; ++d) {
                const double target = position[v][d] + options.relaxation * (sum[d] / count - position[v][d]);
                next[v][d] = std::clamp(target, box[v][d], box[v][d + 3]);
            }
        }
        std::swap(position, next);
        next = position;
    }
    std::vector<Vec3>().swap(next);
    std::vector<std::array<double, 6>>().swap(box);

    // ---- Model space, then two triangles per quad (the diagonal: see triangulate).
    Surface& s = out.surface;
    s.vertices.resize(nv);
    const auto& D = image.direction;
    const auto place = [&](size_t v) {
        const double x = position[v][0] * image.spacing[0], y = position[v][1] * image.spacing[1],
                     z = position[v][2] * image.spacing[2];
        for (int r = 0; r < 3; ++r) s.vertices[v][r] = image.origin[r] + D[3 * r] * x + D[3 * r + 1] * y + D[3 * r + 2] * z;
    };
    for (size_t v = 0; v < nv; ++v) place(v);
    const bool reflected = det3(D) < 0;
    s.triangles.resize(quads.size() * 2);
    s.patches.resize(quads.size() * 2);
    // A vertex in index space scaled by the spacing: model space but for a rotation or
    // reflection and a translation, so shapes measured here are those of model space, and
    // the same bits whatever the origin, direction or output frame (LPS or RAS files of one
    // segmentation give the same triangles).
    const auto scaled = [&](int32_t v) {
        const Vec3& p = position[size_t(v)];
        return Vec3{p[0] * image.spacing[0], p[1] * image.spacing[1], p[2] * image.spacing[2]};
    };
    const auto triangulate = [&](size_t q) {
        const Quad& quad = quads[q];
        Vec3 y[4];
        for (int k = 0; k < 4; ++k) y[k] = scaled(quad.v[k]);
        // The diagonal whose two triangles have the better worst aspect ratio (of shapes
        // equal but for rounding, the shorter): where a junction line runs through three
        // vertices of the quad, smoothing straightens them, and the diagonal between the
        // line's two ends made a triangle of no area (R/r 1e12 on noisy images).
        const auto worst = [&](int a) {
            return std::max(aspect_ratio(y[a], y[(a + 1) % 4], y[(a + 2) % 4]),
                            aspect_ratio(y[a], y[(a + 2) % 4], y[(a + 3) % 4]));
        };
        const double w0 = worst(0), w1 = worst(1);
        const Vec3 g02 = y[2] - y[0], g13 = y[3] - y[1];
        const double d02 = dot(g02, g02), d13 = dot(g13, g13);
        const bool tie = !(std::abs(w1 - w0) > 1e-9 * std::min(w0, w1));  // two infinities too
        int start = (tie ? d13 < d02 : w1 < w0) ? 1 : 0;  // the diagonal start -- start + 2
        const Vec3* x[4];
        for (int k = 0; k < 4; ++k) x[k] = &s.vertices[size_t(quad.v[k])];
        const auto flat = [&](int a) {
            return collinear3d(*x[a], *x[(a + 1) % 4], *x[(a + 2) % 4]) || collinear3d(*x[a], *x[(a + 2) % 4], *x[(a + 3) % 4]);
        };
        if (flat(start) && !flat(1 - start)) start = 1 - start;
        const int32_t a = quad.v[start], b = quad.v[(start + 1) % 4], c = quad.v[(start + 2) % 4],
                      e = quad.v[(start + 3) % 4];
        s.triangles[2 * q] = reflected ? Tri{a, c, b} : Tri{a, b, c};
        s.triangles[2 * q + 1] = reflected ? Tri{a, e, c} : Tri{a, c, e};
        s.patches[2 * q] = s.patches[2 * q + 1] = quad.patch;
    };
    for (size_t q = 0; q < quads.size(); ++q) triangulate(q);

    // ---- Smoothing can spoil what the centroids had right. (1) It can fold the surface
    // through itself where sheets are close (labels touching at corners, thin layers).
    // (2) It can make slivers of no diagonal's help: along junction lines at the image
    // border the line is straightened while its vertices stay in boxes that alternate
    // across a cube face, three of them nearly in a line in a quad of four junction
    // vertices (R/r 100 on noisy images). The four vertices of every quad with a triangle
    // in a crossing pair or of R/r > kMaxAspect go back towards where smoothing found them
    // (the centroids, which do not cross; their triangles measured R/r <= 5.4 on noisy
    // images), half way per round at first, then all the way; the quads around them are
    // split again. Once all the way, every round moves a vertex that was not yet back (a
    // quad of four vertices back is split as the centroids' was: it is no sliver, and two
    // such do not cross), so the rounds end, and then nothing crosses and the worst R/r is
    // at most max(kMaxAspect, the centroids').
    if (options.smoothing_iterations > 0) {
        constexpr double kMaxAspect = 30;  // simplify's default triangle shape limit
        std::vector<std::vector<int32_t>> quads_of;  // built on the first need only
        std::vector<uint8_t> back(nv, 0), slivered(nv, 0);
        // Moves the vertices marked in `back` (and clears the marks), marks those that moved
        // in `moved_mark` if given; returns how many moved.
        const auto move_back = [&](double keep, std::vector<uint8_t>* moved_mark) {
            int64_t moved = 0;
            std::vector<size_t> touched;
            if (quads_of.empty() && std::find(back.begin(), back.end(), uint8_t(1)) != back.end()) {
                quads_of.resize(nv);
                for (size_t q = 0; q < quads.size(); ++q)
                    for (const int32_t v : quads[q].v) quads_of[size_t(v)].push_back(int32_t(q));
            }
            for (size_t v = 0; v < nv; ++v) {
                if (!back[v]) continue;
                back[v] = 0;
                if (position[v] == unsmoothed[v]) continue;
                for (int d = 0; d < 3; ++d) position[v][d] = unsmoothed[v][d] + keep * (position[v][d] - unsmoothed[v][d]);
                place(v);
                for (const int32_t q : quads_of[v]) touched.push_back(size_t(q));
                if (moved_mark) (*moved_mark)[v] = 1;
                ++moved;
            }
            std::sort(touched.begin(), touched.end());
            touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
            for (const size_t q : touched) triangulate(q);
            return moved;
        };
        const auto mark_slivers = [&]() {
            // All four vertices of the quad: a quad of unmoved vertices is split as the
            // centroids' was, so the bound below holds.
            for (size_t q = 0; q < quads.size(); ++q)
                for (const size_t t : {2 * q, 2 * q + 1}) {
                    const Tri& tri = s.triangles[t];
                    if (aspect_ratio(scaled(tri[0]), scaled(tri[1]), scaled(tri[2])) > kMaxAspect) {
                        for (const int32_t v : quads[q].v) back[size_t(v)] = 1;
                        break;
                    }
                }
        };
        for (int round = 0;; ++round) {
            for (int sliver_round = 0;; ++sliver_round) {
                mark_slivers();
                if (move_back(sliver_round < 2 ? 0.5 : 0.0, &slivered) == 0) break;
            }
            CheckOptions check;
            check.max_problems = size_t(1) << 40;
            const CheckResult r = check_intersections(s, check);
            if (r.passed) break;
            for (const CheckProblem& p : r.problems)
                for (const auto& [kind, id] : p.ids)
                    if (kind == "triangle" && id >= 0 && id < int64_t(s.triangles.size()))
                        for (const int32_t v : quads[size_t(id) / 2].v) back[size_t(v)] = 1;
            const int64_t moved = move_back(round < 6 ? 0.5 : 0.0, nullptr);
            if (moved == 0) break;  // the centroids' own crossing (there is none): no use going on
            out.unsmoothed_vertices = moved;
        }
        out.sliver_vertices = std::count(slivered.begin(), slivered.end(), uint8_t(1));
    }
    context.report(1.0, "label image: surface nets");
    return out;
}

}  // namespace

void compact_labels(LabelImage& image) {
    std::vector<int32_t> values;
    {
        std::unordered_set<int32_t> seen = {0};
        int32_t last = 0;
        for (const int32_t l : image.labels)
            if (l != last) {
                last = l;
                if (seen.insert(l).second && seen.size() > 65536)
                    throw InputError("label image", "more than 65536 distinct labels: an intensity image, not a "
                                                    "segmentation?");
            }
        values.assign(seen.begin(), seen.end());
        std::sort(values.begin(), values.end());
    }
    const auto fill = [&](auto& index) {
        index.resize(image.labels.size());
        int32_t last = values[0];
        size_t at = 0;
        for (size_t v = 0; v < image.labels.size(); ++v) {
            const int32_t l = image.labels[v];
            if (l != last) {
                last = l;
                at = size_t(std::lower_bound(values.begin(), values.end(), l) - values.begin());
            }
            index[v] = static_cast<typename std::decay_t<decltype(index)>::value_type>(at);
        }
    };
    image.label_index8.clear();
    image.label_index16.clear();
    if (values.size() <= 256) fill(image.label_index8);
    else fill(image.label_index16);
    image.label_values = std::move(values);
    std::vector<int32_t>().swap(image.labels);
}

LabelSurface label_image_surface(LabelImage image, const LabelSurfaceOptions& options, const Context& context) {
    if (std::string problem = label_image_problem(image); !problem.empty()) throw InputError("label image", problem);
    if (!(options.relaxation > 0 && options.relaxation <= 1) || !(options.margin > 0 && options.margin < 0.5) ||
        options.smoothing_iterations < 0)
        throw InputError("label image", "label surface options out of range (relaxation in (0, 1], margin in (0, 0.5), "
                                        "iterations >= 0)");
    if (!image.compact()) compact_labels(image);
    if (image.label_values.size() <= 256) return extract(image, image.label_index8.data(), options, context);
    return extract(image, image.label_index16.data(), options, context);
}

}  // namespace bpm
