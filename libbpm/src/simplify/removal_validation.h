#pragma once
// Exact validation of a fan's transfer (Krause & Sander §2.2.4): the re-cut original
// edges (phi_transfer.h) are split into pieces, one per new triangle they cross, and
// every new triangle's overlay (the original surface on it) is checked with exact
// predicates (overlay.h check_faces). Also what the plan needs from a valid transfer:
// the edits of the original edges' paths, and the normal deviation.

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "bpm/geometry.h"
#include "simplify/embedding.h"
#include "simplify/fan_retriangulation.h"
#include "simplify/overlay.h"
#include "simplify/phi_transfer.h"
#include "simplify/star_fans.h"
#include "simplify/star_graph.h"

namespace bpm::detail {

// A piece of a re-cut original edge inside one new triangle.
struct Piece {
    int32_t triangle;      // new triangle (polygon-local index)
    int32_t item0, item1;  // star node id, or #nodes + new crossing index
    int32_t edge;
};

// The new path of a run of an original edge: its points first .. last (indices into the
// edge's point sequence, Embedding::path_points) get the new crossings in between.
struct PathEdit {
    int32_t edge, first, last;
    std::vector<Crossing> middle;  // new crossings between first and last, along the edge
};

struct TransferPieces {
    std::vector<std::array<int32_t, 2>> diagonal_triangles;  // the two new triangles on each diagonal
    std::vector<int32_t> side_triangle;                      // the new triangle on each polygon side
    std::vector<Piece> pieces;
    std::vector<PathEdit> path_edits;  // one per straightened segment
    // Emptied crossing lists kept for their capacity (every full plan makes a few per
    // fan, and a plan's rewritten paths one per edited edge): assign_pieces() takes the
    // path edits' `middle` lists from here, and the planner gives back the lists it has
    // read (vertex_removal.cpp), so that planning does not allocate them anew each time.
    std::vector<std::vector<Crossing>> spare;
    void recycle(std::vector<Crossing>& list) {
        if (list.capacity() == 0) return;
        list.clear();
        spare.push_back(std::move(list));
    }
    std::vector<Crossing> take() {
        if (spare.empty()) return {};
        std::vector<Crossing> list = std::move(spare.back());
        spare.pop_back();
        return list;
    }
};

// Splits every cut segment into pieces, each in the one new triangle both its ends are
// in, and writes the path edits. Fails with `why` when the ends of a piece share no
// new triangle, or two (the piece runs along a diagonal: then `along_diagonal` is that
// diagonal's corner pair, so that the caller can retriangulate without it; otherwise it
// is left as it was).
bool assign_pieces(const Fan& fan, const FanTriangulation& tri, const StarGraph& graph, const RecutEdges& cuts,
                   TransferPieces& pieces, std::array<int32_t, 2>& along_diagonal, std::string& why);

// A fan's transfer as check_new_triangles() reads it.
struct FanTransfer {
    const Embedding& emb;
    const std::vector<int8_t>& sign;      // orientation sign of each original triangle
    const std::vector<Vec3>& normals;     // oriented unit normals of the original triangles, or empty
    const Fan& fan;
    const FanTriangulation& tri;
    const std::vector<Vec3>& new_normals;  // unit normal of each new triangle (if `normals`)
    const StarGraph& graph;
    const RecutEdges& cuts;
    const TransferPieces& pieces;
};

// Buffers of one thread's check_new_triangles() (the checks of one plan may be split
// over threads, each with its own).
struct TriangleCheck {
    TriangleGraph graph;
    std::vector<int32_t> local, touched;
    std::vector<OverlayFace> faces;
    std::string reason;
};

// Builds the overlay of new triangles [begin, end) (its corners, the nodes on its
// sides and inside it, its pieces) and checks it exactly (check_faces). Lowers
// `min_cosine` to the smallest cosine between a checked triangle's normal and the
// normal of an original triangle with a face in it (if `normals` is not empty). Fails
// with `why` at the first triangle whose overlay is invalid. Reads `transfer` only, so
// disjoint ranges may be checked on several threads at once.
bool check_new_triangles(const FanTransfer& transfer, int32_t begin, int32_t end, TriangleCheck& check,
                         double& min_cosine, std::string& why);

}  // namespace bpm::detail
