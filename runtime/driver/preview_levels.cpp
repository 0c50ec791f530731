#include "runtime/driver/preview_levels.h"

#include <algorithm>

namespace crex {
namespace {

// The columns (or rows) of a grid of squares of `stride` pixels: each square's first and last.
uint64_t grid_lines(int size, uint32_t stride) {
    if (size <= 0) return 0;
    const uint64_t n = static_cast<uint64_t>(size), k = std::max<uint32_t>(1, stride);
    if (k == 1) return n;
    // Squares start at 0, k, 2k, ...; each adds its start, and its end min(start + k, n - 1)
    // is the next square's start except for the last.
    return (n - 1) / k + 1 + ((n - 1) % k != 0 ? 1 : 0);
}

}  // namespace

uint64_t preview_samples_at(int width, int height, uint32_t spp, uint32_t stride) {
    return grid_lines(width, stride) * grid_lines(height, stride) * spp;
}

}  // namespace crex
