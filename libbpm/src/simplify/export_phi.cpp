#include "simplify/export_phi.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>

#include "bpm/errors.h"
#include "phi/phi_triangle_data.h"
#include "simplify/overlay.h"

namespace bpm::detail {

namespace {

// Consecutive coarse triangles exported by one task, into a Parametrization of their own
// (node_* and piece* arrays, offsets from 0); the chunks are concatenated in order.
struct ExportChunk {
    size_t begin = 0, end = 0;  // into the alive triangles
    Parametrization part;
    double max_deviation = 0.0;
    size_t failed = SIZE_MAX;   // index into the alive triangles of the first invalid one
    std::string why;
};

void export_chunk(const Surface& original, const CoarseMesh& mesh, const Embedding& embedding,
                  const std::vector<int8_t>& sign, const std::vector<int32_t>& alive, ExportChunk& chunk) {
    TriangleGraph graph;
    std::vector<OverlayFace> faces;
    std::vector<Tri> pieces;
    std::vector<int32_t> piece_triangle;
    PhiTriangleData phi_t;  // phi on one coarse triangle, reused for every triangle of the chunk
    const auto& x = original.vertices;
    clear_phi(chunk.part);
    for (size_t i = chunk.begin; i < chunk.end; ++i) {
        const int32_t t = alive[i];
        build_triangle_graph(mesh, embedding, t, graph);
        if (!compute_faces(graph, embedding, sign, faces, &chunk.why) ||
            !triangulate_faces(graph, embedding, sign, faces, pieces, piece_triangle, &chunk.why)) {
            chunk.failed = i;
            return;
        }
        const Tri& c = mesh.triangle(t);
        phi_t.clear();
        for (const GraphNode& g : graph.nodes) {
            const Vec3 image = node_image(g, embedding);
            chunk.max_deviation =
                std::max(chunk.max_deviation, distance(image, barycentric_point(x[c[0]], x[c[1]], x[c[2]], g.bary)));
            const bool crossing = g.kind == NodeKind::EdgeCrossing;
            phi_t.add_node(g.bary, image, g.kind, crossing ? -1 : g.vertex,
                           crossing ? embedding.edges[g.edge] : std::array<int32_t, 2>{-1, -1},
                           crossing ? g.sigma : std::nan(""));
        }
        for (size_t k = 0; k < pieces.size(); ++k) phi_t.add_piece(pieces[k], piece_triangle[k]);
        append_phi_triangle(chunk.part, phi_t);
    }
}

// Reserves room in every array of phi for `scale` times its current size: after the
// first batch, its sizes per triangle estimate the whole (the arrays otherwise grow by
// doubling, each growth copying all of phi so far into freshly faulted pages).
void reserve_phi(Parametrization& p, double scale) {
    auto grow = [scale](auto& v) { v.reserve(static_cast<size_t>(double(v.size()) * scale) + 1); };
    grow(p.node_offsets);
    grow(p.node_barycentric);
    grow(p.node_image);
    grow(p.node_kind);
    grow(p.node_original_vertex);
    grow(p.node_original_edge);
    grow(p.node_edge_parameter);
    grow(p.piece_offsets);
    grow(p.pieces);
    grow(p.piece_original_triangle);
}

}  // namespace

double export_parametrization(const Surface& original, const CoarseMesh& mesh, const Embedding& embedding,
                              const std::vector<int8_t>& orientation_sign, PlanningPool& pool, Parametrization& out) {
    out = Parametrization();
    out.original = original;
    out.coarse = mesh.to_surface(out.coarse_vertex_origin);
    std::vector<int32_t> alive;
    for (int32_t t = 0; t < mesh.triangle_capacity(); ++t)
        if (mesh.alive(t)) alive.push_back(t);
    // At least 512 triangles per chunk, and at most 2^19 chunks (a round of the pool takes
    // fewer than 2^20 tasks); the output is concatenated in order either way.
    const size_t chunk_size = std::max<size_t>(512, (alive.size() + (size_t(1) << 19) - 1) >> 19);
    std::vector<ExportChunk> chunks((alive.size() + chunk_size - 1) / chunk_size);
    for (size_t c = 0; c < chunks.size(); ++c) {
        chunks[c].begin = c * chunk_size;
        chunks[c].end = std::min(alive.size(), (c + 1) * chunk_size);
    }
    // In batches of a few chunks per thread, each appended and freed before the next
    // batch is exported: only a batch's parts are alive beside `out`, not a second copy
    // of the whole of phi.
    const size_t batch = 4 * size_t(pool.threads());
    double max_deviation = 0.0;
    clear_phi(out);
    for (size_t first = 0; first < chunks.size(); first += batch) {
        const size_t count = std::min(batch, chunks.size() - first);
        pool.run_round(count, [&](int, size_t c) {
            export_chunk(original, mesh, embedding, orientation_sign, alive, chunks[first + c]);
        });
        for (size_t c = first; c < first + count; ++c) {
            ExportChunk& chunk = chunks[c];
            if (chunk.failed != SIZE_MAX)
                throw AlgorithmError("internal error: coarse triangle " + std::to_string(chunk.failed) +
                                     " has an invalid parametrization (" + chunk.why + ")");
            append_phi(out, chunk.part);
            max_deviation = std::max(max_deviation, chunk.max_deviation);
            chunk.part = Parametrization();  // its memory back before the next chunk's is appended
        }
        const size_t done = chunks[first + count - 1].end;
        if (first == 0 && done < alive.size()) reserve_phi(out, 1.0625 * double(alive.size()) / double(done));
    }
    return max_deviation;
}

}  // namespace bpm::detail
