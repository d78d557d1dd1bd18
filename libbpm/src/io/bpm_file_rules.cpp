// The format's own rules (io/bpm_file_rules.h), as spec/bpm-format.md states them.
#include "io/bpm_file_rules.h"

#include <cmath>
#include <limits>

#include "bpm/version.h"
#include "phi/phi_layout.h"

namespace bpm {

BpmFormatVersion bpm_format_version() { return {BPM_FORMAT_VERSION_MAJOR, BPM_FORMAT_VERSION_MINOR}; }

namespace detail {

namespace {

// The file-format wording of a layout problem: the dataset path first, then the entry.
std::string layout_message(const Parametrization& p, const LayoutProblem& pr) {
    const bool on_surface = pr.array == PhiArray::Vertices || pr.array == PhiArray::Triangles ||
                            pr.array == PhiArray::Patches;
    const Surface& s = pr.surface == SurfaceRole::Original ? p.original : p.coarse;
    const std::string group = pr.surface == SurfaceRole::Original ? "/original" : "/coarse";
    const std::string path = on_surface                          ? group + "/" + phi_array_name(pr.array)
                             : pr.array == PhiArray::VertexOrigin ? std::string("/coarse/vertex_origin")
                                                                  : std::string("/phi/") + phi_array_name(pr.array);
    const size_t e = static_cast<size_t>(pr.element);
    switch (pr.rule) {
        case LayoutRule::NotFinite:
            if (pr.array == PhiArray::Vertices)
                return path + ": entry [" + num_text(pr.element) + ", " + num_text(pr.component) + "] is not finite (" +
                       num_text(s.vertices[e][pr.component]) + ")";
            if (pr.array == PhiArray::NodeEdgeParameter)
                return path + ": entry " + num_text(pr.element) + " = " + num_text(p.node_edge_parameter[e]) +
                       " is not in [0, 1] for an edge crossing";
            return path + ": entry [" + num_text(pr.element) + ", " + num_text(pr.component) + "] is not finite";
        case LayoutRule::CountMismatch:
            if (pr.array == PhiArray::Patches)
                return path + ": has " + num_text(pr.value) + " entries but " + group + "/triangles has " + num_text(pr.limit) +
                       " rows";
            if (pr.array == PhiArray::VertexOrigin)
                return path + ": has " + num_text(pr.value) + " entries but /coarse/vertices has " + num_text(pr.limit) + " rows";
            if (pr.array == PhiArray::PieceOriginalTriangle)
                return path + ": has " + num_text(pr.value) + " entries but /phi/pieces has " + num_text(pr.limit) + " rows";
            return path + ": has " + num_text(pr.value) + " rows but /phi/node_kind has " + num_text(pr.limit);
        case LayoutRule::OutOfRange: {
            const std::string range = " is out of range [0, " + num_text(pr.limit) + ")";
            if (pr.array == PhiArray::Triangles)
                return path + ": entry [" + num_text(pr.element) + ", " + num_text(pr.component) + "] = " + num_text(pr.value) + range +
                       " (number of rows of " + group + "/vertices)";
            if (pr.array == PhiArray::Pieces)
                return path + ": entry [" + num_text(pr.element) + ", " + num_text(pr.component) + "] = " + num_text(pr.value) + range +
                       " (the nodes of coarse triangle " + num_text(pr.coarse_triangle) + ")";
            const std::string entry = path + ": entry " + num_text(pr.element) + " = " + num_text(pr.value) + range;
            if (pr.array == PhiArray::VertexOrigin) return entry + " (number of rows of /original/vertices)";
            if (pr.array == PhiArray::PieceOriginalTriangle) return entry + " (number of rows of /original/triangles)";
            return entry + " for a node of kind " + num_text(static_cast<int>(p.node_kind[e]));
        }
        case LayoutRule::OffsetsCount:
            return path + ": has " + num_text(pr.value) + " entries, expected " + num_text(pr.limit) +
                   " (number of rows of /coarse/triangles + 1)";
        case LayoutRule::OffsetsStart: return path + ": entry 0 is " + num_text(pr.value) + ", must be 0";
        case LayoutRule::OffsetsDecreasing:
            return path + ": entry " + num_text(pr.element) + " = " + num_text(pr.value) + " is smaller than entry " +
                   num_text(pr.element - 1) + " = " + num_text(pr.limit) + "; offsets must be non-decreasing";
        case LayoutRule::OffsetsEnd:
            return path + ": last entry is " + num_text(pr.value) + " but " +
                   (pr.array == PhiArray::NodeOffsets ? "/phi/node_kind" : "/phi/pieces") + " has " + num_text(pr.limit) +
                   " rows";
        case LayoutRule::InvalidNodeKind:
            return path + ": entry " + num_text(pr.element) + " = " + num_text(pr.value) + " is not a valid node kind (0, 1 or 2)";
        case LayoutRule::NotAnEdge: {
            const auto& oe = p.node_original_edge[e];
            return path + ": row " + num_text(pr.element) + " = (" + num_text(oe[0]) + ", " + num_text(oe[1]) +
                   ") is not an edge (u, w) with 0 <= u < w < " + num_text(pr.limit);
        }
    }
    return path + ": invalid";
}

}  // namespace

std::string find_inconsistency(const BpmFile& file) {
    const Parametrization& p = file.param;
    std::string first;
    visit_phi_layout(p, [&](const LayoutProblem& pr) {
        first = layout_message(p, pr);
        return false;
    });
    if (!first.empty()) return first;
    if (const auto bad = vertex_data_problems(p.original); !bad.empty()) return "/original/point_data: " + bad[0];
    for (const VertexArray& a : p.original.vertex_data)
        for (size_t i = 0; i < a.values.size(); ++i)
            if (!std::isfinite(a.values[i]))
                return "/original/point_data/" + a.name + ": entry [" + num_text(i / size_t(a.components)) + ", " +
                       num_text(i % size_t(a.components)) + "] is not finite (" + num_text(a.values[i]) + ")";
    if (p.original.vertices.size() > size_t(std::numeric_limits<int32_t>::max()) ||
        p.original.triangles.size() > size_t(std::numeric_limits<int32_t>::max()) ||
        p.coarse.vertices.size() > size_t(std::numeric_limits<int32_t>::max()) ||
        p.coarse.triangles.size() > size_t(std::numeric_limits<int32_t>::max()))
        return "/original or /coarse: more than 2^31-1 vertices or triangles";

    // Value rules; the layout above makes every index safe.
    const int64_t ntc = p.coarse.num_triangles();
    for (int64_t t = 0; t < ntc; ++t) {
        const Tri& tri = p.coarse.triangles[static_cast<size_t>(t)];
        for (int64_t i = p.node_offsets[static_cast<size_t>(t)]; i < p.node_offsets[static_cast<size_t>(t) + 1]; ++i) {
            const size_t n = static_cast<size_t>(i);
            const Vec3& b = p.node_barycentric[n];
            for (int c = 0; c < 3; ++c)
                if (b[c] < 0)
                    return "/phi/node_barycentric: entry [" + num_text(i) + ", " + num_text(c) + "] = " + num_text(b[c]) +
                           " is negative";
            if (std::fabs(b[0] + b[1] + b[2] - 1) > 1e-9)
                return "/phi/node_barycentric: row " + num_text(i) + " sums to " + num_text(b[0] + b[1] + b[2]) + ", not 1";
            const int kind = static_cast<int>(p.node_kind[n]);
            const int32_t ov = p.node_original_vertex[n];
            const auto& oe = p.node_original_edge[n];
            const double s = p.node_edge_parameter[n];
            if (kind == int(NodeKind::OriginalVertex) || kind == int(NodeKind::CoarseCorner)) {
                if (oe[0] != -1 || oe[1] != -1)
                    return "/phi/node_original_edge: row " + num_text(i) + " must be (-1, -1) for a node of kind " + num_text(kind);
                if (kind == int(NodeKind::CoarseCorner)) {
                    int corner = -1;
                    for (int c = 0; c < 3; ++c)
                        if (b[c] == 1) corner = c;
                    if (corner < 0)
                        return "/phi/node_barycentric: row " + num_text(i) +
                               " is a coarse corner (kind 2) but not a unit vector";
                    const int32_t expected = p.coarse_vertex_origin[static_cast<size_t>(tri[corner])];
                    if (ov != expected)
                        return "/phi/node_original_vertex: entry " + num_text(i) + " = " + num_text(ov) + " is corner " +
                               num_text(corner) + " of coarse triangle " + num_text(t) + ", whose /coarse/vertex_origin is " +
                               num_text(expected);
                }
            } else {  // EdgeCrossing: the layout admits no other kind
                if (ov != -1)
                    return "/phi/node_original_vertex: entry " + num_text(i) + " must be -1 for an edge crossing (kind 1)";
                if (!(s >= 0 && s <= 1))
                    return "/phi/node_edge_parameter: entry " + num_text(i) + " = " + num_text(s) +
                           " is not in [0, 1] for an edge crossing";
                if (b[0] != 0 && b[1] != 0 && b[2] != 0)
                    return "/phi/node_barycentric: row " + num_text(i) +
                           " is an edge crossing (kind 1) but has no coordinate exactly 0 (not on a coarse edge)";
            }
        }
    }
    return {};
}

std::string find_steps_inconsistency(const SimplificationSteps& s, int64_t nv0) {
    const std::string g = "/simplification_steps";
    const int64_t ns = s.num_steps(), nr = s.num_triangles();
    if (static_cast<int64_t>(s.triangle_offsets.size()) != ns + 1)
        return g + "/triangle_offsets: has " + num_text(s.triangle_offsets.size()) + " entries, expected " + num_text(ns + 1) +
               " (entries of " + g + "/vertex + 1)";
    if (static_cast<int64_t>(s.triangle_patches.size()) != nr)
        return g + "/triangle_patches: has " + num_text(s.triangle_patches.size()) + " entries but " + g +
               "/triangles has " + num_text(nr) + " rows";
    for (int64_t i = 0; i < ns; ++i) {
        const int64_t v = s.vertex[static_cast<size_t>(i)];
        if (v < 0 || v >= nv0)
            return g + "/vertex: entry " + num_text(i) + " = " + num_text(v) + " is out of range [0, " + num_text(nv0) +
                   ") (number of rows of /original/vertices)";
    }
    if (s.triangle_offsets[0] != 0)
        return g + "/triangle_offsets: entry 0 is " + num_text(s.triangle_offsets[0]) + ", must be 0";
    for (size_t i = 1; i < s.triangle_offsets.size(); ++i)
        if (s.triangle_offsets[i] < s.triangle_offsets[i - 1])
            return g + "/triangle_offsets: entry " + num_text(i) + " = " + num_text(s.triangle_offsets[i]) +
                   " is smaller than entry " + num_text(i - 1) + " = " + num_text(s.triangle_offsets[i - 1]) +
                   "; offsets must be non-decreasing";
    if (s.triangle_offsets.back() != nr)
        return g + "/triangle_offsets: last entry is " + num_text(s.triangle_offsets.back()) + " but " + g +
               "/triangles has " + num_text(nr) + " rows";
    for (int64_t t = 0; t < nr; ++t)
        for (int c = 0; c < 3; ++c) {
            const int64_t v = s.triangles[static_cast<size_t>(t)][c];
            if (v < 0 || v >= nv0)
                return g + "/triangles: entry [" + num_text(t) + ", " + num_text(c) + "] = " + num_text(v) + " is out of range [0, " +
                       num_text(nv0) + ") (number of rows of /original/vertices)";
        }
    return {};
}

}  // namespace detail

}  // namespace bpm
