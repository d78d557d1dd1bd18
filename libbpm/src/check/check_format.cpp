// check_format: the in-memory invariants of a parametrization (parametrization.h and
// spec/bpm-format.md). read_bpm already refuses files it cannot read; this re-verifies
// everything the other checks and the evaluator rely on, so that a file produced by a
// buggy writer, or a structure built in memory, is caught with the element at fault.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "bpm/check.h"
#include "bpm/phi_triangle.h"
#include "check/check_internal.h"
#include "check/image_tolerance.h"
#include "core/edge_key.h"
#include "core/number_text.h"
#include "phi/phi_layout.h"

namespace bpm {

namespace {

using Sink = std::function<bool(CheckProblem)>;  // returns false to stop

CheckProblem problem(std::vector<std::pair<std::string, int64_t>> ids, std::string message) {
    return CheckProblem{std::move(ids), std::move(message)};
}

std::string vec_text(const Vec3& v) {
    return "(" + detail::format_number(v[0]) + ", " + detail::format_number(v[1]) + ", " + detail::format_number(v[2]) + ")";
}

// bpm-check's wording of a layout problem: element ids, and a message naming the
// in-memory array. `which` prefixes the element kinds of surface problems ("original",
// "coarse", or "surface" for a surface on its own).
CheckProblem layout_problem(const Parametrization* p, const Surface& s, const std::string& which,
                            const detail::LayoutProblem& pr) {
    using detail::LayoutRule;
    using detail::PhiArray;
    const std::string name = detail::phi_array_name(pr.array);
    const int64_t e = pr.element;
    switch (pr.rule) {
        case LayoutRule::NotFinite:
            if (pr.array == PhiArray::Vertices)
                return problem({{which + "_vertex", e}}, "non-finite coordinate " + vec_text(s.vertices[e]));
            if (pr.array == PhiArray::NodeBarycentric)
                return problem({{"node", e}}, "non-finite barycentric coordinates " + vec_text(p->node_barycentric[e]));
            if (pr.array == PhiArray::NodeImage)
                return problem({{"node", e}}, "non-finite image " + vec_text(p->node_image[e]));
            return problem({{"node", e}}, "edge crossing with non-finite edge parameter");
        case LayoutRule::CountMismatch:
            if (pr.array == PhiArray::Patches)
                return problem({}, which + " surface has " + std::to_string(pr.value) + " patch ids for " +
                                       std::to_string(pr.limit) + " triangles");
            if (pr.array == PhiArray::VertexOrigin)
                return problem({}, "coarse_vertex_origin has " + std::to_string(pr.value) + " entries for " +
                                       std::to_string(pr.limit) + " coarse vertices");
            if (pr.array == PhiArray::PieceOriginalTriangle)
                return problem({}, "piece_original_triangle has " + std::to_string(pr.value) + " entries for " +
                                       std::to_string(pr.limit) + " pieces");
            return problem({}, name + " has " + std::to_string(pr.value) + " entries, node_kind has " +
                                   std::to_string(pr.limit));
        case LayoutRule::OutOfRange: {
            const std::string range = ", out of range [0, " + std::to_string(pr.limit) + ")";
            if (pr.array == PhiArray::Triangles)
                return problem({{which + "_triangle", e}}, "corner " + std::to_string(pr.component) + " is vertex " +
                                                               std::to_string(pr.value) + range);
            if (pr.array == PhiArray::Pieces)
                return problem({{"coarse_triangle", pr.coarse_triangle}, {"piece", e}},
                               "corner " + std::to_string(pr.component) + " is local node " +
                                   std::to_string(pr.value) + range);
            const std::string plain_range = " is out of range [0, " + std::to_string(pr.limit) + ")";
            if (pr.array == PhiArray::VertexOrigin)
                return problem({{"coarse_vertex", e}}, "coarse_vertex_origin " + std::to_string(pr.value) + plain_range);
            if (pr.array == PhiArray::PieceOriginalTriangle)
                return problem({{"coarse_triangle", pr.coarse_triangle}, {"piece", e}},
                               "original triangle " + std::to_string(pr.value) + plain_range);
            return problem({{"node", e}}, "original vertex " + std::to_string(pr.value) + plain_range);
        }
        case LayoutRule::OffsetsCount:
            return problem({}, name + " has " + std::to_string(pr.value) + " entries, expected #coarse triangles + 1 = " +
                                   std::to_string(pr.limit));
        case LayoutRule::OffsetsStart: return problem({}, name + "[0] is " + std::to_string(pr.value) + ", expected 0");
        case LayoutRule::OffsetsDecreasing:
            return problem({{"coarse_triangle", pr.coarse_triangle}},
                           name + "[" + std::to_string(e) + "] = " + std::to_string(pr.value) + " is less than " + name +
                               "[" + std::to_string(e - 1) + "] = " + std::to_string(pr.limit));
        case LayoutRule::OffsetsEnd:
            return problem({}, name + " ends at " + std::to_string(pr.value) + ", but there are " +
                                   std::to_string(pr.limit) + " entries");
        case LayoutRule::InvalidNodeKind:
            return problem({{"node", e}}, "node_kind " + std::to_string(pr.value) + " is not 0, 1 or 2");
        case LayoutRule::NotAnEdge: {
            const auto& oe = p->node_original_edge[e];
            return problem({{"node", e}}, "edge crossing on original edge (" + std::to_string(oe[0]) + ", " +
                                              std::to_string(oe[1]) + "): not two vertices u < w in range");
        }
    }
    return problem({}, name + ": invalid layout");
}

// Everything needed to index safely (phi_layout.h), and coordinates in the range bpm
// computes in (bpm/surface.h: beyond it the measures the other checks take overflow, and
// a file written elsewhere may hold anything). Reports through `sink`; returns true when
// safe.
bool structure(const Parametrization& p, const Sink& sink) {
    if (!detail::visit_phi_layout(p, [&](const detail::LayoutProblem& pr) {
            const bool original = pr.surface == detail::SurfaceRole::Original;
            return sink(layout_problem(&p, original ? p.original : p.coarse, original ? "original" : "coarse", pr));
        }))
        return false;
    for (const auto& [surface, which] : {std::pair{&p.original, "original"}, std::pair{&p.coarse, "coarse"}})
        if (const std::string why = coordinate_range_problem(*surface); !why.empty()) {
            sink(problem({}, std::string(which) + " surface: " + why));
            return false;
        }
    return true;
}

using detail::edge_key;

}  // namespace

namespace detail {

std::optional<std::string> parametrization_unsafe(const Parametrization& param) {
    std::optional<std::string> first;
    structure(param, [&](CheckProblem p) {
        first = "the format check failed (" + p.describe() + ")";
        return false;
    });
    return first;
}

std::optional<std::string> surface_unsafe(const Surface& surface) {
    std::optional<std::string> first;
    // Patch ids are optional here: intersections and quality do not use them, and
    // compute_topology treats missing ones as patch 0.
    detail::visit_surface_layout(
        surface, detail::SurfaceRole::Alone,
        [&](const detail::LayoutProblem& pr) {
            first = layout_problem(nullptr, surface, "surface", pr).describe();
            return false;
        },
        false);
    return first;
}

}  // namespace detail

namespace {

// `stored`: the images a format 1.x file stored (BpmFile::stored_node_image), compared
// with the recomputation instead of p.node_image; null for p.node_image itself.
CheckResult check_format_of(const Parametrization& p, const std::vector<Vec3>* stored, const CheckOptions& options,
                            const Context& context) {
    CheckResult r;
    r.name = "format";
    const size_t maxp = options.max_problems;
    auto add = [&](std::vector<std::pair<std::string, int64_t>> ids, std::string message) {
        r.add_problem(problem(std::move(ids), std::move(message)), maxp);
    };
    context.report(0.0, "checking format");
    const bool safe = structure(p, [&](CheckProblem pr) {
        r.add_problem(std::move(pr), maxp);
        return true;
    });
    r.add_count("original_vertices", p.original.num_vertices());
    r.add_count("original_triangles", p.original.num_triangles());
    r.add_count("coarse_vertices", p.coarse.num_vertices());
    r.add_count("coarse_triangles", p.coarse.num_triangles());
    r.add_count("nodes", p.num_nodes());
    r.add_count("pieces", p.num_pieces());
    if (!safe) {
        r.summary = detail::count_text(r.problem_count, "structural problem");
        return r;
    }

    const double diagonal = bounding_box_diagonal(p.original);
    const double tolerance = detail::kImageToleranceRelativeToDiagonal * diagonal;
    const double bary_tolerance = 1e-12;  // dimensionless
    double worst = 0.0;
    std::vector<std::pair<std::string, int64_t>> worst_ids;
    auto deviation = [&](double d, std::vector<std::pair<std::string, int64_t>> ids) {
        const double rel = diagonal > 0 ? d / diagonal : d;
        if (rel > worst || (worst_ids.empty() && rel >= worst)) {
            worst = rel;
            worst_ids = std::move(ids);
        }
    };

    // Coarse vertices are original vertices: distinct and at the same place.
    {
        std::vector<int32_t> seen(p.original.vertices.size(), -1);
        for (int32_t c = 0; c < p.coarse.num_vertices(); ++c) {
            const int32_t o = p.coarse_vertex_origin[c];
            if (seen[o] >= 0)
                add({{"coarse_vertex", c}}, "same original vertex " + std::to_string(o) + " as coarse vertex " +
                                                std::to_string(seen[o]));
            seen[o] = c;
            const double d = distance(p.coarse.vertices[c], p.original.vertices[o]);
            deviation(d, {{"coarse_vertex", c}});
            if (!(d <= tolerance))
                add({{"coarse_vertex", c}}, "position " + vec_text(p.coarse.vertices[c]) + " differs from original vertex " +
                                                std::to_string(o) + " at " + vec_text(p.original.vertices[o]) +
                                                " by " + detail::format_number(d));
        }
    }

    // Original edges, for EdgeCrossing identities.
    std::vector<uint64_t> original_edges;
    original_edges.reserve(p.original.triangles.size() * 3);
    for (const Tri& tri : p.original.triangles)
        for (int k = 0; k < 3; ++k) original_edges.push_back(edge_key(tri[k], tri[(k + 1) % 3]));
    std::sort(original_edges.begin(), original_edges.end());
    original_edges.erase(std::unique(original_edges.begin(), original_edges.end()), original_edges.end());

    const int32_t nt = p.coarse.num_triangles();
    for (int32_t t = 0; t < nt; ++t) {
        if ((t & 0xfff) == 0) context.report(static_cast<double>(t) / std::max(nt, 1), "checking format");
        int corner_node[3] = {-1, -1, -1};
        const PhiTriangle phi(p, t);
        for (int64_t i = 0; i < phi.num_nodes(); ++i) {
            const int64_t n = phi.first_node() + i;
            const std::vector<std::pair<std::string, int64_t>> ids{{"coarse_triangle", t}, {"node", n}};
            const Vec3& b = phi.barycentric(i);
            const NodeKind kind = phi.kind(i);
            if (b[0] < 0 || b[1] < 0 || b[2] < 0) add(ids, "negative barycentric coordinate " + vec_text(b));
            const double sum = b[0] + b[1] + b[2];
            if (!(std::abs(sum - 1.0) <= bary_tolerance))
                add(ids, "barycentric coordinates " + vec_text(b) + " sum to " + detail::format_number(sum) + ", not 1");
            const int zeros = (b[0] == 0) + (b[1] == 0) + (b[2] == 0);
            Vec3 expected{0, 0, 0};
            bool identity_ok = true;
            if (kind == NodeKind::CoarseCorner) {
                int k = -1;
                for (int j = 0; j < 3; ++j)
                    if (b[j] == 1.0 && b[(j + 1) % 3] == 0.0 && b[(j + 2) % 3] == 0.0) k = j;
                if (k < 0) {
                    add(ids, "coarse corner node at " + vec_text(b) + ", not exactly at a corner (a unit vector)");
                } else {
                    if (corner_node[k] >= 0)
                        add(ids, "second node at corner " + std::to_string(k) + " (first: node " +
                                     std::to_string(corner_node[k]) + ")");
                    corner_node[k] = static_cast<int>(n);
                    const int32_t c = phi.corners()[k];
                    if (phi.original_vertex(i) != p.coarse_vertex_origin[c])
                        add(ids, "corner " + std::to_string(k) + " is coarse vertex " + std::to_string(c) +
                                     " = original vertex " + std::to_string(p.coarse_vertex_origin[c]) +
                                     ", but the node names original vertex " + std::to_string(phi.original_vertex(i)));
                }
            } else if (zeros >= 2) {
                add(ids, "node at a corner " + vec_text(b) + " must be of kind CoarseCorner");
            }
            if (kind == NodeKind::EdgeCrossing) {
                if (zeros != 1) add(ids, "edge crossing at " + vec_text(b) + " is not on a coarse edge (needs exactly one zero)");
                const auto& e = phi.original_edge(i);
                const double s = phi.edge_parameter(i);
                if (phi.original_vertex(i) != -1)
                    add(ids, "edge crossing names original vertex " + std::to_string(phi.original_vertex(i)) +
                                 "; expected -1");
                if (!std::binary_search(original_edges.begin(), original_edges.end(), edge_key(e[0], e[1]))) {
                    add(ids, "original edge (" + std::to_string(e[0]) + ", " + std::to_string(e[1]) +
                                 ") does not exist in the original surface");
                    identity_ok = false;
                }
                if (!(s > 0.0 && s < 1.0)) {
                    add(ids, "edge parameter " + detail::format_number(s) + " is not strictly between 0 and 1");
                }
            } else {
                const auto& e = phi.original_edge(i);
                if (e != std::array<int32_t, 2>{-1, -1})
                    add(ids, "vertex node names original edge (" + std::to_string(e[0]) + ", " + std::to_string(e[1]) +
                                 "); expected (-1, -1)");
                if (!std::isnan(phi.edge_parameter(i)))
                    add(ids, "vertex node has edge parameter " + detail::format_number(phi.edge_parameter(i)) +
                                 "; expected NaN");
            }
            if (identity_ok) {
                // Indices were range-checked by structure(); the writer uses the same function.
                expected = node_image_from_kind(p, n);
                const Vec3& image = stored ? (*stored)[static_cast<size_t>(n)] : phi.image(i);
                const double d = distance(expected, image);
                deviation(d, ids);
                if (!(d <= tolerance))
                    add(ids, std::string(stored ? "stored image " : "image ") + vec_text(image) +
                                 " differs from the point the node names " +
                                 vec_text(expected) + " by " + detail::format_number(d) + " (tolerance " +
                                 detail::format_number(tolerance) + ")");
            }
        }
        for (int k = 0; k < 3; ++k)
            if (corner_node[k] < 0) add({{"coarse_triangle", t}}, "no CoarseCorner node at corner " + std::to_string(k));
        for (int64_t j = 0; j < phi.num_pieces(); ++j) {
            const Tri& piece = phi.piece(j);
            if (piece[0] == piece[1] || piece[1] == piece[2] || piece[0] == piece[2])
                add({{"coarse_triangle", t}, {"piece", phi.first_piece() + j}},
                    "repeated corner: local nodes " + std::to_string(piece[0]) + ", " + std::to_string(piece[1]) + ", " +
                        std::to_string(piece[2]) + " (nodes " + std::to_string(phi.piece_node(j, 0)) + "...)");
        }
    }
    r.worst = WorstValue{"image_deviation_relative_to_diagonal", worst, worst_ids};
    r.summary = std::to_string(p.coarse.num_triangles()) + " coarse triangles, " + std::to_string(p.num_nodes()) +
                " nodes, " + std::to_string(p.num_pieces()) + " pieces, largest image deviation " +
                detail::format_number(worst) + " of the diagonal";
    context.report(1.0, "checking format");
    return r;
}

}  // namespace

CheckResult check_format(const Parametrization& p, const CheckOptions& options, const Context& context) {
    return check_format_of(p, nullptr, options, context);
}

CheckResult check_format(const BpmFile& file, const CheckOptions& options, const Context& context) {
    // A 1.x file's stored images must be the points their nodes name (spec §6.2 of 1.x);
    // param.node_image is that recomputation already.
    const bool stored = file.stored_node_image.size() == file.param.node_image.size() && !file.stored_node_image.empty();
    return check_format_of(file.param, stored ? &file.stored_node_image : nullptr, options, context);
}

}  // namespace bpm
