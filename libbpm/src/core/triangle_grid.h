#pragma once
// A uniform grid over triangle bounding boxes, for finding the triangles near a new
// one while the surface changes. Internal to libbpm.

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "bpm/geometry.h"
#include "core/probed_keys.h"

namespace bpm::detail {

class TriangleGrid {
public:
    // A triangle with its bounding box, as stored in the cells: queries test the boxes
    // while they scan a cell, without looking the triangles up. The box is quantized on a
    // lattice of 65536 steps per axis over the box of all positions (Frame), rounded
    // outwards by a step: it only filters candidates for exact tests, and a triangle sits
    // in several cells, so the entries are a large part of the simplifier's memory
    // (16 bytes here; 28 with a float box).
    struct Entry {
        int32_t id;
        std::array<uint16_t, 3> lo, hi;
    };
    // The lattice of the boxes: lattice index floor((x - origin) * scale) per axis.
    struct Frame {
        Vec3 origin{};
        Vec3 scale{};  // lattice steps per unit length; 0 on an axis of zero or infinite extent
        // The frame of the box [lo, hi], which must contain every point given to the grid.
        static Frame of_box(const Vec3& lo, const Vec3& hi);
    };
    // A box on the lattice, rounded outwards: it contains the lattice cell of every point
    // of the box it was made from (at most one lattice step of rounding either way).
    struct LatticeBox {
        std::array<uint16_t, 3> lo, hi;
    };
    LatticeBox lattice_box(const Vec3& lo, const Vec3& hi) const;
    // Whether the boxes the two lattice boxes were made from are disjoint (proved by the
    // lattice: false may still mean disjoint).
    static bool apart(const LatticeBox& a, const std::array<uint16_t, 3>& lo, const std::array<uint16_t, 3>& hi) {
        for (int k = 0; k < 3; ++k)
            if (hi[k] < a.lo[k] || lo[k] > a.hi[k]) return true;
        return false;
    }

    // `cell` is the edge length of a grid cell; `frame` the lattice of the stored boxes.
    TriangleGrid(double cell, const Frame& frame) : cell_(cell), frame_(frame) {}
    explicit TriangleGrid(double cell) : cell_(cell) {}
    double cell() const { return cell_; }
    void insert(int32_t id, const Vec3& a, const Vec3& b, const Vec3& c);
    void remove(int32_t id, const Vec3& a, const Vec3& b, const Vec3& c);
    // insert() of triangle ids[i] with corners x[corners[i][0..2]] for every i, into an
    // empty grid: the cells are counted first and each list allocated once at its size
    // (inserting one by one grows every list several times and leaves it up to half empty).
    void insert_all(const std::vector<int32_t>& ids, const std::vector<Tri>& corners, const std::vector<Vec3>& x);
    // The triangles whose bounding box meets the closed box [lo, hi], sorted by id,
    // each once.
    void query_boxes(const Vec3& lo, const Vec3& hi, std::vector<Entry>& out) const;
    // The triangles whose bounding box may lie inside the closed box [lo, hi] (the
    // lattice boxes decide: a box inside [lo, hi] has its lattice box inside
    // lattice_box(lo, hi), rounding being monotone; the converse need not hold), in no
    // order and with repeats (a triangle in several cells): a filter for exact tests that
    // need no order (simplify/island_guard.h). Cheaper than query_boxes: no sort.
    void query_within(const Vec3& lo, const Vec3& hi, std::vector<Entry>& out) const;
    void clear() {
        cells_.clear();
        big_.clear();
    }

    // For a walk over all stored pairs (simplify/input_intersections.h): the cell of a
    // point (per axis floor(x / cell), as insert() places a box's corners), the key of a
    // cell, f(key, entries) for every cell, and the entries of the oversized triangles,
    // which are in no cell. A stored box lies in exactly the cells from the cell of its
    // low corner to that of its high corner (keys wrap: one list may hold several cells).
    std::array<int64_t, 3> cell_of(const Vec3& p) const {
        std::array<int64_t, 3> c;
        for (int k = 0; k < 3; ++k) c[size_t(k)] = static_cast<int64_t>(std::floor(p[k] / cell_));
        return c;
    }
    static uint64_t cell_key(int64_t x, int64_t y, int64_t z) {
        // 21 bits per axis, wrapped: collisions only cost extra candidates.
        const uint64_t m = (1u << 21) - 1;
        return (uint64_t(x) & m) | ((uint64_t(y) & m) << 21) | ((uint64_t(z) & m) << 42);
    }
    template <class F>
    void for_each_cell(F&& f) const {
        cells_.for_each_keyed(f);
    }
    const std::vector<Entry>& oversized_entries() const { return big_; }

private:
    // Cell key -> the entries of that cell, open addressing with linear probing over a
    // dense array of keys: a query looks up every cell its box meets, and the buckets and
    // nodes of std::unordered_map were a third of the query time. A cell whose list
    // empties keeps its slot (and the list its capacity: new triangles of the same star
    // come into the same cells) until the grid is rebuilt.
    class CellTable {
    public:
        const std::vector<Entry>* find(uint64_t key) const {
            const size_t slot = keys_.find(key);
            return slot == ProbedKeys::kNone ? nullptr : &lists_[slot];
        }
        std::vector<Entry>* find(uint64_t key) {
            return const_cast<std::vector<Entry>*>(static_cast<const CellTable&>(*this).find(key));
        }
        std::vector<Entry>& operator[](uint64_t key);  // inserts an empty list if absent
        void reserve(size_t cells);                      // room for that many cells without rehashing
        // For a bulk insertion (insert_all): count(key) once per entry to come, then
        // reserve_counted() gives each list room for its count (and forgets the counts).
        // The counts sit beside the keys: a std::unordered_map of them, a node per cell,
        // was most of insert_all's first pass.
        void count(uint64_t key);
        void reserve_counted();
        template <class F>
        void for_each(F&& f) const {  // f(list) for every cell
            for (size_t i = 0; i < keys_.slots(); ++i)
                if (keys_.occupied(i)) f(lists_[i]);
        }
        template <class F>
        void for_each_keyed(F&& f) const {  // f(key, list) for every cell
            for (size_t i = 0; i < keys_.slots(); ++i)
                if (keys_.occupied(i)) f(keys_.key(i), lists_[i]);
        }
        void clear() {
            keys_.clear();
            lists_.clear();
            counts_.clear();
        }

    private:
        ProbedKeys keys_{true};  // cell keys use 63 bits (never ProbedKeys::kEmpty)
        std::vector<std::vector<Entry>> lists_;  // per slot of keys_
        std::vector<uint32_t> counts_;  // per slot, between count() and reserve_counted(); else empty
        void rehash(size_t capacity);
    };

    double cell_;
    Frame frame_;
    CellTable cells_;
    std::vector<Entry> big_;  // triangles spanning too many cells
    bool oversized(const Vec3& lo, const Vec3& hi) const;
    template <class F>
    void for_cells(const Vec3& lo, const Vec3& hi, F&& f) const;
    // Calls f(entry) for every stored entry of a cell the box overlaps (repeats possible).
    template <class F>
    void for_entries(const Vec3& lo, const Vec3& hi, F&& f) const;
};

}  // namespace bpm::detail
