// Creases with chains (core/crease_chains.h).

#include "core/crease_chains.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "bpm/errors.h"
#include "core/crease.h"

namespace bpm::detail {

namespace {

int32_t find_root(std::vector<int32_t>& parent, int32_t x) {
    while (parent[size_t(x)] != x) x = parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
    return x;
}

}  // namespace

std::vector<uint8_t> find_creases(const std::vector<Vec3>& p, const std::vector<SheetEdge>& edges,
                                  const CreaseRule& rule) {
    const CreaseTest sharp(rule.feature_angle_degrees);
    std::vector<uint8_t> crease(edges.size(), 0);
    if (!(rule.chain_angle_degrees < rule.feature_angle_degrees) || !(rule.chain_angle_degrees < 180.0)) {
        for (size_t e = 0; e < edges.size(); ++e)
            crease[e] = sharp.is_crease(p, edges[e].t0, edges[e].t1, edges[e].u, edges[e].w) ? 1 : 0;
        return crease;
    }

    // Sharp edges, and the shallow ones: not sharp, normals more than the chain angle
    // apart. angle = the angle between the normals (180 - the ridge angle). One cosine of
    // the normals per edge for the three questions (they computed it one after the other:
    // ~3 % of the 832k-triangle floor was these normals).
    const CreaseTest shallow_test(rule.chain_angle_degrees);
    std::vector<int32_t> shallow;  // edge indices
    std::vector<double> angle;     // per shallow edge
    for (size_t e = 0; e < edges.size(); ++e) {
        const SheetEdge& s = edges[e];
        double cosine;
        if (!oriented_normal_cosine(p, s.t0, s.t1, s.u, s.w, cosine)) continue;  // neither
        if (sharp.is_crease(cosine)) {
            crease[e] = 1;
            continue;
        }
        if (!shallow_test.is_crease(cosine)) continue;
        shallow.push_back(int32_t(e));
        angle.push_back(180.0 - ridge_angle_degrees(cosine));
    }
    if (shallow.empty()) return crease;

    // Per vertex: the shallow edges at it (up to two are remembered) and whether a sharp one is.
    int32_t nv = 0;
    for (const SheetEdge& s : edges) nv = std::max({nv, s.u + 1, s.w + 1});
    std::vector<int32_t> count(size_t(nv), 0), first(size_t(nv), -1), second(size_t(nv), -1);
    std::vector<uint8_t> at_sharp(size_t(nv), 0);
    for (size_t e = 0; e < edges.size(); ++e)
        if (crease[e]) at_sharp[size_t(edges[e].u)] = at_sharp[size_t(edges[e].w)] = 1;
    for (int32_t i = 0; i < int32_t(shallow.size()); ++i)
        for (const int32_t v : {edges[size_t(shallow[size_t(i)])].u, edges[size_t(shallow[size_t(i)])].w}) {
            const int32_t k = count[size_t(v)]++;
            if (k == 0) first[size_t(v)] = i;
            else if (k == 1) second[size_t(v)] = i;
        }

    // Join the two shallow edges at each vertex where the line goes on smoothly.
    const double cos_turn = std::cos(kChainTurnDegrees * M_PI / 180.0);
    std::vector<int32_t> parent(shallow.size());
    std::iota(parent.begin(), parent.end(), 0);
    for (int32_t v = 0; v < nv; ++v) {
        if (count[size_t(v)] != 2 || at_sharp[size_t(v)]) continue;
        const int32_t i = first[size_t(v)], j = second[size_t(v)];
        const SheetEdge &a = edges[size_t(shallow[size_t(i)])], &b = edges[size_t(shallow[size_t(j)])];
        // Directions through v: from a's other end to v, and from v to b's other end.
        const Vec3 in = p[size_t(v)] - p[size_t(a.u == v ? a.w : a.u)];
        const Vec3 out = p[size_t(b.u == v ? b.w : b.u)] - p[size_t(v)];
        const double lengths = norm(in) * norm(out);
        if (!(lengths > 0) || dot(in, out) < cos_turn * lengths) continue;
        const double lo = std::min(angle[size_t(i)], angle[size_t(j)]);
        const double hi = std::max(angle[size_t(i)], angle[size_t(j)]);
        if (hi > kChainAngleRatio * lo) continue;
        parent[size_t(find_root(parent, i))] = find_root(parent, j);
    }

    // Chains of at least kChainMinEdges edges and min_chain_length are creases.
    std::vector<double> length(shallow.size(), 0.0);
    std::vector<int32_t> chain_edges(shallow.size(), 0);
    for (int32_t i = 0; i < int32_t(shallow.size()); ++i) {
        const SheetEdge& s = edges[size_t(shallow[size_t(i)])];
        const size_t root = size_t(find_root(parent, i));
        length[root] += distance(p[size_t(s.u)], p[size_t(s.w)]);
        ++chain_edges[root];
    }
    for (int32_t i = 0; i < int32_t(shallow.size()); ++i) {
        const size_t root = size_t(find_root(parent, i));
        if (chain_edges[root] >= kChainMinEdges && length[root] >= rule.min_chain_length)
            crease[size_t(shallow[size_t(i)])] = 1;
    }
    return crease;
}

void check_crease_rule_numbers(double feature_angle_degrees, double chain_angle_degrees, double chain_length,
                               const std::string& who) {
    if (!(feature_angle_degrees >= 0 && feature_angle_degrees <= 180))
        throw OptionError(who + "feature_angle_degrees must be between 0 and 180 degrees");
    if (!(chain_angle_degrees >= 0 && chain_angle_degrees <= 180))
        throw OptionError(who + "crease_chain_angle_degrees must be between 0 and 180 degrees");
    if (!(chain_length >= 0 && chain_length <= 1))
        throw OptionError(who + "crease_chain_length must be between 0 and 1 (of the diagonal)");
}

}  // namespace bpm::detail
