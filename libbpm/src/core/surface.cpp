// Surface basics: extent, validation against bpm's input rules, and the two repairs.
#include "bpm/surface.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <unordered_map>

#include "bpm/predicates.h"
#include "core/edge_uses.h"
#include "core/huge_pages.h"
#include "core/number_text.h"

namespace bpm {

namespace {

bool finite(const Vec3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

// Lexicographic order of positions; -0 and +0 compare equal, as exact equality wants.
bool position_less(const Vec3& a, const Vec3& b) {
    if (a[0] != b[0]) return a[0] < b[0];
    if (a[1] != b[1]) return a[1] < b[1];
    return a[2] < b[2];
}

// For each vertex, the smallest index of a vertex at the same position (itself if none).
// Vertices with a NaN or infinite coordinate are never merged.
std::vector<int32_t> first_at_same_position(const std::vector<Vec3>& vertices) {
    std::vector<int32_t> order;
    order.reserve(vertices.size());
    for (size_t i = 0; i < vertices.size(); ++i) {
        if (finite(vertices[i])) order.push_back(static_cast<int32_t>(i));
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](int32_t a, int32_t b) { return position_less(vertices[a], vertices[b]); });
    std::vector<int32_t> first(vertices.size());
    std::iota(first.begin(), first.end(), 0);
    for (size_t i = 1; i < order.size(); ++i) {
        const Vec3& a = vertices[order[i - 1]];
        const Vec3& b = vertices[order[i]];
        // stable_sort keeps equal positions in index order, so the run's first is its smallest.
        if (a[0] == b[0] && a[1] == b[1] && a[2] == b[2]) first[order[i]] = first[order[i - 1]];
    }
    return first;
}

}  // namespace

double bounding_box_diagonal(const std::vector<Vec3>& points) {
    if (points.empty()) return 0.0;
    Vec3 lo = points[0], hi = points[0];
    for (const Vec3& p : points) {
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], p[k]);
            hi[k] = std::max(hi[k], p[k]);
        }
    }
    return norm(hi - lo);
}

double bounding_box_diagonal(const Surface& surface) { return bounding_box_diagonal(surface.vertices); }

std::string SurfaceProblem::describe() const {
    const std::string e = std::to_string(element);
    const std::string o = std::to_string(other);
    switch (kind) {
        case Kind::NonFiniteCoordinate: return "vertex " + e + ": coordinate is NaN or infinite";
        case Kind::IndexOutOfRange: return "triangle " + e + ": vertex index " + o + " is out of range";
        case Kind::RepeatedCorner: return "triangle " + e + ": two corners are the same vertex " + o;
        case Kind::ZeroArea: return "triangle " + e + ": zero area (its three corners are collinear)";
        case Kind::DuplicateTriangle: return "triangle " + e + ": same three vertices as triangle " + o;
        case Kind::UnreferencedVertex: return "vertex " + e + ": not used by any triangle";
        case Kind::DuplicateVertex: return "vertex " + e + ": same position as vertex " + o;
        case Kind::PatchCountMismatch: return e + " patch ids for " + o + " triangles";
    }
    return "unknown problem";
}

