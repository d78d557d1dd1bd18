#include "simplify/floater_repair.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Sparse>
#include <Eigen/SparseLU>

#include "simplify/polar_map.h"  // angle_between

namespace bpm::detail {

bool floater_repair(const Embedding& emb, StarGraph& graph, std::string& why) {
    // Floater's shape-preserving idea with mean value weights from the original surface:
    // every free node becomes a convex combination of its neighbours in the straightened
    // graph, with the polygon boundary fixed. On a convex polygon this embeds the graph
    // without flips (Floater 1997/2003).
    const auto& x = emb.original->vertices;
    std::vector<int32_t> index(graph.nodes.size(), -1);
    int32_t count = 0;
    for (size_t i = 0; i < graph.nodes.size(); ++i)
        if (graph.nodes[i].free) index[i] = count++;
    if (count == 0) return true;
    // Neighbours with 3D positions of their images.
    std::vector<std::vector<std::pair<int32_t, Vec3>>> neighbours(graph.nodes.size());
    auto image = [&](int32_t node, int32_t edge, double sigma) {
        const StarNode& s = graph.nodes[node];
        if (s.vertex >= 0) return x[s.vertex];
        const auto& e = emb.edges[edge];
        return (1.0 - sigma) * x[e[0]] + sigma * x[e[1]];
    };
    for (const StraightSegment& s : graph.segments) {
        neighbours[s.a].push_back({s.b, image(s.b, s.edge, s.sigma_b)});
        neighbours[s.b].push_back({s.a, image(s.a, s.edge, s.sigma_a)});
    }
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(count, 2);
    for (size_t i = 0; i < graph.nodes.size(); ++i) {
        if (index[i] < 0) continue;
        const Vec3 center = x[graph.nodes[i].vertex];
        auto& nb = neighbours[i];
        if (nb.size() < 2) {
            why = "free node with fewer than two neighbours";
            return false;
        }
        // Order the neighbours around the node by angle in a tangent frame of the
        // original surface (the average of the directions' plane).
        Vec3 normal{0, 0, 0};
        for (size_t a = 0; a < nb.size(); ++a) {
            const Vec3 d0 = nb[a].second - center, d1 = nb[(a + 1) % nb.size()].second - center;
            normal = normal + cross(d0, d1);
        }
        // A robust frame: first direction, and normal from PCA-free accumulation.
        Vec3 e0 = nb[0].second - center;
        const double l0 = norm(e0);
        if (!(l0 > 0)) {
            why = "zero-length neighbour direction";
            return false;
        }
        e0 = (1.0 / l0) * e0;
        Vec3 nrm = normal;
        if (!(norm(nrm) > 0)) nrm = cross(e0, Vec3{0.0, 0.0, 1.0});
        if (!(norm(nrm) > 0)) nrm = cross(e0, Vec3{0.0, 1.0, 0.0});
        nrm = (1.0 / norm(nrm)) * nrm;
        const Vec3 e1 = cross(nrm, e0);
        std::vector<std::pair<double, size_t>> order;
        for (size_t a = 0; a < nb.size(); ++a) {
            const Vec3 d = nb[a].second - center;
            order.push_back({std::atan2(dot(d, e1), dot(d, e0)), a});
        }
        std::sort(order.begin(), order.end());
        const size_t m = order.size();
        std::vector<double> w(m, 0.0);
        double total = 0.0;
        for (size_t a = 0; a < m; ++a) {
            const Vec3 dp = nb[order[(a + m - 1) % m].second].second - center;
            const Vec3 d = nb[order[a].second].second - center;
            const Vec3 dn = nb[order[(a + 1) % m].second].second - center;
            const double len = norm(d);
            const double t0 = std::tan(0.5 * angle_between(dp, d)), t1 = std::tan(0.5 * angle_between(d, dn));
            w[a] = (len > 0 && std::isfinite(t0 + t1)) ? (t0 + t1) / len : 0.0;
            if (!(w[a] > 0.0)) w[a] = len > 0 ? 1.0 / len : 1.0;  // fall back to positive weights
            total += w[a];
        }
        const int32_t row = index[i];
        triplets.push_back({row, row, 1.0});
        for (size_t a = 0; a < m; ++a) {
            const int32_t other = nb[order[a].second].first;
            const double weight = w[a] / total;
            if (index[other] >= 0)
                triplets.push_back({row, index[other], -weight});
            else {
                rhs(row, 0) += weight * graph.nodes[other].pos[0];
                rhs(row, 1) += weight * graph.nodes[other].pos[1];
            }
        }
    }
    Eigen::SparseMatrix<double> A(count, count);
    A.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::SparseLU<Eigen::SparseMatrix<double>> solver;
    solver.compute(A);
    if (solver.info() != Eigen::Success) {
        why = "shape-preserving map: singular system";
        return false;
    }
    Eigen::MatrixXd sol = solver.solve(rhs);
    if (solver.info() != Eigen::Success || !sol.allFinite()) {
        why = "shape-preserving map: solve failed";
        return false;
    }
    for (size_t i = 0; i < graph.nodes.size(); ++i)
        if (index[i] >= 0) graph.nodes[i].pos = {sol(index[i], 0), sol(index[i], 1)};
    return true;
}

}  // namespace bpm::detail
