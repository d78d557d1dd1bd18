#include "phi/phi_layout.h"

#include "bpm/errors.h"

#include <cmath>

namespace bpm::detail {

const char* phi_array_name(PhiArray array) {
    switch (array) {
        case PhiArray::Vertices: return "vertices";
        case PhiArray::Triangles: return "triangles";
        case PhiArray::Patches: return "patches";
        case PhiArray::VertexOrigin: return "vertex_origin";
        case PhiArray::NodeOffsets: return "node_offsets";
        case PhiArray::NodeBarycentric: return "node_barycentric";
        case PhiArray::NodeImage: return "node_image";
        case PhiArray::NodeKind: return "node_kind";
        case PhiArray::NodeOriginalVertex: return "node_original_vertex";
        case PhiArray::NodeOriginalEdge: return "node_original_edge";
        case PhiArray::NodeEdgeParameter: return "node_edge_parameter";
        case PhiArray::PieceOffsets: return "piece_offsets";
        case PhiArray::Pieces: return "pieces";
        case PhiArray::PieceOriginalTriangle: return "piece_original_triangle";
    }
    return "?";
}

namespace {

// The first coordinate of `v` that is not finite, or -1.
int first_non_finite(const Vec3& v) {
    for (int c = 0; c < 3; ++c)
        if (!std::isfinite(v[c])) return c;
    return -1;
}

// Tracks whether anything was reported and whether the sink wants more.
class Visit {
public:
    explicit Visit(const LayoutSink& sink) : sink_(sink) {}
    // Reports `pr`; returns false when the visit must stop.
    bool report(const LayoutProblem& pr) {
        clean_ = false;
        if (go_) go_ = sink_(pr);
        return go_;
    }
    bool clean() const { return clean_; }
    bool go() const { return go_; }

private:
    const LayoutSink& sink_;
    bool clean_ = true;
    bool go_ = true;
};

// One CSR offsets array over the coarse triangles. Stops at its first violation: the
// later rules of the same array are meaningless once one fails.
void visit_offsets(const std::vector<int64_t>& offsets, PhiArray array, int64_t target_rows, int64_t num_triangles,
                   Visit& visit) {
    if (static_cast<int64_t>(offsets.size()) != num_triangles + 1) {
        visit.report({LayoutRule::OffsetsCount, array, SurfaceRole::Alone, -1, -1, -1,
                      static_cast<int64_t>(offsets.size()), num_triangles + 1});
        return;
    }
    if (offsets[0] != 0) {
        visit.report({LayoutRule::OffsetsStart, array, SurfaceRole::Alone, 0, -1, -1, offsets[0], 0});
        return;
    }
    for (size_t i = 1; i < offsets.size(); ++i)
        if (offsets[i] < offsets[i - 1]) {
            visit.report({LayoutRule::OffsetsDecreasing, array, SurfaceRole::Alone, static_cast<int64_t>(i), -1,
                          static_cast<int32_t>(i - 1), offsets[i], offsets[i - 1]});
            return;
        }
    if (offsets.back() != target_rows)
        visit.report({LayoutRule::OffsetsEnd, array, SurfaceRole::Alone, -1, -1, -1, offsets.back(), target_rows});
}

}  // namespace

bool visit_surface_layout(const Surface& s, SurfaceRole role, const LayoutSink& sink, bool need_patches) {
    Visit visit(sink);
    const int64_t nv = static_cast<int64_t>(s.vertices.size());
    for (int64_t v = 0; v < nv; ++v)
        if (const int c = first_non_finite(s.vertices[static_cast<size_t>(v)]); c >= 0)
            if (!visit.report({LayoutRule::NotFinite, PhiArray::Vertices, role, v, c})) return false;
    for (size_t t = 0; t < s.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int64_t v = s.triangles[t][k];
            if (v < 0 || v >= nv)
                if (!visit.report({LayoutRule::OutOfRange, PhiArray::Triangles, role, static_cast<int64_t>(t), k, -1,
                                   v, nv}))
                    return false;
        }
    if (need_patches && s.patches.size() != s.triangles.size())
        visit.report({LayoutRule::CountMismatch, PhiArray::Patches, role, -1, -1, -1,
                      static_cast<int64_t>(s.patches.size()), static_cast<int64_t>(s.triangles.size())});
    return visit.clean();
}

bool visit_phi_layout(const Parametrization& p, const LayoutSink& sink) {
    Visit visit(sink);
    const LayoutSink forward = [&](const LayoutProblem& pr) { return visit.report(pr); };
    visit_surface_layout(p.original, SurfaceRole::Original, forward);
    if (!visit.go()) return false;
    visit_surface_layout(p.coarse, SurfaceRole::Coarse, forward);
    if (!visit.clean()) return false;

    const int64_t ntc = static_cast<int64_t>(p.coarse.triangles.size());
    const int64_t nn = p.num_nodes();
    const int64_t np = p.num_pieces();
    const auto count = [&](size_t size, int64_t expected, PhiArray array) {
        if (static_cast<int64_t>(size) != expected)
            visit.report({LayoutRule::CountMismatch, array, SurfaceRole::Alone, -1, -1, -1, static_cast<int64_t>(size),
                          expected});
        return visit.go();
    };
    if (!count(p.coarse_vertex_origin.size(), static_cast<int64_t>(p.coarse.vertices.size()), PhiArray::VertexOrigin) ||
        !count(p.node_barycentric.size(), nn, PhiArray::NodeBarycentric) ||
        !count(p.node_image.size(), nn, PhiArray::NodeImage) ||
        !count(p.node_original_vertex.size(), nn, PhiArray::NodeOriginalVertex) ||
        !count(p.node_original_edge.size(), nn, PhiArray::NodeOriginalEdge) ||
        !count(p.node_edge_parameter.size(), nn, PhiArray::NodeEdgeParameter) ||
        !count(p.piece_original_triangle.size(), np, PhiArray::PieceOriginalTriangle))
        return false;
    visit_offsets(p.node_offsets, PhiArray::NodeOffsets, nn, ntc, visit);
    if (!visit.go()) return false;
    visit_offsets(p.piece_offsets, PhiArray::PieceOffsets, np, ntc, visit);
    if (!visit.clean()) return false;

    // From here on every index below is known to be in range.
    const int64_t nv0 = static_cast<int64_t>(p.original.vertices.size());
    const int64_t nt0 = static_cast<int64_t>(p.original.triangles.size());
    for (size_t c = 0; c < p.coarse_vertex_origin.size(); ++c) {
        const int32_t o = p.coarse_vertex_origin[c];
        if (o < 0 || o >= nv0)
            if (!visit.report({LayoutRule::OutOfRange, PhiArray::VertexOrigin, SurfaceRole::Alone,
                               static_cast<int64_t>(c), -1, -1, o, nv0}))
                return false;
    }
    for (int64_t n = 0; n < nn; ++n) {
        const size_t i = static_cast<size_t>(n);
        const auto kind = static_cast<uint8_t>(p.node_kind[i]);
        if (kind > 2) {
            if (!visit.report({LayoutRule::InvalidNodeKind, PhiArray::NodeKind, SurfaceRole::Alone, n, -1, -1, kind}))
                return false;
            continue;  // the other rules depend on the kind
        }
        if (const int c = first_non_finite(p.node_barycentric[i]); c >= 0)
            if (!visit.report({LayoutRule::NotFinite, PhiArray::NodeBarycentric, SurfaceRole::Alone, n, c}))
                return false;
        if (const int c = first_non_finite(p.node_image[i]); c >= 0)
            if (!visit.report({LayoutRule::NotFinite, PhiArray::NodeImage, SurfaceRole::Alone, n, c})) return false;
        if (p.node_kind[i] == NodeKind::EdgeCrossing) {
            const auto& e = p.node_original_edge[i];
            if (e[0] < 0 || e[1] >= nv0 || e[0] >= e[1])
                if (!visit.report({LayoutRule::NotAnEdge, PhiArray::NodeOriginalEdge, SurfaceRole::Alone, n, -1, -1, 0,
                                   nv0}))
                    return false;
            if (!std::isfinite(p.node_edge_parameter[i]))
                if (!visit.report({LayoutRule::NotFinite, PhiArray::NodeEdgeParameter, SurfaceRole::Alone, n}))
                    return false;
        } else {
            const int32_t v = p.node_original_vertex[i];
            if (v < 0 || v >= nv0)
                if (!visit.report({LayoutRule::OutOfRange, PhiArray::NodeOriginalVertex, SurfaceRole::Alone, n, -1, -1,
                                   v, nv0}))
                    return false;
        }
    }
    for (int64_t t = 0; t < ntc; ++t) {
        const size_t ti = static_cast<size_t>(t);
        const int64_t nodes = p.node_offsets[ti + 1] - p.node_offsets[ti];
        for (int64_t q = p.piece_offsets[ti]; q < p.piece_offsets[ti + 1]; ++q) {
            const size_t qi = static_cast<size_t>(q);
            for (int k = 0; k < 3; ++k) {
                const int32_t local = p.pieces[qi][k];
                if (local < 0 || local >= nodes)
                    if (!visit.report({LayoutRule::OutOfRange, PhiArray::Pieces, SurfaceRole::Alone, q, k,
                                       static_cast<int32_t>(t), local, nodes}))
                        return false;
            }
            const int32_t o = p.piece_original_triangle[qi];
            if (o < 0 || o >= nt0)
                if (!visit.report({LayoutRule::OutOfRange, PhiArray::PieceOriginalTriangle, SurfaceRole::Alone, q, -1,
                                   static_cast<int32_t>(t), o, nt0}))
                    return false;
        }
    }
    return visit.clean();
}

void require_coordinates_in_range(const Parametrization& p) {
    for (const Surface* surface : {&p.original, &p.coarse})
        if (std::string why = coordinate_range_problem(*surface); !why.empty()) throw AlgorithmError(std::move(why));
}

}  // namespace bpm::detail