std::string describe_problem(const SurfaceProblem& problem, const Surface& surface) {
    using Kind = SurfaceProblem::Kind;
    const auto& V = surface.vertices;
    const auto& T = surface.triangles;
    const int64_t e = problem.element;
    const bool vertex_ok = e >= 0 && e < static_cast<int64_t>(V.size());
    const bool triangle_ok = e >= 0 && e < static_cast<int64_t>(T.size());
    auto corners = [&](const Tri& t) {
        return " (vertices " + std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " + std::to_string(t[2]) + ")";
    };
    auto position = [](const Vec3& p) {
        return "(" + detail::round_trip_text(p[0]) + ", " + detail::round_trip_text(p[1]) + ", " +
               detail::round_trip_text(p[2]) + ")";
    };
    switch (problem.kind) {
        case Kind::NonFiniteCoordinate:
            if (vertex_ok) {
                const Vec3& p = V[static_cast<size_t>(e)];
                for (int k = 0; k < 3; ++k) {
                    if (!std::isfinite(p[k])) {
                        return "vertex " + std::to_string(e) + ": coordinate " + "xyz"[k] + " is " +
                               (std::isnan(p[k]) ? "NaN" : "infinite");
                    }
                }
            }
            break;
        case Kind::IndexOutOfRange:
            if (triangle_ok) {
                return "triangle " + std::to_string(e) + corners(T[static_cast<size_t>(e)]) + ": vertex index " +
                       std::to_string(problem.other) + " is out of range (" + std::to_string(V.size()) + " vertices)";
            }
            break;
        case Kind::RepeatedCorner:
            if (triangle_ok) {
                const Tri& t = T[static_cast<size_t>(e)];
                const int a = t[0] == t[1] || t[0] == t[2] ? 0 : 1;
                const int b = t[0] == t[1] ? 1 : 2;
                return "triangle " + std::to_string(e) + corners(t) + ": corners " + std::to_string(a) + " and " +
                       std::to_string(b) + " are the same vertex";
            }
            break;
        case Kind::ZeroArea:
            if (triangle_ok) {
                return "triangle " + std::to_string(e) + corners(T[static_cast<size_t>(e)]) +
                       ": zero area (its three corners are collinear)";
            }
            break;
        case Kind::DuplicateTriangle:
            if (triangle_ok) {
                return "triangle " + std::to_string(e) + corners(T[static_cast<size_t>(e)]) +
                       ": same three vertices as triangle " + std::to_string(problem.other);
            }
            break;
        case Kind::DuplicateVertex:
            if (vertex_ok) {
                return "vertex " + std::to_string(e) + ": same position " + position(V[static_cast<size_t>(e)]) +
                       " as vertex " + std::to_string(problem.other);
            }
            break;
        case Kind::UnreferencedVertex:
        case Kind::PatchCountMismatch: break;
    }
    return problem.describe();
}

std::vector<SurfaceProblem> validate_surface(const Surface& surface, const ValidateOptions& options) {
    using Kind = SurfaceProblem::Kind;
    std::vector<SurfaceProblem> problems;
    const size_t limit = options.max_problems == 0 ? std::numeric_limits<size_t>::max() : options.max_problems;
    auto add = [&](Kind kind, int64_t element, int64_t other = -1) {
        problems.push_back({kind, element, other});
        return problems.size() >= limit;
    };
    const auto& V = surface.vertices;
    const auto& T = surface.triangles;
    const int64_t nv = static_cast<int64_t>(V.size());

    if (surface.patches.size() != T.size()) {
        if (add(Kind::PatchCountMismatch, static_cast<int64_t>(surface.patches.size()), static_cast<int64_t>(T.size()))) {
            return problems;
        }
    }
    for (size_t v = 0; v < V.size(); ++v) {
        if (!finite(V[v]) && add(Kind::NonFiniteCoordinate, static_cast<int64_t>(v))) return problems;
    }

    // Per triangle: indices, repeated corners, then (only for a well-formed triangle with
    // finite corners) the exact collinearity test.
    std::vector<char> usable(T.size(), 0);
    for (size_t t = 0; t < T.size(); ++t) {
        const Tri& tri = T[t];
        bool ok = true;
        for (int k = 0; k < 3 && ok; ++k) {
            if (tri[k] < 0 || tri[k] >= nv) {
                ok = false;
                if (add(Kind::IndexOutOfRange, static_cast<int64_t>(t), tri[k])) return problems;
            }
        }
        if (!ok) continue;
        if (tri[0] == tri[1] || tri[0] == tri[2] || tri[1] == tri[2]) {
            const int32_t same = tri[0] == tri[1] || tri[0] == tri[2] ? tri[0] : tri[1];
            if (add(Kind::RepeatedCorner, static_cast<int64_t>(t), same)) return problems;
            continue;
        }
        usable[t] = 1;
        const Vec3 &a = V[tri[0]], &b = V[tri[1]], &c = V[tri[2]];
        if (finite(a) && finite(b) && finite(c) && collinear3d(a, b, c)) {
            if (add(Kind::ZeroArea, static_cast<int64_t>(t))) return problems;
        }
    }

    // Duplicate triangles: the same vertex set in any order and orientation.
    {
        std::vector<std::pair<Tri, int32_t>> keys;
        detail::reserve_huge_pages(keys, T.size());
        for (size_t t = 0; t < T.size(); ++t) {
            if (!usable[t]) continue;
            Tri k = T[t];
            std::sort(k.begin(), k.end());
            keys.push_back({k, static_cast<int32_t>(t)});
        }
        std::sort(keys.begin(), keys.end());
        std::vector<SurfaceProblem> duplicates;
        size_t run = 0;  // first entry of the current run of equal vertex sets (smallest index)
        for (size_t i = 1; i < keys.size(); ++i) {
            if (keys[i].first != keys[run].first) {
                run = i;
                continue;
            }
            duplicates.push_back({Kind::DuplicateTriangle, keys[i].second, keys[run].second});
        }
        std::sort(duplicates.begin(), duplicates.end(),
                  [](const SurfaceProblem& a, const SurfaceProblem& b) { return a.element < b.element; });
        for (const SurfaceProblem& p : duplicates) {
            if (add(p.kind, p.element, p.other)) return problems;
        }
    }

    if (!options.allow_unreferenced_vertices) {
        std::vector<char> used(V.size(), 0);
        for (const Tri& tri : T) {
            for (int32_t v : tri) {
                if (v >= 0 && v < nv) used[static_cast<size_t>(v)] = 1;
            }
        }
        for (size_t v = 0; v < V.size(); ++v) {
            if (!used[v] && add(Kind::UnreferencedVertex, static_cast<int64_t>(v))) return problems;
        }
    }

    if (!options.allow_duplicate_vertices) {
        const std::vector<int32_t> first = first_at_same_position(V);
        for (size_t v = 0; v < V.size(); ++v) {
            if (first[v] != static_cast<int32_t>(v) && add(Kind::DuplicateVertex, static_cast<int64_t>(v), first[v])) {
                return problems;
            }
        }
    }
    return problems;
}

