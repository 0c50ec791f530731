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
/// (farm-bench, 7 pairs). What remains is the cache miss on each level's cell; visiting the
/// queries in Morton order to share them cost more in sorting than it saved.
#pragma once

#include <cstdint>
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

/// Cells (63-bit keys) to lists of entries, kept in insertion order.
class CellTable {
public:
    bool empty() const { return cells_.empty(); }

    const std::vector<GridEntry>* find(uint64_t key) const {
        if (slots_.empty()) return nullptr;
        const size_t mask = slots_.size() - 1;
        for (size_t i = mix64(key) & mask;; i = (i + 1) & mask) {
            const Slot& s = slots_[i];
            if (s.key == key) return &cells_[s.cell];
            if (s.key == kEmpty) return nullptr;
        }
    }

    std::vector<GridEntry>& at(uint64_t key) {
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
    std::vector<std::vector<GridEntry>> cells_;
};

}  // namespace crex
