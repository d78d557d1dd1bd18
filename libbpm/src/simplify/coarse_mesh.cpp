#include "simplify/coarse_mesh.h"

#include <algorithm>
#include <cmath>

#include "core/crease_chains.h"
#include "core/directed_edge.h"
#include "core/huge_pages.h"

namespace bpm::detail {

CoarseMesh::CoarseMesh(const Surface& original) : CoarseMesh(original, EdgeUses(original)) {}

CoarseMesh::CoarseMesh(const Surface& original, const EdgeUses& uses)
    : positions_(&original.vertices),
      patches_(original.patches),
      alive_(original.triangles.size(), 1),
      initially_flipped_(original.triangles.size(), 0),
      vertex_triangles_(original.vertices.size()),
      neighbour_bits_(original.vertices.size(), 0),
      feature_degree_(original.vertices.size(), 0) {
    reserve_huge_pages(triangles_, original.triangles.size());
    triangles_.assign(original.triangles.begin(), original.triangles.end());
    if (patches_.size() != triangles_.size()) patches_.assign(triangles_.size(), 0);
    // One patch (the common case): no per-triangle patch until a triangle with another.
    if (std::all_of(patches_.begin(), patches_.end(), [&](int32_t p) { return p == patches_[0]; })) {
        uniform_patch_ = patches_.empty() ? 0 : patches_[0];
        decltype(patches_)().swap(patches_);
    }
    for (int32_t t = 0; t < int32_t(triangles_.size()); ++t) {
        const Tri& c = triangles_[t];
        const uint64_t bits = vertex_bit(c[0]) | vertex_bit(c[1]) | vertex_bit(c[2]);
        for (int32_t v : c) {
            vertex_triangles_.push_back(v, t);
            neighbour_bits_[v] |= bits;
        }
    }
    num_alive_ = static_cast<int32_t>(triangles_.size());
    for (int32_t v = 0; v < int32_t(vertex_triangles_.num_vertices()); ++v) num_vertices_alive_ += vertex_alive(v) ? 1 : 0;

    // Orient each sheet consistently by a breadth-first walk over edges with exactly two
    // triangles. On a non-orientable sheet the walk leaves some edges inconsistent;
    // that only restricts which vertices can be removed later.
    // across[3 t + k]: the other triangle of the edge of side k of original triangle t
    // (corners k, k + 1) when that edge has exactly two, else -1. Read off the grouped
    // sides: the walk used to collect each side's triangles from a corner's triangle
    // list (edge_triangles), ~4 % of the floor on 832k triangles.
    std::vector<int32_t>& across = across_;
    reserve_huge_pages(across, 3 * triangles_.size());
    across.assign(3 * triangles_.size(), -1);
    uses.for_each_edge([&](int32_t a, int32_t b, const EdgeUses::Use* at, size_t count) {
        if (count != 2) return;
        for (int i = 0; i < 2; ++i) {
            const int32_t t = at[i].triangle();
            const Tri& c = triangles_[size_t(t)];
            for (int k = 0; k < 3; ++k)
                if ((c[k] == a && c[(k + 1) % 3] == b) || (c[k] == b && c[(k + 1) % 3] == a))
                    across[3 * size_t(t) + size_t(k)] = at[1 - i].triangle();
        }
    });
    std::vector<uint8_t> visited(triangles_.size(), 0);
    std::vector<int32_t> queue;
    for (int32_t seed = 0; seed < int32_t(triangles_.size()); ++seed) {
        if (visited[seed]) continue;
        visited[seed] = 1;
        queue.assign(1, seed);
        for (size_t head = 0; head < queue.size(); ++head) {
            const int32_t t = queue[head];
            for (int k = 0; k < 3; ++k) {
                const int32_t a = triangles_[t][k], b = triangles_[t][(k + 1) % 3];
                // Stored side k of a flipped triangle (c0, c2, c1) is original side 2 - k.
                const int32_t n = across[3 * size_t(t) + size_t(initially_flipped_[t] ? 2 - k : k)];
                if (n < 0 || visited[n]) continue;
                visited[n] = 1;
                // A consistent neighbour traverses the shared edge as b->a.
                if (runs_from(triangles_[n], a, b)) {
                    std::swap(triangles_[n][1], triangles_[n][2]);
                    initially_flipped_[n] = 1;
                }
                queue.push_back(n);
            }
        }
    }
    // After the orientation: the corners in their stored order.
    reserve_huge_pages(aspects_, triangles_.size());
    aspects_.resize(triangles_.size());
    for (size_t t = 0; t < triangles_.size(); ++t) {
        const Tri& c = triangles_[t];
        aspects_[t] = aspect_ratio((*positions_)[c[0]], (*positions_)[c[1]], (*positions_)[c[2]]);
    }
}

// The triangles on both a and b, by merging their sorted lists as has_edge() does: the
// same triangles in the same (increasing) order as testing the corners of each triangle
// at a for b, without those scattered reads (mark_feature_edges asks for every edge:
// ~5 % of the floor on 832k triangles, most of it waiting for the corners).
void CoarseMesh::edge_triangles(int32_t a, int32_t b, std::vector<int32_t>& out) const {
    out.clear();
    for_each_common(vertex_triangles_.of(a), vertex_triangles_.of(b), [&](int32_t t) {
        out.push_back(t);
        return true;
    });
}

// The triangle lists are sorted by id (ids only grow: a new triangle goes to the end,
// a removed one is erased in place), so a triangle on both a and b is found by merging
// the two short lists, without reading the triangles' corners (scattered in memory:
// these lookups run for every ear a planner considers).
bool CoarseMesh::has_edge(int32_t a, int32_t b) const {
    if (!(neighbour_bits_[a] & vertex_bit(b))) return false;
    bool found = false;
    for_each_common(vertex_triangles_.of(a), vertex_triangles_.of(b), [&](int32_t) {
        found = true;
        return false;  // one is enough
    });
    return found;
}

int32_t CoarseMesh::find_triangle(int32_t a, int32_t b, int32_t c) const {
    if ((neighbour_bits_[a] & (vertex_bit(b) | vertex_bit(c))) != (vertex_bit(b) | vertex_bit(c))) return -1;
    const auto la = vertex_triangles_.of(a);
    const auto lb = vertex_triangles_.of(b);
    const auto lc = vertex_triangles_.of(c);
    auto i = la.begin(), j = lb.begin(), k = lc.begin();
    while (i != la.end() && j != lb.end() && k != lc.end()) {
        const int32_t t = std::max({*i, *j, *k});
        if (*i == t && *j == t && *k == t) return t;
        while (i != la.end() && *i < t) ++i;
        while (j != lb.end() && *j < t) ++j;
        while (k != lc.end() && *k < t) ++k;
    }
    return -1;
}

void CoarseMesh::set_feature_edge(int32_t a, int32_t b, Feature kind) { mark(a, b, kind); }

void CoarseMesh::mark(int32_t a, int32_t b, Feature kind) {
    auto it = feature_edges_.find(edge_key(a, b));
    if (it != feature_edges_.end()) {
        if (kind != Feature::None) {
            it->second = kind;
            return;
        }
        feature_edges_.erase(it);
        --feature_degree_[a];
        --feature_degree_[b];
    } else if (kind != Feature::None) {
        feature_edges_[edge_key(a, b)] = kind;
        ++feature_degree_[a];
        ++feature_degree_[b];
    }
}

void CoarseMesh::reserve_triangles(size_t ids) {
    if (ids <= triangles_.capacity()) return;
    triangles_.reserve(ids);
    if (!patches_.empty()) patches_.reserve(ids);
    alive_.reserve(ids);
    if (keep_aspects_) aspects_.reserve(ids);
}

void CoarseMesh::grow_triangle_arrays() {
    const size_t n = triangles_.size();
    reserve_triangles(n + std::max<size_t>(n / 8, 1024));
}

int32_t CoarseMesh::add_triangle(const Tri& corners, int32_t patch) {
    const int32_t t = static_cast<int32_t>(triangles_.size());
    if (triangles_.size() == triangles_.capacity()) grow_triangle_arrays();
    if (patches_.empty() && patch != uniform_patch_) {
        patches_.reserve(triangles_.capacity());
        patches_.assign(triangles_.size(), uniform_patch_);
    }
    triangles_.push_back(corners);
    if (!patches_.empty()) patches_.push_back(patch);
    alive_.push_back(1);
    if (keep_aspects_)
        aspects_.push_back(aspect_ratio((*positions_)[corners[0]], (*positions_)[corners[1]], (*positions_)[corners[2]]));
    const uint64_t bits = vertex_bit(corners[0]) | vertex_bit(corners[1]) | vertex_bit(corners[2]);
    for (int32_t v : corners) {
        if (vertex_triangles_.empty(v)) ++num_vertices_alive_;
        vertex_triangles_.push_back(v, t);
        neighbour_bits_[v] |= bits;
    }
    ++num_alive_;
    return t;
}

void CoarseMesh::remove_triangle(int32_t t) {
    if (!alive_[t]) return;
    alive_[t] = 0;
    --num_alive_;
    for (int32_t v : triangles_[t]) {
        vertex_triangles_.erase(v, t);
        if (vertex_triangles_.empty(v)) --num_vertices_alive_;
    }
    // A bit may stand for a vertex of t only: recount the corners' bits from the
    // triangles they keep (their stars were just read by the planner: cheap).
    for (int32_t v : triangles_[t]) set_neighbour_bits(v);
}

void CoarseMesh::remove_triangles(const std::vector<int32_t>& ts) {
    // The corners to recount: the first of each distinct one (a star has few).
    int32_t corners[64];
    size_t count = 0;
    bool overflow = false;
    for (int32_t t : ts) {
        if (!alive_[t]) continue;
        alive_[t] = 0;
        --num_alive_;
        for (int32_t v : triangles_[t]) {
            vertex_triangles_.erase(v, t);
            if (vertex_triangles_.empty(v)) --num_vertices_alive_;
            if (std::find(corners, corners + count, v) != corners + count) continue;
            if (count < 64)
                corners[count++] = v;
            else
                overflow = true;
        }
    }
    if (overflow) {  // a very large star: recount every corner of every triangle
        for (int32_t t : ts)
            for (int32_t v : triangles_[t]) set_neighbour_bits(v);
        return;
    }
    for (size_t i = 0; i < count; ++i) set_neighbour_bits(corners[i]);
}

void CoarseMesh::set_neighbour_bits(int32_t v) {
    uint64_t bits = 0;
    for (int32_t u : vertex_triangles_.of(v))
        for (int32_t x : triangles_[u]) bits |= vertex_bit(x);
    neighbour_bits_[v] = bits;
}

void CoarseMesh::mark_feature_edges(const CreaseRule& rule) {
    // First every edge in the order of the walk, then the marks in that order (the order
    // the feature edges went into feature_edges_ before the chains: the same map).
    struct WalkedEdge {
        int32_t a, b;
        int32_t sheet;  // index into `sheet`; -1: a hard edge (not two triangles of one patch)
    };
    std::vector<WalkedEdge> walk;
    std::vector<SheetEdge> sheet;
    std::vector<int32_t> around;
    // An edge per side and a half (closed surfaces), reserved: grown by doubling, `sheet`
    // was ~3 % of the 832k-triangle floor (--ratio 1), most of it page faults in the copies.
    reserve_huge_pages(walk, 3 * size_t(num_alive_) / 2 + 16);
    reserve_huge_pages(sheet, 3 * size_t(num_alive_) / 2 + 16);
    // Nothing added or removed since the constructor: across_ still tells each side's
    // other triangle, so the edges with two triangles (nearly all) need no merge of the
    // corners' triangle lists (edge_triangles, ~2 % of that floor).
    const bool fresh = across_.size() == 3 * triangles_.size() && size_t(num_alive_) == triangles_.size();
    // Edge (a, b) with its triangles t0 and t1 (-1: not exactly two): hard unless two of one patch.
    auto walk_edge = [&](int32_t a, int32_t b, int32_t t0, int32_t t1) {
        if (t1 < 0 || patch(t0) != patch(t1)) {
            walk.push_back({a, b, -1});
            return;
        }
        walk.push_back({a, b, int32_t(sheet.size())});
        sheet.push_back({a, b, triangles_[t0], triangles_[t1]});
    };
    for (int32_t t = 0; t < int32_t(triangles_.size()); ++t) {
        if (!alive_[t]) continue;
        for (int k = 0; k < 3; ++k) {
            const int32_t a = triangles_[t][k], b = triangles_[t][(k + 1) % 3];
            // Stored side k of a flipped triangle (c0, c2, c1) is original side 2 - k.
            const int32_t n = fresh ? across_[3 * size_t(t) + size_t(initially_flipped_[t] ? 2 - k : k)] : -1;
            if (n >= 0 && n != t) {
                // Its two triangles are t and n, the first of them the smaller.
                if (n > t) walk_edge(a, b, t, n);
                continue;
            }
            // Each edge once, from the first triangle that has it: the triangle lists
            // are in increasing id (nothing was removed yet), so that is around[0].
            // (A triangle with a repeated corner may meet an edge twice; marking is
            // idempotent.)
            edge_triangles(a, b, around);
            if (around.empty() || around[0] != t) continue;
            walk_edge(a, b, around[0], around.size() == 2 ? around[1] : -1);
        }
    }
    decltype(across_)().swap(across_);
    const std::vector<uint8_t> crease = find_creases(*positions_, sheet, rule);
    for (const WalkedEdge& e : walk) {
        if (e.sheet < 0)
            mark(e.a, e.b, Feature::Hard);
        else if (crease[size_t(e.sheet)])
            mark(e.a, e.b, Feature::Crease);
    }
}

void CoarseMesh::mark_corners(double feature_angle_degrees, double min_crease_length, bool keep) {
    const auto& p = *positions_;
    const size_t nv = vertex_triangles_.num_vertices();
    std::vector<int32_t> hard(nv, 0);
    // Crease edges per vertex (CSR), for walking along crease lines.
    std::vector<int32_t> offsets(nv + 1, 0), ends;
    for (const auto& [key, kind] : feature_edges_) {
        const int32_t a = int32_t(key >> 32), b = int32_t(key & 0xffffffffu);
        if (kind == Feature::Hard) {
            ++hard[a];
            ++hard[b];
        } else {
            ++offsets[a + 1];
            ++offsets[b + 1];
        }
    }
    for (size_t v = 0; v < nv; ++v) offsets[v + 1] += offsets[v];
    ends.resize(size_t(offsets[nv]));
    {
        std::vector<int32_t> fill(offsets.begin(), offsets.end() - 1);
        for (const auto& [key, kind] : feature_edges_) {
            if (kind != Feature::Crease) continue;
            const int32_t a = int32_t(key >> 32), b = int32_t(key & 0xffffffffu);
            ends[size_t(fill[a]++)] = b;
            ends[size_t(fill[b]++)] = a;
        }
    }
    auto crease_degree = [&](int32_t v) { return offsets[v + 1] - offsets[v]; };
    // Does the crease line leaving v towards w run at least min_crease_length (through
    // vertices on exactly two creases and no hard edge)? Noise on scanned surfaces makes
    // short creases that meet and end everywhere; a crease shorter than that is not a
    // line whose corners must stay.
    auto long_line = [&](int32_t v, int32_t w) {
        double length = 0.0;
        int32_t from = v;
        while (true) {
            length += distance(p[from], p[w]);
            if (length >= min_crease_length) return true;
            if (w == v || crease_degree(w) != 2 || hard[w] != 0) return false;
            const int32_t a = ends[size_t(offsets[w])], b = ends[size_t(offsets[w] + 1)];
            const int32_t next = a == from ? b : a;
            from = w;
            w = next;
        }
    };
    // Defect of a circular cone whose generators' normals on opposite sides are the
    // feature angle apart: half-angle alpha = 90 - theta / 2, defect 2 pi (1 - sin alpha).
    const double theta = feature_angle_degrees * M_PI / 180.0;
    const double cone_defect = 2.0 * M_PI * (1.0 - std::cos(0.5 * theta));
    corners_.assign(nv, uint8_t(Corner::None));
    for (size_t v = 0; v < nv; ++v) {
        if (hard[v] == 1 || hard[v] >= 3) {  // kept by the classification of its star
            ++hard_feature_vertices_;
            continue;
        }
        if (crease_degree(int32_t(v)) == 0) continue;
        int32_t lines = 0;  // creases at v that are long lines
        for (int32_t i = offsets[v]; i < offsets[v + 1]; ++i) lines += long_line(int32_t(v), ends[size_t(i)]);
        if (lines == 0) continue;
        if (hard[v] + lines >= 3) {
            corners_[v] = uint8_t(Corner::Junction);
            continue;
        }
        if (hard[v] != 0 || crease_degree(int32_t(v)) != 1) continue;
        // A crease ends here, inside one sheet (no hard edge: the star is a disk).
        double angles = 0.0;
        for (int32_t t : vertex_triangles_.of(v)) {
            const Tri& c = triangles_[t];
            int k = 0;
            while (c[k] != int32_t(v)) ++k;
            const Vec3 e1 = p[c[(k + 1) % 3]] - p[v], e2 = p[c[(k + 2) % 3]] - p[v];
            angles += std::atan2(norm(cross(e1, e2)), dot(e1, e2));
        }
        if (std::abs(2.0 * M_PI - angles) >= cone_defect) corners_[v] = uint8_t(Corner::ConeEnd);
    }
    for (uint8_t c : corners_) ++corner_counts_[c];
    if (!keep) corners_.clear();
}

Surface CoarseMesh::to_surface(std::vector<int32_t>& vertex_origin) const {
    Surface s;
    std::vector<int32_t> index(vertex_triangles_.num_vertices(), -1);
    vertex_origin.clear();
    vertex_origin.reserve(size_t(num_vertices_alive_));
    reserve_huge_pages(s.vertices, size_t(num_vertices_alive_));
    reserve_huge_pages(s.triangles, size_t(num_alive_));
    s.patches.reserve(size_t(num_alive_));
    // Vertices in increasing original id, so that the output is deterministic.
    for (int32_t v = 0; v < int32_t(vertex_triangles_.num_vertices()); ++v) {
        if (vertex_triangles_.empty(v)) continue;
        index[v] = static_cast<int32_t>(vertex_origin.size());
        vertex_origin.push_back(v);
        s.vertices.push_back((*positions_)[v]);
    }
    for (size_t i = 0; i < triangles_.size(); ++i) {
        if (!compacted_ && !alive_[i]) continue;  // after shrink_to_fit() every stored one is alive
        s.triangles.push_back({index[triangles_[i][0]], index[triangles_[i][1]], index[triangles_[i][2]]});
        s.patches.push_back(patches_.empty() ? uniform_patch_ : patches_[i]);
    }
    return s;
}

void CoarseMesh::alive_triangles(std::vector<int32_t>& out) const {
    out.clear();
    if (compacted_) {
        out = kept_;
        return;
    }
    out.reserve(size_t(num_alive_));
    for (int32_t t = 0; t < int32_t(triangles_.size()); ++t)
        if (alive_[t]) out.push_back(t);
}

void CoarseMesh::shrink_to_fit() {
    decltype(across_)().swap(across_);
    vertex_triangles_.compact();
    if (compacted_) return;
    std::vector<int32_t> kept;
    alive_triangles(kept);
    std::vector<Tri> triangles(kept.size());
    std::vector<int32_t> patches(patches_.empty() ? 0 : kept.size());
    std::vector<double> aspects(aspects_.empty() ? 0 : kept.size());
    for (size_t i = 0; i < kept.size(); ++i) {
        triangles[i] = triangles_[size_t(kept[i])];
        if (!patches.empty()) patches[i] = patches_[size_t(kept[i])];
        if (!aspects.empty()) aspects[i] = aspects_[size_t(kept[i])];
    }
    capacity_ = static_cast<int32_t>(triangles_.size());
    triangles_ = std::move(triangles);
    patches_ = std::move(patches);
    aspects_ = std::move(aspects);
    decltype(alive_)().swap(alive_);
    kept_ = std::move(kept);
    compacted_ = true;
    // Only the planners and the flips ask for edges, features, corners and the initial
    // orientation (the export has its own orientation signs): ~1.5 MB at 208k triangles.
    decltype(neighbour_bits_)().swap(neighbour_bits_);
    decltype(feature_degree_)().swap(feature_degree_);
    decltype(feature_edges_)().swap(feature_edges_);
    decltype(corners_)().swap(corners_);
    decltype(initially_flipped_)().swap(initially_flipped_);
}

}  // namespace bpm::detail
