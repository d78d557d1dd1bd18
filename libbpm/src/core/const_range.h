#pragma once
// A read-only range of consecutive elements that lives elsewhere (a path's crossings, a
// coarse edge's vertices): what a container hands out when its elements are not stored
// as one std::vector per item. Internal to libbpm.

#include <cstddef>
#include <vector>

namespace bpm::detail {

template <class T>
class ConstRange {
public:
    ConstRange() = default;
    ConstRange(const T* b, const T* e) : b_(b), e_(e) {}
    explicit ConstRange(const std::vector<T>& v) : b_(v.data()), e_(v.data() + v.size()) {}
    const T* begin() const { return b_; }
    const T* end() const { return e_; }
    size_t size() const { return size_t(e_ - b_); }
    bool empty() const { return b_ == e_; }
    const T& operator[](size_t i) const { return b_[i]; }

private:
    const T* b_ = nullptr;
    const T* e_ = nullptr;
};

}  // namespace bpm::detail