namespace {

// Keeps the vertices with keep[v] (in their order) and renumbers the triangles through
// `target` (old index -> old index of the vertex that replaces it). Indices that were
// out of range become -1, which validate_surface() still reports.
void compact_vertices(Surface& surface, const std::vector<char>& keep, const std::vector<int32_t>& target) {
    const size_t nv = surface.vertices.size();
    std::vector<int32_t> new_index(nv, -1);
    size_t next = 0;
    for (size_t v = 0; v < nv; ++v) {
        if (!keep[v]) continue;
        new_index[v] = static_cast<int32_t>(next);
        for (VertexArray& array : surface.vertex_data) {
            const size_t k = static_cast<size_t>(array.components);
            if (array.values.size() != nv * k) continue;  // malformed: left for vertex_data_problems()
            std::copy_n(array.values.begin() + static_cast<std::ptrdiff_t>(v * k), k,
                        array.values.begin() + static_cast<std::ptrdiff_t>(next * k));
        }
        surface.vertices[next++] = surface.vertices[v];
    }
    surface.vertices.resize(next);
    for (VertexArray& array : surface.vertex_data)
        if (array.values.size() == nv * static_cast<size_t>(array.components))
            array.values.resize(next * static_cast<size_t>(array.components));
    for (Tri& tri : surface.triangles) {
        for (int32_t& v : tri) {
            v = v >= 0 && static_cast<size_t>(v) < nv ? new_index[static_cast<size_t>(target[static_cast<size_t>(v)])] : -1;
        }
    }
}

}  // namespace

std::vector<std::string> vertex_data_problems(const Surface& surface) {
    std::vector<std::string> problems;
    const size_t nv = surface.vertices.size();
    for (size_t i = 0; i < surface.vertex_data.size(); ++i) {
        const VertexArray& a = surface.vertex_data[i];
        const std::string label = "vertex data '" + a.name + "'";
        if (a.name.empty() || a.name == "." || a.name.find('/') != std::string::npos)
            problems.push_back(label + ": the name must not be empty, '.' or contain '/'");
        for (size_t j = 0; j < i; ++j)
            if (surface.vertex_data[j].name == a.name) problems.push_back(label + ": the name is used twice");
        if (a.components < 1) {
            problems.push_back(label + ": " + std::to_string(a.components) + " components (must be at least 1)");
            continue;
        }
        if (a.values.size() != nv * static_cast<size_t>(a.components))
            problems.push_back(label + ": " + std::to_string(a.values.size()) + " values for " + std::to_string(nv) +
                               " vertices x " + std::to_string(a.components) + " components");
    }
    return problems;
}

