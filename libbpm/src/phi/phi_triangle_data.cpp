#include "phi/phi_triangle_data.h"

#include "bpm/phi_triangle.h"

namespace bpm::detail {

namespace {

template <class T>
void append(std::vector<T>& to, const std::vector<T>& from) {
    to.insert(to.end(), from.begin(), from.end());
}

}  // namespace

PhiTriangleData load_phi_triangle(const Parametrization& p, int32_t t) {
    const PhiTriangle phi(p, t);
    PhiTriangleData x;
    for (int64_t i = 0; i < phi.num_nodes(); ++i)
        x.add_node(phi.barycentric(i), phi.image(i), phi.kind(i), phi.original_vertex(i), phi.original_edge(i),
                   phi.edge_parameter(i));
    for (int64_t j = 0; j < phi.num_pieces(); ++j) x.add_piece(phi.piece(j), phi.original_triangle(j));
    return x;
}

void clear_phi(Parametrization& p) {
    p.node_offsets.assign(1, 0);
    p.piece_offsets.assign(1, 0);
    p.node_barycentric.clear();
    p.node_image.clear();
    p.node_kind.clear();
    p.node_original_vertex.clear();
    p.node_original_edge.clear();
    p.node_edge_parameter.clear();
    p.pieces.clear();
    p.piece_original_triangle.clear();
}

void append_phi_triangle(Parametrization& p, const PhiTriangleData& t) {
    append(p.node_barycentric, t.barycentric);
    append(p.node_image, t.image);
    append(p.node_kind, t.kind);
    append(p.node_original_vertex, t.original_vertex);
    append(p.node_original_edge, t.original_edge);
    append(p.node_edge_parameter, t.edge_parameter);
    append(p.pieces, t.pieces);
    append(p.piece_original_triangle, t.piece_original_triangle);
    p.node_offsets.push_back(static_cast<int64_t>(p.node_kind.size()));
    p.piece_offsets.push_back(static_cast<int64_t>(p.pieces.size()));
}

void append_phi(Parametrization& p, const Parametrization& part) {
    const int64_t node_base = p.node_offsets.back(), piece_base = p.piece_offsets.back();
    append(p.node_barycentric, part.node_barycentric);
    append(p.node_image, part.node_image);
    append(p.node_kind, part.node_kind);
    append(p.node_original_vertex, part.node_original_vertex);
    append(p.node_original_edge, part.node_original_edge);
    append(p.node_edge_parameter, part.node_edge_parameter);
    append(p.pieces, part.pieces);
    append(p.piece_original_triangle, part.piece_original_triangle);
    for (size_t k = 1; k < part.node_offsets.size(); ++k) {
        p.node_offsets.push_back(node_base + part.node_offsets[k]);
        p.piece_offsets.push_back(piece_base + part.piece_offsets[k]);
    }
}

}  // namespace bpm::detail
