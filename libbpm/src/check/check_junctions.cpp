// check_junctions: around every edge where three or more triangles meet, the wedges
// between consecutive sheets are claimed by the same material from both sides. The
// triangles are sorted around the edge with exact predicates (core/sheet_order.h); a
// triangle's side towards a wedge is its front (where its normal points) or its back,
// and patch_info says which material each side of its patch faces. A sheet turned past
// another around their common edge intersects nothing, so the intersection check
// passes, but the volume regions change: bpm-mesh then finds regions whose sides
// disagree about their material.
//
// The same for whole components: a sheet swept across an island (a component it never
// touches) intersects nothing either. So each component of S (triangles connected through
// shared vertices) is compared with its component of S0 by the materials it lies in:
// from one of its vertices, the parity of a ray's crossings with the other components'
// triangles bounding each material (core/ray_crossing.h, exact).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <map>

#include "bpm/check.h"
#include "bpm/patch_info.h"
#include "bpm/surface_topology.h"
#include "check/check_internal.h"
#include "core/number_text.h"
#include "core/ray_crossing.h"
#include "core/sheet_order.h"
#include "core/vertex_components.h"

namespace bpm {

namespace {

bool same_material(const std::string& x, const std::string& y) {
    return x.size() == y.size() && std::equal(x.begin(), x.end(), y.begin(), [](char p, char q) {
               return std::tolower(static_cast<unsigned char>(p)) == std::tolower(static_cast<unsigned char>(q));
           });
}

struct JunctionCounts {
    int64_t junction_edges = 0;      // edges of three or more triangles
    int64_t unknown_materials = 0;   // of those, with a triangle whose patch has no oriented materials
    int64_t overlapping = 0;         // two triangles on one half-plane (or a degenerate one)
    int64_t inconsistent = 0;        // a wedge claimed by two materials
};

// Scans `surface`; problems name triangles by `triangle_kind` and the edge's vertices by
// `vertex_name` (e.g. the original id of a coarse vertex). With `reference` set the
// surface is the reference (S0 of a file): nothing is a problem, and the patches of its
// inconsistent edges are added to `*reference`. Patches listed in `doubtful` count as
// without materials.
template <class VertexName>
JunctionCounts scan_junctions(const Surface& surface, const std::vector<PatchInfo>& infos,
                              const std::string& triangle_kind, const VertexName& vertex_name, CheckResult& r,
                              size_t max_problems, std::vector<int32_t>* reference,
                              const std::vector<int32_t>& doubtful, const std::vector<uint64_t>* material_bits = nullptr,
                              uint64_t* open_materials = nullptr) {
    JunctionCounts counts;
    const SurfaceConnectivity conn = build_connectivity(surface);
    const bool have_patches = surface.patches.size() == surface.triangles.size();
    std::vector<int32_t> tris, order;
    std::vector<Vec3> apexes;
    std::vector<int8_t> forward;  // the triangle runs a -> b
    std::vector<const PatchInfo*> info;
    for (int32_t e = 0; e < conn.num_edges(); ++e) {
        if (material_bits) {  // the materials whose boundary is open at e (compare_components)
            uint64_t x = 0;
            for (int32_t i = conn.edge_triangle_offsets[e]; i < conn.edge_triangle_offsets[e + 1]; ++i)
                x ^= (*material_bits)[size_t(conn.edge_triangles[size_t(i)])];
            *open_materials |= x;
        }
        if (conn.edge_degree(e) < 3) continue;
        ++counts.junction_edges;
        const int32_t a = conn.edges[e][0], b = conn.edges[e][1];
        tris.assign(conn.edge_triangles.begin() + conn.edge_triangle_offsets[e],
                    conn.edge_triangles.begin() + conn.edge_triangle_offsets[e + 1]);
        apexes.clear();
        forward.clear();
        info.clear();
        bool known = have_patches;
        for (int32_t t : tris) {
            const Tri& c = surface.triangles[t];
            int ka = 0;
            while (ka < 3 && c[ka] != a) ++ka;
            const int32_t next = c[(ka + 1) % 3], prev = c[(ka + 2) % 3];
            forward.push_back(next == b ? 1 : 0);
            apexes.push_back(surface.vertices[next == b ? prev : next]);
            const PatchInfo* pi = have_patches ? find_patch_info(infos, surface.patches[t]) : nullptr;
            if (!pi || !pi->has_materials() || !pi->oriented) known = false;
            if (have_patches && std::find(doubtful.begin(), doubtful.end(), surface.patches[t]) != doubtful.end())
                known = false;
            info.push_back(pi);
        }
        const Vec3& pa = surface.vertices[a];
        const Vec3& pb = surface.vertices[b];
        const std::string edge_where =
            "edge " + vertex_name(a) + " -- " + vertex_name(b) + " (" + std::to_string(tris.size()) + " triangles)";
        if (!detail::sort_around_edge(pa, pb, apexes, order)) {
            ++counts.overlapping;
            if (reference) continue;
            r.add_problem({{{triangle_kind, tris[0]}},
                           edge_where + ": two of its triangles lie on one half-plane, or one is degenerate: their "
                                        "order around the edge is undefined"},
                          max_problems);
            continue;
        }
        if (!known) {
            ++counts.unknown_materials;
            continue;
        }
        // Wedge k lies after sheet order[k] and before order[k + 1] (turning around a -> b):
        // on the front of a triangle that runs a -> b (its normal points to where the
        // turn goes), on the back of one that runs b -> a.
        int bad = 0, first_bad = -1;
        const size_t n = order.size();
        for (size_t k = 0; k < n; ++k) {
            const int32_t i = order[k], j = order[(k + 1) % n];
            const std::string& mi = forward[i] ? info[i]->front : info[i]->back;
            const std::string& mj = forward[j] ? info[j]->back : info[j]->front;
            if (!same_material(mi, mj)) {
                if (first_bad < 0) first_bad = static_cast<int>(k);
                ++bad;
            }
        }
        if (bad == 0) continue;
        ++counts.inconsistent;
        if (reference) {
            for (int32_t t : tris) reference->push_back(surface.patches[t]);
            continue;
        }
        const int32_t i = order[first_bad], j = order[(first_bad + 1) % n];
        const std::string& mi = forward[i] ? info[i]->front : info[i]->back;
        const std::string& mj = forward[j] ? info[j]->back : info[j]->front;
        std::string sequence;
        for (size_t k = 0; k < n; ++k) {
            const int32_t t = order[k];
            if (k) sequence += ", ";
            sequence += std::to_string(tris[t]) + " (patch " + std::to_string(surface.patches[tris[t]]) + ")";
        }
        r.add_problem({{{triangle_kind, tris[i]}, {"other_" + triangle_kind, tris[j]}},
                       edge_where + ": the wedge between triangles " + std::to_string(tris[i]) + " and " +
                           std::to_string(tris[j]) + " faces " + mi + " on one side and " + mj + " on the other" +
                           (bad > 1 ? " (" + std::to_string(bad) + " of its " + std::to_string(n) + " wedges disagree)" : "") +
                           "; the sheets in turning order: " + sequence},
                      max_problems);
    }
    return counts;
}

// The materials a component lies in, as bits: bit m is set when the parity of the
// crossings of a ray from one of its vertices (to infinity) with the triangles of the
// other components that bound material m is odd, i.e. when the material m begins or ends
// between the component and the unbounded region. A patch bounds each of its two
// materials (none when they are equal); the patches without materials count as bounding
// one material of their own (kUnknownBit): a closed surface of one material, whose inner
// shells are then cavities or islands. Bits of a material whose bounding triangles are no
// closed surface (an edge in an odd number of them: a reader's guess that contradicts the
// surface, or an open surface) say nothing: they are left out (`open`).
constexpr int kUnknownBit = 63;

struct MaterialBits {
    std::vector<uint64_t> of_patch_triangle;  // per triangle
    bool usable = true;                       // at most 63 materials
};

int material_bit(std::map<std::string, int>& bits, const std::string& name) {
    std::string key = name;
    for (char& c : key) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    auto it = bits.find(key);
    if (it != bits.end()) return it->second;
    const int b = static_cast<int>(bits.size());
    bits.emplace(key, b);
    return b;
}

MaterialBits triangle_bits(const Surface& surface, const std::vector<PatchInfo>& infos,
                           std::map<std::string, int>& bits) {
    MaterialBits m;
    const bool have_patches = surface.patches.size() == surface.triangles.size();
    m.of_patch_triangle.resize(surface.triangles.size());
    std::map<int32_t, uint64_t> of_patch;
    for (size_t t = 0; t < surface.triangles.size(); ++t) {
        const int32_t patch = have_patches ? surface.patches[t] : 0;
        auto it = of_patch.find(patch);
        if (it == of_patch.end()) {
            const PatchInfo* pi = have_patches ? find_patch_info(infos, patch) : nullptr;
            uint64_t mask = uint64_t(1) << kUnknownBit;
            if (pi && pi->has_materials()) {
                const int f = material_bit(bits, pi->front), b = material_bit(bits, pi->back);
                if (f >= kUnknownBit || b >= kUnknownBit) m.usable = false;
                mask = f == b ? 0 : (uint64_t(1) << (f % kUnknownBit)) ^ (uint64_t(1) << (b % kUnknownBit));
            }
            it = of_patch.emplace(patch, mask).first;
        }
        m.of_patch_triangle[t] = it->second;
    }
    return m;
}

// Components through shared vertices: per vertex (-1 for a vertex of no triangle).
int32_t vertex_components(const Surface& surface, std::vector<int32_t>& component) {
    detail::VertexComponents components(surface.vertices.size());
    for (const Tri& t : surface.triangles) components.add(t);
    return components.number(component);
}

// The triangles in cells of the (y, z) plane, for rays along +x: a ray from p meets only
// triangles whose (y, z) box holds p, and those are in p's cell (the cell index is
// monotone in the coordinate, rounding included, so a box's cells include p's).
class RayCells {
public:
    explicit RayCells(const Surface& s) {
        if (s.triangles.empty()) return;
        lo_ = {s.vertices[size_t(s.triangles[0][0])][1], s.vertices[size_t(s.triangles[0][0])][2]};
        Vec2 hi = lo_;
        for (const Tri& t : s.triangles)
            for (int32_t c : t)
                for (int k = 0; k < 2; ++k) {
                    lo_[k] = std::min(lo_[k], s.vertices[size_t(c)][k + 1]);
                    hi[k] = std::max(hi[k], s.vertices[size_t(c)][k + 1]);
                }
        n_ = std::max<int64_t>(1, std::min<int64_t>(2048, int64_t(std::sqrt(double(s.triangles.size()) / 2.0))));
        for (int k = 0; k < 2; ++k) scale_[k] = hi[k] > lo_[k] ? double(n_) / (hi[k] - lo_[k]) : 0.0;
        // Counted first, then each cell's list in one array (start_: offsets per cell).
        start_.assign(size_t(n_ * n_ + 1), 0);
        for (int pass = 0; pass < 2; ++pass) {
            std::vector<int64_t> next;
            if (pass == 1) {
                for (size_t i = 1; i < start_.size(); ++i) start_[i] += start_[i - 1];
                ids_.resize(size_t(start_.back()));
                next.assign(start_.begin(), start_.end() - 1);
            }
            for (size_t t = 0; t < s.triangles.size(); ++t) {
                int64_t span[4];  // cells: y from, y to, z from, z to
                const Tri& c = s.triangles[t];
                for (int k = 0; k < 2; ++k) {
                    const double u = s.vertices[size_t(c[0])][k + 1], v = s.vertices[size_t(c[1])][k + 1],
                                 w = s.vertices[size_t(c[2])][k + 1];
                    span[2 * k] = cell(std::min({u, v, w}), k);
                    span[2 * k + 1] = cell(std::max({u, v, w}), k);
                }
                for (int64_t i = span[0]; i <= span[1]; ++i)
                    for (int64_t j = span[2]; j <= span[3]; ++j) {
                        if (pass == 0)
                            ++start_[size_t(i * n_ + j + 1)];
                        else
                            ids_[size_t(next[size_t(i * n_ + j)]++)] = int32_t(t);
                    }
            }
        }
    }