Surface combine_surfaces(const std::vector<Surface>& parts, std::vector<std::pair<int, int32_t>>* patch_origin,
                         std::vector<std::string>* dropped_arrays) {
    Surface out;
    std::map<std::pair<int, int32_t>, int32_t> patch_id;
    std::vector<std::pair<int, int32_t>> origin;
    // Arrays every part has, with the same number of components (in the first part's order).
    std::vector<const VertexArray*> kept;
    if (!parts.empty())
        for (const VertexArray& a : parts[0].vertex_data) {
            bool everywhere = true;
            for (const Surface& part : parts) {
                bool found = false;
                for (const VertexArray& b : part.vertex_data) found = found || (b.name == a.name && b.components == a.components);
                everywhere = everywhere && found;
            }
            if (everywhere) {
                kept.push_back(&a);
                out.vertex_data.push_back({a.name, a.components, {}});
            }
        }
    if (dropped_arrays) {
        dropped_arrays->clear();
        for (const Surface& part : parts)
            for (const VertexArray& a : part.vertex_data) {
                bool is_kept = false;
                for (const VertexArray* k : kept) is_kept = is_kept || k->name == a.name;
                if (!is_kept && std::find(dropped_arrays->begin(), dropped_arrays->end(), a.name) == dropped_arrays->end())
                    dropped_arrays->push_back(a.name);
            }
    }
    for (size_t i = 0; i < parts.size(); ++i) {
        const Surface& part = parts[i];
        const int32_t offset = static_cast<int32_t>(out.vertices.size());
        out.vertices.insert(out.vertices.end(), part.vertices.begin(), part.vertices.end());
        for (size_t t = 0; t < part.triangles.size(); ++t) {
            Tri tri = part.triangles[t];
            for (int32_t& v : tri) v += offset;
            out.triangles.push_back(tri);
            const std::pair<int, int32_t> key{static_cast<int>(i), t < part.patches.size() ? part.patches[t] : 0};
            auto it = patch_id.find(key);
            if (it == patch_id.end()) {
                it = patch_id.emplace(key, static_cast<int32_t>(origin.size())).first;
                origin.push_back(key);
            }
            out.patches.push_back(it->second);
        }
        for (size_t k = 0; k < kept.size(); ++k)
            for (const VertexArray& b : part.vertex_data)
                if (b.name == kept[k]->name) {
                    out.vertex_data[k].values.insert(out.vertex_data[k].values.end(), b.values.begin(), b.values.end());
                    break;
                }
    }
    if (patch_origin) *patch_origin = std::move(origin);
    return out;
}

int64_t merge_duplicate_vertices(Surface& surface) {
    const std::vector<int32_t> first = first_at_same_position(surface.vertices);
    std::vector<char> keep(first.size());
    int64_t merged = 0;
    for (size_t v = 0; v < first.size(); ++v) {
        keep[v] = first[v] == static_cast<int32_t>(v);
        merged += keep[v] ? 0 : 1;
    }
    if (merged > 0) compact_vertices(surface, keep, first);
    return merged;
}

