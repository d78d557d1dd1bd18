#include "simplify/export_phi.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>

#include "bpm/errors.h"
#include "bpm/predicates.h"
#include "core/free_memory.h"
#include "core/huge_pages.h"
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

// Whether coarse triangle t is still one original triangle: nothing on its sides and
// nothing inside, so that its overlay (build_triangle_graph) is its three corners and no
// segment. Every triangle of a run that removed nothing is one (--ratio 1, the floor of
// issue 21), and many triangles far from the removals are.
bool is_bare_triangle(const CoarseMesh& mesh, const Embedding& embedding, int32_t t) {
    if (!embedding.inside.empty(t)) return false;
    const Tri& c = mesh.triangle(t);
    for (int k = 0; k < 3; ++k) {
        EdgeContentView content;
        if (embedding.content(c[k], c[(k + 1) % 3], content) &&
            (!content.vertices.empty() || !content.crossing_edges.empty()))
            return false;
    }
    return true;
}

// phi of a bare coarse triangle t (is_bare_triangle), appended to `into`: what the
// general path (build_triangle_graph, compute_faces, triangulate_faces) makes of it
// without its graph, maps and face walk. The three corner nodes in corner order, one
// piece (0, 1, 2) in the original triangle with these corners, found as faces_into finds
// it (the original edges from the smallest corner to the two others). Returns false, appending
// nothing, where that triangle is not found or its image has the wrong orientation: the
// general path then reports the error. The export of the 832k-triangle floor (--ratio 1
// --threads 1) spent ~1.9 us a triangle in the general path.
bool append_bare_triangle(const Surface& original, const CoarseMesh& mesh, const Embedding& embedding,
                          const std::vector<int8_t>& sign, int32_t t, double& max_deviation, Parametrization& into) {
    const Tri& c = mesh.triangle(t);
    std::array<int32_t, 3> vs = c;
    std::sort(vs.begin(), vs.end());
    if (vs[0] == vs[1] || vs[1] == vs[2]) return false;
    const int32_t e0 = embedding.find_edge(vs[0], vs[1]), e1 = embedding.find_edge(vs[0], vs[2]);
    if (e0 < 0 || e1 < 0) return false;
    const int32_t tri = embedding.triangle_of_edges(e0, e1);
    if (tri < 0) return false;
    // The image of corner k in `tri`: its barycentric unit vector there (image_barycentric);
    // the face's image must have the coarse surface's orientation relative to `tri`,
    // summed as faces_into sums it, and the piece too (triangulate_faces).
    Vec2 image[3];
    for (int k = 0; k < 3; ++k) {
        const GraphNode g = corner_node(k, c[k]);
        Vec3 beta;
        if (!image_barycentric(g, embedding, tri, beta)) return false;
        image[k] = {beta[1], beta[2]};
    }
    const double image_area2 = cross(image[0], image[1]) + cross(image[1], image[2]) + cross(image[2], image[0]);
    if (!(image_area2 * sign[tri] > 0.0) || !(orient2d(image[0], image[1], image[2]) * sign[tri] > 0)) return false;
    const auto& x = original.vertices;
    for (int k = 0; k < 3; ++k) {
        const GraphNode g = corner_node(k, c[k]);
        const Vec3& p = x[c[k]];
        max_deviation = std::max(max_deviation, distance(p, barycentric_point(x[c[0]], x[c[1]], x[c[2]], g.bary)));
        into.node_barycentric.push_back(g.bary);
        into.node_image.push_back(p);
        into.node_kind.push_back(NodeKind::CoarseCorner);
        into.node_original_vertex.push_back(c[k]);
        into.node_original_edge.push_back({-1, -1});
        into.node_edge_parameter.push_back(std::nan(""));
    }
    into.pieces.push_back({0, 1, 2});
    into.piece_original_triangle.push_back(tri);
    into.node_offsets.push_back(static_cast<int64_t>(into.node_kind.size()));
    into.piece_offsets.push_back(static_cast<int64_t>(into.pieces.size()));
    return true;
}

// Appends phi of the chunk's triangles to `into` (chunk.part, or the output itself when
// one thread exports everything).
void export_chunk(const Surface& original, const CoarseMesh& mesh, const Embedding& embedding,
                  const std::vector<int8_t>& sign, const std::vector<int32_t>& alive, ExportChunk& chunk,
                  Parametrization& into) {
    TriangleGraph graph;
    std::vector<OverlayFace> faces;
    std::vector<Tri> pieces;
    std::vector<int32_t> piece_triangle;
    PhiTriangleData phi_t;  // phi on one coarse triangle, reused for every triangle of the chunk
    const auto& x = original.vertices;
    for (size_t i = chunk.begin; i < chunk.end; ++i) {
        const int32_t t = alive[i];
        if (is_bare_triangle(mesh, embedding, t) &&
            append_bare_triangle(original, mesh, embedding, sign, t, chunk.max_deviation, into))
            continue;
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
        append_phi_triangle(into, phi_t);
    }
}

