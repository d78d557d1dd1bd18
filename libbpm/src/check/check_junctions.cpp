// check_junctions: around every edge where three or more triangles meet, the wedges
// between consecutive sheets are claimed by the same material from both sides. The
// triangles are sorted around the edge with exact predicates (core/sheet_order.h); a
// triangle's side towards a wedge is its front (where its normal points) or its back,
// and patch_info says which material each side of its patch faces. A sheet turned past
// another around their common edge intersects nothing, so the intersection check
// passes, but the volume regions change: bpm-mesh then finds regions whose sides
// disagree about their material.
#include <algorithm>
#include <cctype>

#include "bpm/check.h"
#include "bpm/patch_info.h"
#include "bpm/surface_topology.h"
#include "check/check_internal.h"
#include "core/number_text.h"
#include "core/sheet_order.h"

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
                              const std::vector<int32_t>& doubtful) {
    JunctionCounts counts;
    const SurfaceConnectivity conn = build_connectivity(surface);
    const bool have_patches = surface.patches.size() == surface.triangles.size();
    std::vector<int32_t> tris, order;
    std::vector<Vec3> apexes;
    std::vector<int8_t> forward;  // the triangle runs a -> b
    std::vector<const PatchInfo*> info;
    for (int32_t e = 0; e < conn.num_edges(); ++e) {
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
    const JunctionCounts original = scan_junctions(
        p.original, file.patch_info, "original_triangle",
        [](int32_t v) { return "original vertex " + std::to_string(v); }, r, options.max_problems, &doubtful, {});
    std::sort(doubtful.begin(), doubtful.end());
    doubtful.erase(std::unique(doubtful.begin(), doubtful.end()), doubtful.end());
    context.report(0.5, "sheets around junction edges of the coarse surface");
    const JunctionCounts coarse = scan_junctions(
        p.coarse, file.patch_info, "coarse_triangle",
        [&](int32_t v) {
            return "coarse vertex " + std::to_string(v) + " (original " + std::to_string(p.coarse_vertex_origin[v]) + ")";
        },
        r, options.max_problems, nullptr, doubtful);
    add_counts(r, "original_", original);
    add_counts(r, "", coarse);
    r.add_count("patches_contradicting_original", static_cast<int64_t>(doubtful.size()));
    r.summary = describe(" on S", coarse) + "; " + describe(" on S0", original);
    if (!doubtful.empty())
        r.summary += "; the materials of " + std::to_string(doubtful.size()) +
                     " patches contradict S0 (not checked on S)";
    context.report(1.0, "sheets around junction edges");
    return r;
}

}  // namespace bpm
