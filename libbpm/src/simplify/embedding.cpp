#include "simplify/embedding.h"

#include <algorithm>

#include "core/huge_pages.h"

namespace bpm::detail {

void Embedding::init_identity(const Surface& s, int32_t triangle_capacity) {
    init_identity(s, triangle_capacity, EdgeUses(s));
}

void Embedding::init_identity(const Surface& s, int32_t triangle_capacity, const EdgeUses& uses) {
    original = &s;
    const int32_t nv = s.num_vertices();
    // for_each_edge visits the edges in increasing (u, w) order, each edge's triangles in
    // increasing order: the sorted edges and the edge -> triangles CSR as they are read.
    // (A sort of all 3 T sides and a find_edge per side twice were ~7 % of the floor.)
    edges.clear();
    reserve_huge_pages(edges, uses.num_edges());
    smaller_vertex_edges.assign(nv + 1, 0);
    edge_triangle_offsets.assign(1, 0);
    reserve_huge_pages(edge_triangle_offsets, uses.num_edges() + 1);
    edge_triangles.clear();
    reserve_huge_pages(edge_triangles, uses.num_uses());
    uses.for_each_edge([&](int32_t u, int32_t w, const EdgeUses::Use* at, size_t count) {
        edges.push_back({u, w});
        ++smaller_vertex_edges[u + 1];
        for (size_t i = 0; i < count; ++i) edge_triangles.push_back(at[i].triangle());
        edge_triangle_offsets.push_back(int32_t(edge_triangles.size()));
    });
    // The edges (u, w > u) are sorted, so those whose smaller vertex is u form one range.
    for (int32_t v = 0; v < nv; ++v) smaller_vertex_edges[v + 1] += smaller_vertex_edges[v];

    vertex_edge_offsets.assign(nv + 1, 0);
    for (const auto& e : edges) {
        ++vertex_edge_offsets[e[0] + 1];
        ++vertex_edge_offsets[e[1] + 1];
    }
    for (int32_t v = 0; v < nv; ++v) vertex_edge_offsets[v + 1] += vertex_edge_offsets[v];
    reserve_huge_pages(vertex_edges, size_t(vertex_edge_offsets[nv]));
    vertex_edges.assign(vertex_edge_offsets[nv], 0);
    std::vector<int32_t> fill(vertex_edge_offsets.begin(), vertex_edge_offsets.end() - 1);
    for (int32_t e = 0; e < int32_t(edges.size()); ++e) {
        vertex_edges[fill[edges[e][0]]++] = e;
        vertex_edges[fill[edges[e][1]]++] = e;
    }

    reserve_huge_pages(location, size_t(nv));
    location.assign(nv, SurfacePoint());
    for (int32_t v = 0; v < nv; ++v) location[v] = SurfacePoint::corner(v);
    path.reset(edges.size());
    path_version.assign(edges.size(), 0);
    inside.reset(nv, triangle_capacity);
    edge_content.clear();
    frozen_ = false;
    decltype(frozen_path_offsets_)().swap(frozen_path_offsets_);
    decltype(frozen_crossings_)().swap(frozen_crossings_);
    decltype(frozen_keys_)().swap(frozen_keys_);
    decltype(frozen_content_offsets_)().swap(frozen_content_offsets_);
    decltype(frozen_ids_)().swap(frozen_ids_);
}

bool Embedding::content(int32_t a, int32_t b, EdgeContentView& out) const {
    const uint64_t key = edge_key(a, b);
    if (!frozen_) {
        const EdgeContentMap::Entry* entry = edge_content.find(key);
        if (!entry) return false;
        out = edge_content.view(*entry);
        return true;
    }
    const auto it = std::lower_bound(frozen_keys_.begin(), frozen_keys_.end(), key);
    if (it == frozen_keys_.end() || *it != key) return false;
    const size_t i = size_t(it - frozen_keys_.begin());
    const int32_t* ids = frozen_ids_.data();
    out.vertices = {ids + frozen_content_offsets_[2 * i], ids + frozen_content_offsets_[2 * i + 1]};
    out.crossing_edges = {ids + frozen_content_offsets_[2 * i + 1], ids + frozen_content_offsets_[2 * i + 2]};
    return true;
}

void Embedding::freeze() {
    if (frozen_) return;
    inside.shrink_to_fit();
    // Paths: one array of crossings with an offset per edge. uint32 offsets: 2^32
    // crossings would be 96 GB.
    std::vector<uint32_t> path_offsets;
    path_offsets.reserve(path.size() + 1);
    std::vector<Crossing> all;
    all.reserve(path.total_crossings());
    path_offsets.push_back(0);
    for (size_t e = 0; e < path.size(); ++e) {
        const ConstRange<Crossing> p = path[e];
        all.insert(all.end(), p.begin(), p.end());
        path_offsets.push_back(static_cast<uint32_t>(all.size()));
    }
    path.release();
    decltype(path_version)().swap(path_version);
    // Edge contents: the keys sorted, each key's vertices and crossing edges in one array
    // of ids, in the order of the changing form.
    std::vector<std::pair<uint64_t, EdgeContentView>> entries;
    entries.reserve(edge_content.size());
    size_t ids = 0;
    edge_content.for_each([&](uint64_t key, const EdgeContentView& c) {
        entries.emplace_back(key, c);
        ids += c.vertices.size() + c.crossing_edges.size();
    });
    std::sort(entries.begin(), entries.end(),
              [](const auto& x, const auto& y) { return x.first < y.first; });
    std::vector<uint64_t> keys;
    std::vector<uint32_t> offsets;
    std::vector<int32_t> flat;
    keys.reserve(entries.size());
    offsets.reserve(2 * entries.size() + 1);
    flat.reserve(ids);
    offsets.push_back(0);
    for (const auto& [key, c] : entries) {
        keys.push_back(key);
        flat.insert(flat.end(), c.vertices.begin(), c.vertices.end());
        offsets.push_back(static_cast<uint32_t>(flat.size()));
        flat.insert(flat.end(), c.crossing_edges.begin(), c.crossing_edges.end());
        offsets.push_back(static_cast<uint32_t>(flat.size()));
    }
    decltype(entries)().swap(entries);
    edge_content.release();
    frozen_path_offsets_ = std::move(path_offsets);
    frozen_crossings_ = std::move(all);
    frozen_keys_ = std::move(keys);
    frozen_content_offsets_ = std::move(offsets);
    frozen_ids_ = std::move(flat);
    frozen_ = true;
}

int32_t Embedding::find_edge(int32_t u, int32_t w) const {
    if (u > w) std::swap(u, w);
    if (u < 0 || w + 1 >= int32_t(smaller_vertex_edges.size())) return -1;
    // A short scan of contiguous (u, w) pairs sorted by w; no indirection through
    // vertex_edges (this lookup is a few percent of the simplifier's time).
    for (int32_t e = smaller_vertex_edges[u]; e < smaller_vertex_edges[u + 1]; ++e) {
        if (edges[e][1] == w) return e;
        if (edges[e][1] > w) break;
    }
    return -1;
}

int32_t Embedding::triangle_of_edges(int32_t e, int32_t f) const {
    if (e == f) return -1;
    for (int32_t i = edge_triangle_offsets[e]; i < edge_triangle_offsets[e + 1]; ++i) {
        const int32_t t = edge_triangles[i];
        for (int32_t j = edge_triangle_offsets[f]; j < edge_triangle_offsets[f + 1]; ++j)
            if (edge_triangles[j] == t) return t;
    }
    return -1;
}

void Embedding::path_points(int32_t e, std::vector<SurfacePoint>& points, std::vector<double>& sigmas) const {
    points.clear();
    sigmas.clear();
    points.push_back(location[edges[e][0]]);
    sigmas.push_back(0.0);
    for (const Crossing& c : crossings(e)) {
        points.push_back(SurfacePoint{SurfacePoint::OnEdge, c.a, c.b, c.s, {}});
        sigmas.push_back(c.sigma);
    }
    points.push_back(location[edges[e][1]]);
    sigmas.push_back(1.0);
}

void Embedding::clear_location(int32_t vertex) {
    const SurfacePoint& p = location[vertex];
    if (p.kind == SurfacePoint::Inside) {
        inside.remove(p.a, vertex);
    } else if (p.kind == SurfacePoint::OnEdge) {
        edge_content.remove_vertex(edge_key(p.a, p.b), vertex);
    }
}

void Embedding::set_location(int32_t vertex, const SurfacePoint& p) {
    clear_location(vertex);
    location[vertex] = p;
    if (p.kind == SurfacePoint::Inside) {
        inside.add(p.a, vertex);
    } else if (p.kind == SurfacePoint::OnEdge) {
        edge_content.add_vertex(edge_key(p.a, p.b), vertex);
    }
}

void Embedding::set_path(int32_t e, const std::vector<Crossing>& crossings) {
    // A removal re-cuts a path only inside its star: its crossings elsewhere stay, on the
    // same coarse edges. So only the coarse edges the path leaves or newly crosses get e
    // taken off or put on (taking e off every old edge and putting it back on every new
    // one was a hash lookup and a list search per crossing, most of a commit's time). The
    // lists end up with the same ids; only their order differs, which no reader depends
    // on (every reader sorts them). Quadratic matching: paths are short; a long pair
    // (never seen in a removal) matches nothing.
    const ConstRange<Crossing> old = path[size_t(e)];
    auto& kept = kept_crossings_;
    kept.assign(crossings.size(), 0);
    const bool match = old.size() * crossings.size() <= 4096;
    for (const Crossing& c : old) {
        if (match) {
            size_t j = 0;
            while (j < crossings.size() && (kept[j] || crossings[j].a != c.a || crossings[j].b != c.b)) ++j;
            if (j < crossings.size()) {
                kept[j] = 1;
                continue;
            }
        }
        edge_content.remove_crossing_edge(edge_key(c.a, c.b), e);
    }
    path.assign(size_t(e), crossings.data(), crossings.size());
    ++path_version[e];
    for (size_t j = 0; j < crossings.size(); ++j)
        if (!kept[j]) edge_content.add_crossing_edge(edge_key(crossings[j].a, crossings[j].b), e);
}

}  // namespace bpm::detail
