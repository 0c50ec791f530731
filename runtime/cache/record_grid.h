/// \file record_grid.h
/// The irradiance cache's spatial index: a hierarchy of uniform grids (level L has cells of
/// top / 2^L), each a hash table from cell to the records that reach into it, with what a
/// lookup tests first (position and R) copied beside each record's index.
///
/// Why not std::unordered_map: its prime-sized buckets cost a 64-bit division per probe and
/// a node per cell, and the first test read a 232-byte record per candidate (perf put a
/// quarter of `crex run --ic --spp 16` on the Cornell box in lookups). Here a cell is found
/// by linear probing in a power-of-two table, and candidates that fail the distance test are
/// rejected from 20 contiguous bytes: the same records in the same order, 4 % less wall time
/// (farm-bench, 7 pairs). Visiting the queries in Morton order to share cells cost more in
/// sorting than it saved.
///
/// A cell holds its entries in blocks of 8, each coordinate contiguous, so the first test runs
/// on several entries at once (SIMD compares): records are filed by their reach at the coarsest
/// accuracy the render uses, so a lookup at a finer one scans many that fail it (on the
/// corridor walk of sel_aa, 116 entries a lookup, of which 8 passed). The normals are not
/// here but beside the records (IrradianceCache::normals_): most cells hold one or two
/// entries in a block of eight lanes, and three floats more a lane cost 43 MB at the peak.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "runtime/base/sampling.h"
#include "runtime/base/vec3.h"

namespace crex {

/// What a lookup needs of a record before it reads the record itself.
struct GridEntry {
    float x, y, z;    ///< position (local coordinates), rounded
    float radius;     ///< harmonic distance R
    uint32_t index;   ///< into the cache's records
};

/// A cell's entries, in insertion order, in blocks of kLanes.
class GridCell {
public:
    static constexpr size_t kLanes = 8;

    /// Returns whether it took a new block (memory the cache counts: IrradianceCache::bytes).
    bool push_back(const GridEntry& e) {
        const bool fresh = size_ % kLanes == 0;
        if (fresh) blocks_.emplace_back();
        Block& b = blocks_.back();
        const size_t k = size_ % kLanes;
        b.x[k] = e.x, b.y[k] = e.y, b.z[k] = e.z, b.radius[k] = e.radius, b.index[k] = e.index;
        ++size_;
        return fresh;
    }
    static constexpr size_t block_bytes() { return sizeof(Block); }
    size_t size() const { return size_; }
    /// Asks for the first block's cache lines ahead of for_each_near.
    void prefetch() const {
        if (blocks_.empty()) return;
        const char* b = reinterpret_cast<const char*>(blocks_.data());
        for (size_t line = 0; line < sizeof(Block); line += 64) __builtin_prefetch(b + line);
    }

    /// Calls near(index) for each entry, in insertion order, whose position is within
    /// `scale * radius + slack` of (px, py, pz) (in float; NaN anywhere fails the test).
    template <class Near>
    void for_each_near(float px, float py, float pz, float scale, float slack, Near&& near) const {
        for (const Block& b : blocks_) {
            // Arithmetic and compares without a branch, over the lanes: SIMD instructions.
            int32_t in[kLanes];
            for (size_t k = 0; k < kLanes; ++k) {
                const float dx = px - b.x[k], dy = py - b.y[k], dz = pz - b.z[k], reach = scale * b.radius[k] + slack;
                in[k] = dx * dx + dy * dy + dz * dz < reach * reach ? -1 : 0;
            }
            int32_t any = 0;
            for (size_t k = 0; k < kLanes; ++k) any |= in[k];
            if (!any) continue;
            for (size_t k = 0; k < kLanes; ++k)
                if (in[k]) near(b.index[k]);
        }
    }

private:
    struct Block {
        // Lanes past the cell's size sit at infinity: no lookup finds them near.
        float x[kLanes] = {kFar, kFar, kFar, kFar, kFar, kFar, kFar, kFar};
        float y[kLanes] = {}, z[kLanes] = {}, radius[kLanes] = {};
        uint32_t index[kLanes] = {};
    };
    static constexpr float kFar = std::numeric_limits<float>::infinity();
    static_assert(kLanes == 8, "Block's initialiser lists eight lanes");
    std::vector<Block> blocks_;
    size_t size_ = 0;
};

/// Cells (63-bit keys) to their entries.
class CellTable {
public:
    bool empty() const { return cells_.empty(); }

    /// Asks for the slot `key` is looked for first, ahead of find().
    void prefetch(uint64_t key) const {
        if (!slots_.empty()) __builtin_prefetch(&slots_[mix64(key) & (slots_.size() - 1)]);
    }

    const GridCell* find(uint64_t key) const {
        if (slots_.empty()) return nullptr;
        const size_t mask = slots_.size() - 1;
        for (size_t i = mix64(key) & mask;; i = (i + 1) & mask) {
            const Slot& s = slots_[i];
            if (s.key == key) return &cells_[s.cell];
            if (s.key == kEmpty) return nullptr;
        }
    }

    GridCell& at(uint64_t key) {
        if (2 * (cells_.size() + 1) > slots_.size()) grow();  // at most half full: short probes
        const size_t mask = slots_.size() - 1;
        for (size_t i = mix64(key) & mask;; i = (i + 1) & mask) {
            Slot& s = slots_[i];
            if (s.key == key) return cells_[s.cell];
            if (s.key == kEmpty) {
                s.key = key;
                s.cell = static_cast<uint32_t>(cells_.size());
                return cells_.emplace_back();
            }
        }
    }

    /// Files an entry in cell `key`.
    void add(uint64_t key, const GridEntry& e) { blocks_ += at(key).push_back(e) ? 1 : 0; }
    /// What the table holds, in bytes (its slots and cells at their sizes, and their blocks).
    size_t bytes() const { return slots_.size() * sizeof(Slot) + cells_.size() * sizeof(GridCell) + blocks_ * GridCell::block_bytes(); }

private:
    static constexpr uint64_t kEmpty = ~uint64_t{0};  // cell keys use 63 bits
    struct Slot {
        uint64_t key = kEmpty;
        uint32_t cell = 0;
    };

    void grow() {
        std::vector<Slot> old = std::move(slots_);
        slots_.assign(old.empty() ? 64 : 2 * old.size(), Slot{});
        const size_t mask = slots_.size() - 1;
        for (const Slot& s : old) {
            if (s.key == kEmpty) continue;
            size_t i = mix64(s.key) & mask;
            while (slots_[i].key != kEmpty) i = (i + 1) & mask;
            slots_[i] = s;
        }
    }

    std::vector<Slot> slots_;
    std::vector<GridCell> cells_;
    size_t blocks_ = 0;  ///< the cells' blocks, taken by add()
};

}  // namespace crex