namespace {

// Finite points bucketed in cubes of side `cell` from `origin`: the points within `cell`
// of a point are in its cube or the 26 around it.
class PointGrid {
public:
    PointGrid(const Vec3& origin, double cell) : origin_(origin), cell_(cell) {}
    using Key = std::array<int64_t, 3>;
    Key key(const Vec3& p) const {
        Key k;
        for (int i = 0; i < 3; ++i) k[size_t(i)] = static_cast<int64_t>(std::floor((p[i] - origin_[i]) / cell_));
        return k;
    }
    void insert(const Vec3& p, int32_t id) { cells_[key(p)].push_back(id); }
    template <class Visit>
    void for_each_near(const Vec3& p, Visit&& visit) const {
        const Key k = key(p);
        for (int64_t dx = -1; dx <= 1; ++dx)
            for (int64_t dy = -1; dy <= 1; ++dy)
                for (int64_t dz = -1; dz <= 1; ++dz) {
                    const auto it = cells_.find({k[0] + dx, k[1] + dy, k[2] + dz});
                    if (it == cells_.end()) continue;
                    for (int32_t id : it->second) visit(id);
                }
    }

private:
    struct Hash {
        size_t operator()(const Key& k) const {
            uint64_t h = 1469598103934665603ull;
            for (int64_t x : k) h = (h ^ static_cast<uint64_t>(x)) * 1099511628211ull;
            return static_cast<size_t>(h);
        }
    };
    Vec3 origin_;
    double cell_;
    std::unordered_map<Key, std::vector<int32_t>, Hash> cells_;
};

// The grid for points within `distance` of each other on `points`: cubes no smaller than
// 1e-12 of the extent, so that cube indices stay far from overflow.
PointGrid grid_for(const std::vector<Vec3>& points, double distance) {
    Vec3 lo{0, 0, 0};
    bool any = false;
    for (const Vec3& p : points)
        if (finite(p)) {
            for (int k = 0; k < 3; ++k) lo[k] = any ? std::min(lo[k], p[k]) : p[k];
            any = true;
        }
    double extent = 0;
    for (const Vec3& p : points)
        if (finite(p)) extent = std::max({extent, p[0] - lo[0], p[1] - lo[1], p[2] - lo[2]});
    const double cell = std::max({distance, 1e-12 * extent, std::numeric_limits<double>::min()});
    return PointGrid(lo, cell);
}

}  // namespace

CloseVertexMerge merge_close_vertices(Surface& surface, double distance) {
    CloseVertexMerge result;
    const std::vector<Vec3>& V = surface.vertices;
    if (!(distance >= 0)) return result;
    PointGrid grid = grid_for(V, distance);
    std::vector<int32_t> target(V.size());
    std::iota(target.begin(), target.end(), 0);
    for (size_t v = 0; v < V.size(); ++v) {
        if (!finite(V[v])) continue;
        int32_t joined = -1;
        double moved = 0;
        grid.for_each_near(V[v], [&](int32_t kept) {
            const double d = bpm::distance(V[v], V[size_t(kept)]);
            if (d <= distance && (joined < 0 || kept < joined)) joined = kept, moved = d;
        });
        if (joined >= 0) {
            target[v] = joined;
            ++result.merged;
            result.largest_move = std::max(result.largest_move, moved);
        } else {
            grid.insert(V[v], static_cast<int32_t>(v));
        }
    }
    if (result.merged == 0) return result;
    const int32_t nv = static_cast<int32_t>(V.size());
    for (size_t t = 0; t < surface.triangles.size(); ++t) {
        const Tri& tri = surface.triangles[t];
        for (int k = 0; k < 3; ++k) {
            const int32_t a = tri[size_t(k)], b = tri[size_t((k + 1) % 3)];
            if (a < 0 || b < 0 || a >= nv || b >= nv || a == b) continue;  // left for validate_surface()
            if (target[size_t(a)] == target[size_t(b)]) {
                result.collapsed_triangle = static_cast<int32_t>(t);
                result.collapsed_corners = {a, b};
                result.merged = 0;
                result.largest_move = 0;
                return result;
            }
        }
    }
    std::vector<char> keep(V.size());
    for (size_t v = 0; v < V.size(); ++v) keep[v] = target[v] == static_cast<int32_t>(v);
    compact_vertices(surface, keep, target);
    return result;
}

std::optional<OpenSeam> find_open_seam(const Surface& surface, double max_gap) {
    return detail::find_open_seam(surface, detail::EdgeUses(surface).boundary_edges(), max_gap);
}