// The number of nodes of coarse triangle t in its overlay, counted as
// build_triangle_graph (overlay.cpp) makes them: the three corners, the original vertices
// on each side and the crossings of original edges with it, the original vertices inside.
size_t count_nodes(const CoarseMesh& mesh, const Embedding& embedding, int32_t t, std::vector<int32_t>& crossing,
                   size_t& inside) {
    const Tri& c = mesh.triangle(t);
    size_t n = 3;
    for (int k = 0; k < 3; ++k) {
        const int32_t a = c[k], b = c[(k + 1) % 3];
        EdgeContentView content;
        if (!embedding.content(a, b, content)) continue;
        n += content.vertices.size();
        crossing.assign(content.crossing_edges.begin(), content.crossing_edges.end());
        std::sort(crossing.begin(), crossing.end());
        crossing.erase(std::unique(crossing.begin(), crossing.end()), crossing.end());
        const int32_t lo = std::min(a, b), hi = std::max(a, b);
        for (int32_t e : crossing)
            for (const Crossing& x : embedding.crossings(e)) n += x.a == lo && x.b == hi;
    }
    inside = embedding.inside.count(t);
    return n + inside;
}

// Reserves every array of phi at its final size: the arrays otherwise grow by doubling
// (or from an estimate made after the first batch, which fell short), and a growth near
// the end of the export holds the old and the new array at once, at the peak of the run
// (208k-triangle input to 10k vertices: 54 MB of phi arrays at the peak for 38 MB of
// content). The nodes are counted exactly; the pieces by Euler's formula for a
// triangulated triangle (2 inner + boundary - 2 per coarse triangle, every node a corner
// of the pieces), which is exact for every overlay so far and only a reservation if not.
void reserve_phi(Parametrization& p, const CoarseMesh& mesh, const Embedding& embedding,
                 const std::vector<int32_t>& alive) {
    std::vector<int32_t> crossing;
    size_t nodes = 0, pieces = 0;
    for (int32_t t : alive) {
        size_t inside = 0;
        const size_t n = count_nodes(mesh, embedding, t, crossing, inside);
        nodes += n;
        pieces += n + inside - 2;
    }
    reserve_huge_pages(p.node_offsets, alive.size() + 1);
    reserve_huge_pages(p.node_barycentric, nodes);
    reserve_huge_pages(p.node_image, nodes);
    reserve_huge_pages(p.node_kind, nodes);
    reserve_huge_pages(p.node_original_vertex, nodes);
    reserve_huge_pages(p.node_original_edge, nodes);
    reserve_huge_pages(p.node_edge_parameter, nodes);
    reserve_huge_pages(p.piece_offsets, alive.size() + 1);
    reserve_huge_pages(p.pieces, pieces);
    reserve_huge_pages(p.piece_original_triangle, pieces);
}

AlgorithmError invalid_triangle(const ExportChunk& chunk) {
    return AlgorithmError("internal error: coarse triangle " + std::to_string(chunk.failed) +
                          " has an invalid parametrization (" + chunk.why + ")");
}

}  // namespace

double export_parametrization(const Surface& original, const CoarseMesh& mesh, const Embedding& embedding,
                              const std::vector<int8_t>& orientation_sign, PlanningPool& pool, Parametrization& out) {
    // The simplifier has freed its planning state (grid, queue, planners: hundreds of
    // thousands of small blocks) just before; glibc keeps those pages, while phi's large
    // arrays below come from fresh mappings. Handing the free pages back first lowers the
    // peak a little (fragmentation keeps most: 208k triangles to 10k vertices, one run,
    // 139 -> 136 MB).
    return_free_memory();
    // `original` may be out.original already (simplify(Surface&&)): kept, not copied.
    if (&original != &out.original) {
        out = Parametrization();
        out.original = original;
    } else {
        out.coarse = Surface();
        out.coarse_vertex_origin.clear();
    }
    out.coarse = mesh.to_surface(out.coarse_vertex_origin);
    std::vector<int32_t> alive;
    mesh.alive_triangles(alive);
    clear_phi(out);
    reserve_phi(out, mesh, embedding, alive);
    if (pool.threads() == 1) {
        // One thread: every triangle straight into `out`, in the same order, so the same
        // arrays without the parts, their copies and their fresh pages (208k triangles,
        // --ratio 1 --threads 1: export 0.47 -> 0.44 CPU s, median of 5; in the noise on 832k).
        ExportChunk all;
        all.end = alive.size();
        export_chunk(original, mesh, embedding, orientation_sign, alive, all, out);
        if (all.failed != SIZE_MAX) throw invalid_triangle(all);
        return all.max_deviation;
    }
    // At least 128 triangles per chunk, and at most 2^19 chunks (a round of the pool takes
    // fewer than 2^20 tasks); the output is concatenated in order either way. The parts of
    // a batch are alive beside `out` at the end of the export, the peak of a run: with 512
    // triangles per chunk a batch was 2048 coarse triangles' phi at one thread (armadillo
    // --ratio 0.1: 40 % of phi's 5200 triangles).
    const size_t chunk_size = std::max<size_t>(128, (alive.size() + (size_t(1) << 19) - 1) >> 19);
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
    for (size_t first = 0; first < chunks.size(); first += batch) {
        const size_t count = std::min(batch, chunks.size() - first);
        pool.run_round(count, [&](int, size_t c) {
            ExportChunk& chunk = chunks[first + c];
            clear_phi(chunk.part);
            export_chunk(original, mesh, embedding, orientation_sign, alive, chunk, chunk.part);
        });
        for (size_t c = first; c < first + count; ++c) {
            ExportChunk& chunk = chunks[c];
            if (chunk.failed != SIZE_MAX) throw invalid_triangle(chunk);
            append_phi(out, chunk.part);
            max_deviation = std::max(max_deviation, chunk.max_deviation);
            chunk.part = Parametrization();  // its memory back before the next chunk's is appended
        }
    }
    return max_deviation;
}

}  // namespace bpm::detail
