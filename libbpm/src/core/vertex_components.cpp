#include "core/vertex_components.h"

#include <algorithm>
#include <numeric>

namespace bpm::detail {

VertexComponents::VertexComponents(size_t vertex_count) : parent_(vertex_count), used_(vertex_count, 0) {
    std::iota(parent_.begin(), parent_.end(), 0);
}

int32_t VertexComponents::root(int32_t x) {
    while (parent_[size_t(x)] != x) x = parent_[size_t(x)] = parent_[size_t(parent_[size_t(x)])];
    return x;
}

void VertexComponents::add(const Tri& t) {
    used_[size_t(t[0])] = 1;
    for (int k = 1; k < 3; ++k) {
        used_[size_t(t[size_t(k)])] = 1;
        const int32_t a = root(t[0]), b = root(t[size_t(k)]);
        if (a != b) parent_[size_t(std::max(a, b))] = std::min(a, b);
    }
}

int32_t VertexComponents::number(std::vector<int32_t>& component) {
    const size_t n = parent_.size();
    component.assign(n, -1);
    std::vector<int32_t> id(n, -1);  // per root
    int32_t count = 0;
    for (size_t x = 0; x < n; ++x) {
        if (!used_[x]) continue;
        const int32_t r = root(int32_t(x));
        if (id[size_t(r)] < 0) id[size_t(r)] = count++;
        component[x] = id[size_t(r)];
    }
    return count;
}

}  // namespace bpm::detail