std::optional<OpenSeam> detail::find_open_seam(const Surface& surface,
                                               const std::vector<std::pair<int32_t, int32_t>>& boundary,
                                               double max_gap) {
    const std::vector<Vec3>& V = surface.vertices;
    const int32_t nv = static_cast<int32_t>(V.size());
    if (boundary.empty() || !(max_gap > 0)) return std::nullopt;
    const auto is_boundary = [&](int32_t a, int32_t b) {
        return std::binary_search(boundary.begin(), boundary.end(), std::pair(std::min(a, b), std::max(a, b)));
    };
    // Each boundary vertex's nearest other boundary vertex within max_gap (the smaller
    // index on ties), then the boundary edges whose ends' nearest ones are a boundary edge.
    std::vector<char> on_boundary(V.size(), 0);
    for (const auto& [a, b] : boundary) on_boundary[size_t(a)] = on_boundary[size_t(b)] = 1;
    std::vector<Vec3> points;
    for (int32_t v = 0; v < nv; ++v)
        if (on_boundary[size_t(v)]) points.push_back(V[size_t(v)]);
    PointGrid grid = grid_for(points, max_gap);
    for (int32_t v = 0; v < nv; ++v)
        if (on_boundary[size_t(v)] && finite(V[size_t(v)])) grid.insert(V[size_t(v)], v);
    std::unordered_map<int32_t, std::pair<int32_t, double>> nearest;
    for (int32_t v = 0; v < nv; ++v) {
        if (!on_boundary[size_t(v)] || !finite(V[size_t(v)])) continue;
        int32_t best = -1;
        double best_d = 0;
        grid.for_each_near(V[size_t(v)], [&](int32_t w) {
            if (w == v) return;
            const double d = distance(V[size_t(v)], V[size_t(w)]);
            if (d <= max_gap && (best < 0 || d < best_d || (d == best_d && w < best))) best = w, best_d = d;
        });
        if (best >= 0) nearest[v] = {best, best_d};
    }
    OpenSeam seam;
    seam.boundary_edges = static_cast<int64_t>(boundary.size());
    for (const auto& [a, b] : boundary) {
        const auto na = nearest.find(a), nb = nearest.find(b);
        if (na == nearest.end() || nb == nearest.end()) continue;
        const int32_t c = na->second.first, d = nb->second.first;
        if (c == d || (c == b && d == a)) continue;
        if (!is_boundary(c, d)) continue;
        if (seam.paired_edges == 0) seam.first_edge = {a, b};
        ++seam.paired_edges;
        seam.gap = std::max({seam.gap, na->second.second, nb->second.second});
    }
    if (seam.paired_edges == 0) return std::nullopt;
    return seam;
}

double seam_merge_tolerance(const Surface& surface, const OpenSeam& seam, double diagonal) {
    if (!(diagonal > 0) || !std::isfinite(diagonal)) return 0.0;
    const double tolerance = std::pow(10.0, std::ceil(std::log10(std::max(2 * seam.gap / diagonal, 1e-15))));
    Surface trial = surface;
    if (merge_close_vertices(trial, tolerance * diagonal).collapsed_triangle >= 0) return 0.0;
    const std::optional<OpenSeam> left = find_open_seam(trial, kOpenSeamMaxGap * diagonal);
    return left && left->paired_edges >= seam.paired_edges ? 0.0 : tolerance;
}

int64_t drop_unreferenced_vertices(Surface& surface) {
    const size_t nv = surface.vertices.size();
    std::vector<char> keep(nv, 0);
    for (const Tri& tri : surface.triangles) {
        for (int32_t v : tri) {
            if (v >= 0 && static_cast<size_t>(v) < nv) keep[static_cast<size_t>(v)] = 1;
        }
    }
    const int64_t dropped = std::count(keep.begin(), keep.end(), 0);
    if (dropped > 0) {
        std::vector<int32_t> identity(nv);
        std::iota(identity.begin(), identity.end(), 0);
        compact_vertices(surface, keep, identity);
    }
    return dropped;
}