    // The triangles whose (y, z) box may hold p.
    template <class F>
    void for_candidates(const Vec3& p, F&& f) const {
        if (ids_.empty()) return;
        const size_t key = size_t(cell(p[1], 0) * n_ + cell(p[2], 1));
        for (int64_t i = start_[key]; i < start_[key + 1]; ++i) f(ids_[size_t(i)]);
    }

private:
    int64_t cell(double y, int k) const {
        const double c = std::floor((y - lo_[k]) * scale_[k]);
        return std::clamp<int64_t>(std::isfinite(c) ? int64_t(c) : 0, 0, n_ - 1);
    }
    Vec2 lo_{};
    Vec2 scale_{};
    int64_t n_ = 1;
    std::vector<int64_t> start_;
    std::vector<int32_t> ids_;
};

// The bits (above) of the component `own` seen from p, over the other components'
// triangles; false when p lies on one of them (they intersect: not decided).
bool lies_in(const Surface& s, const RayCells& cells, const std::vector<int32_t>& component, int32_t own,
             const std::vector<uint64_t>& mask, const Vec3& p, uint64_t& bits) {
    bits = 0;
    bool on = false;
    cells.for_candidates(p, [&](int32_t t) {
        const Tri& c = s.triangles[size_t(t)];
        if (component[size_t(c[0])] == own || mask[size_t(t)] == 0) return;
        const detail::RayHit h = detail::ray_crosses(p, s.vertices[size_t(c[0])], s.vertices[size_t(c[1])],
                                                     s.vertices[size_t(c[2])]);
        if (h == detail::RayHit::Touches) on = true;
        if (h == detail::RayHit::Cross) bits ^= mask[size_t(t)];
    });
    return !on;
}

std::string material_names(uint64_t b, const std::map<std::string, int>& bits) {
    if (b == 0) return "the unbounded region's material";
    // b holds the material at the vertex and the unbounded region's, which is exterior
    // for label images and one file per material.
    std::vector<std::string> names;
    bool exterior = false;
    for (const auto& [name, bit] : bits)
        if (bit < kUnknownBit && (b >> bit & 1)) {
            if (same_material(name, kExteriorMaterial))
                exterior = true;
            else
                names.push_back(name);
        }
    if (b >> kUnknownBit & 1) names.push_back("what the patches without materials enclose");
    std::string text;
    for (const std::string& n : names) text += (text.empty() ? "" : ", ") + n;
    if (exterior && names.size() == 1) return text;
    return "materials other than the unbounded region's (" + text + (exterior ? ", exterior" : "") + ")";
}

struct ComponentCounts {
    int64_t components = 0, original_components = 0;
    int64_t moved = 0;         // lying in other materials than on S0
    int64_t not_compared = 0;  // a vertex on another component's triangle (an intersection)
};

// What compare_components needs of S and S0: their components and the triangles'
// material bits (only when either has two or more components).
struct ComponentMaterials {
    std::vector<int32_t> comp0, comp;  // per vertex
    ComponentCounts counts;
    std::map<std::string, int> bits;  // material name (lower case) -> bit
    MaterialBits m0, m;
    bool active() const { return counts.original_components > 1 || counts.components > 1; }
};

ComponentMaterials component_materials(const BpmFile& file) {
    ComponentMaterials c;
    c.counts.original_components = vertex_components(file.param.original, c.comp0);
    c.counts.components = vertex_components(file.param.coarse, c.comp);
    if (!c.active()) return c;
    c.m0 = triangle_bits(file.param.original, file.patch_info, c.bits);
    c.m = triangle_bits(file.param.coarse, file.patch_info, c.bits);
    return c;
}

// Every component of S against its component of S0 (through the original id of one of
// its vertices); `open`: the materials left out (their boundary is not closed on S or S0).
void compare_components(const BpmFile& file, ComponentMaterials& c, uint64_t open, CheckResult& r,
                        size_t max_problems) {
    const Parametrization& p = file.param;
    ComponentCounts& counts = c.counts;
    if (!c.active()) return;
    if (!c.m0.usable || !c.m.usable) {
        counts.not_compared = counts.components;
        return;
    }
    const RayCells cells0(p.original), cells(p.coarse);
    std::vector<int32_t> first(size_t(counts.components), -1);
    for (size_t v = 0; v < c.comp.size(); ++v)
        if (c.comp[v] >= 0 && first[size_t(c.comp[v])] < 0) first[size_t(c.comp[v])] = int32_t(v);
    for (int32_t k = 0; k < counts.components; ++k) {
        const int32_t v = first[size_t(k)];
        const int32_t o = p.coarse_vertex_origin[size_t(v)];
        uint64_t on_s = 0, on_s0 = 0;
        if (!lies_in(p.coarse, cells, c.comp, k, c.m.of_patch_triangle, p.coarse.vertices[size_t(v)], on_s) ||
            !lies_in(p.original, cells0, c.comp0, c.comp0[size_t(o)], c.m0.of_patch_triangle,
                     p.original.vertices[size_t(o)], on_s0)) {
            ++counts.not_compared;
            continue;
        }
        on_s &= ~open;
        on_s0 &= ~open;
        if (on_s == on_s0) continue;
        ++counts.moved;
        r.add_problem({{{"coarse_vertex", v}, {"original_vertex", o}},
                       "the component of coarse vertex " + std::to_string(v) + " (original " + std::to_string(o) +
                           ") lies in " + material_names(on_s, c.bits) + " on S but in " +
                           material_names(on_s0, c.bits) + " on S0: a sheet was moved across it"},
                      max_problems);
    }
}

void add_counts(CheckResult& r, const std::string& prefix, const JunctionCounts& c) {
    r.add_count(prefix + "junction_edges", c.junction_edges);
    r.add_count(prefix + "junction_edges_without_materials", c.unknown_materials);
    r.add_count(prefix + "overlapping_junction_edges", c.overlapping);
    r.add_count(prefix + "inconsistent_junction_edges", c.inconsistent);
}

std::string describe(const std::string& what, const JunctionCounts& c) {
    std::string s = detail::count_text(c.junction_edges, "junction edge") + what;
    if (c.junction_edges == 0) return s;
    s += ", " + std::to_string(c.inconsistent) + " with wedges claimed by two materials";
    if (c.overlapping) s += ", " + std::to_string(c.overlapping) + " with overlapping sheets";
    if (c.unknown_materials) s += " (" + std::to_string(c.unknown_materials) + " not checked: materials unknown)";
    return s;
}

}  // namespace

CheckResult check_junctions(const Surface& surface, const std::vector<PatchInfo>& patch_info,
                            const CheckOptions& options, const Context& context) {
    CheckResult r;
    r.name = "junctions";
    if (auto why = detail::surface_unsafe(surface)) {
        detail::refuse(r, *why);
        return r;
    }
    context.report(0.0, "sheets around junction edges");
    const JunctionCounts c = scan_junctions(
        surface, patch_info, "triangle", [](int32_t v) { return "vertex " + std::to_string(v); }, r,
        options.max_problems, nullptr, {});
    add_counts(r, "", c);
    r.summary = describe("", c);
    context.report(1.0, "sheets around junction edges");
    return r;
}

CheckResult check_junctions(const BpmFile& file, const CheckOptions& options, const Context& context) {
    const Parametrization& p = file.param;
    CheckResult r;
    r.name = "junctions";
    if (auto why = detail::parametrization_unsafe(p)) {
        detail::refuse(r, *why);
        return r;
    }
    // S0 is the reference: the check is that S keeps its structure. Where the materials
    // patch_info gives contradict S0 itself (a guess of the reader: one file read as one
    // material, whose inner walls then claim "exterior" on one side), they say nothing
    // about S either: those patches are left out on S, and S0 is only counted.
    context.report(0.0, "sheets around junction edges of the original surface");
    std::vector<int32_t> doubtful;
    ComponentMaterials components = component_materials(file);
    uint64_t open = 0;  // materials whose boundary is not closed (left out of the components' comparison)
    const JunctionCounts original = scan_junctions(
        p.original, file.patch_info, "original_triangle",
        [](int32_t v) { return "original vertex " + std::to_string(v); }, r, options.max_problems, &doubtful, {},
        components.active() ? &components.m0.of_patch_triangle : nullptr, &open);
    std::sort(doubtful.begin(), doubtful.end());
    doubtful.erase(std::unique(doubtful.begin(), doubtful.end()), doubtful.end());
    context.report(0.5, "sheets around junction edges of the coarse surface");
    const JunctionCounts coarse = scan_junctions(
        p.coarse, file.patch_info, "coarse_triangle",
        [&](int32_t v) {
            return "coarse vertex " + std::to_string(v) + " (original " + std::to_string(p.coarse_vertex_origin[v]) + ")";
        },
        r, options.max_problems, nullptr, doubtful, components.active() ? &components.m.of_patch_triangle : nullptr,
        &open);
    add_counts(r, "original_", original);
    add_counts(r, "", coarse);
    r.add_count("patches_contradicting_original", static_cast<int64_t>(doubtful.size()));
    context.report(0.75, "materials around the components");
    compare_components(file, components, open, r, options.max_problems);
    const ComponentCounts& cc = components.counts;
    r.add_count("components", cc.components);
    r.add_count("original_components", cc.original_components);
    r.add_count("components_in_other_materials", cc.moved);
    r.add_count("components_not_compared", cc.not_compared);
    r.summary = describe(" on S", coarse) + "; " + describe(" on S0", original);
    if (components.active()) {
        r.summary += "; " + detail::count_text(cc.components, "component") + ", " + std::to_string(cc.moved) +
                     " lying in other materials than on S0";
        if (cc.not_compared) r.summary += " (" + std::to_string(cc.not_compared) + " not compared)";
    }
    if (!doubtful.empty())
        r.summary += "; the materials of " + std::to_string(doubtful.size()) +
                     " patches contradict S0 (not checked on S)";
    context.report(1.0, "sheets around junction edges");
    return r;
}

}  // namespace bpm