int64_t fuse_duplicate_triangles(Surface& surface, std::vector<FusedPatch>* interfaces) {
    auto& T = surface.triangles;
    auto& P = surface.patches;
    const int64_t nv = surface.num_vertices();
    if (P.size() != T.size()) return 0;  // validate_surface() reports it
    // (sorted corners, index) of every usable triangle; equal keys are one set.
    std::vector<std::pair<Tri, int32_t>> keys;
    keys.reserve(T.size());
    for (size_t t = 0; t < T.size(); ++t) {
        Tri k = T[t];
        if (k[0] < 0 || k[1] < 0 || k[2] < 0 || k[0] >= nv || k[1] >= nv || k[2] >= nv) continue;
        if (k[0] == k[1] || k[0] == k[2] || k[1] == k[2]) continue;
        std::sort(k.begin(), k.end());
        keys.push_back({k, static_cast<int32_t>(t)});
    }
    std::sort(keys.begin(), keys.end());
    std::vector<char> keep(T.size(), 1);
    // Each set, in order of its first triangle: the new patch is numbered in that order.
    std::vector<std::pair<int32_t, std::vector<int32_t>>> sets;  // (first triangle, patches of the set)
    for (size_t begin = 0, end = 0; begin < keys.size(); begin = end) {
        for (end = begin + 1; end < keys.size() && keys[end].first == keys[begin].first; ++end) {
        }
        if (end - begin < 2) continue;
        std::vector<int32_t> patches;
        for (size_t i = begin; i < end; ++i) {
            patches.push_back(P[size_t(keys[i].second)]);
            if (i > begin) keep[size_t(keys[i].second)] = 0;  // keys[begin] has the smallest index
        }
        std::sort(patches.begin(), patches.end());
        patches.erase(std::unique(patches.begin(), patches.end()), patches.end());
        sets.push_back({keys[begin].second, std::move(patches)});
    }
    if (sets.empty()) return 0;
    std::sort(sets.begin(), sets.end());
    int32_t next = 0;
    for (int32_t p : P) next = std::max(next, p + 1);
    std::map<std::vector<int32_t>, size_t> made;  // patches joined -> index into *interfaces
    std::vector<FusedPatch> fused;
    for (auto& [t, patches] : sets) {
        if (patches.size() < 2) continue;  // a plain duplicate within one patch
        auto it = made.find(patches);
        if (it == made.end()) {
            it = made.emplace(patches, fused.size()).first;
            fused.push_back({next++, patches, 0, P[size_t(t)]});
        }
        FusedPatch& f = fused[it->second];
        if (f.kept_from != P[size_t(t)]) f.kept_from = -1;
        P[size_t(t)] = f.patch;
        ++f.triangles;
    }
    int64_t removed = 0;
    size_t out = 0;
    for (size_t t = 0; t < T.size(); ++t) {
        if (!keep[t]) {
            ++removed;
            continue;
        }
        T[out] = T[t];
        P[out] = P[t];
        ++out;
    }
    T.resize(out);
    P.resize(out);
    if (interfaces) *interfaces = std::move(fused);
    return removed;
}

std::string coordinate_range_problem(const Surface& surface) {
    if (surface.vertices.empty()) return {};
    Vec3 lo = surface.vertices[0], hi = lo;
    double largest = 0.0;
    for (const Vec3& p : surface.vertices)
        for (int k = 0; k < 3; ++k) {
            if (!std::isfinite(p[k])) return {};  // validate_surface() says which vertex
            lo[k] = std::min(lo[k], p[k]);
            hi[k] = std::max(hi[k], p[k]);
            largest = std::max(largest, std::fabs(p[k]));
        }
    // The sides, not the diagonal: its squares would overflow for the inputs checked here.
    double extent = 0.0;
    for (int k = 0; k < 3; ++k) extent = std::max(extent, hi[k] - lo[k]);
    const auto g = [](double x) { return detail::three_digit_text(x); };
    const std::string range = "bpm computes with squares and fourth powers of lengths, which leave double precision "
                              "(overflow near 1e77, underflow near 1e-77), so coordinates must be within +-" +
                              g(kMaxCoordinate) + " and the bounding box at least " + g(kMinExtent) + " across";
    const std::string fix = ". Rescale the input, e.g. express it in another length unit";
    if (largest > kMaxCoordinate)
        return "coordinates out of range: the largest magnitude is " + g(largest) + " (bounding box " + g(extent) +
               " across); " + range + fix;
    if (extent < kMinExtent && extent > 0.0)
        return "coordinates out of range: the bounding box is only " + g(extent) + " across (largest magnitude " +
               g(largest) + "); " + range + fix;
    return {};
}

}  // namespace bpm
