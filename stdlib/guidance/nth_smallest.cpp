// Percentiles of a map without sorting it: a non-negative float's bits order as the float
// does, so the k-th smallest is found from two 16-bit histograms of the bits (high half, then
// low half within the one high bucket that holds it) in two passes and no copy. The result is
// the very value std::nth_element would pick.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "stdlib/guidance/raster.h"

namespace crex::guidance {

float nth_smallest(const std::vector<float>& values, size_t k) {
    constexpr uint32_t kInfinity = 0x7f800000u;  // larger bits: NaN, or the sign set (negatives, -0)
    std::vector<uint32_t> count(1u << 16, 0);
    for (float x : values) {
        uint32_t u = std::bit_cast<uint32_t>(x);
        if (u > kInfinity) {  // not a map value: take the general route
            std::vector<float> copy = values;
            std::nth_element(copy.begin(), copy.begin() + static_cast<std::ptrdiff_t>(k), copy.end());
            return copy[k];
        }
        ++count[u >> 16];
    }
    // The high half: the bucket where the running count passes k.
    uint32_t high = 0;
    while (k >= count[high]) k -= count[high++];
    std::fill(count.begin(), count.end(), 0u);
    for (float x : values) {
        uint32_t u = std::bit_cast<uint32_t>(x);
        if (u >> 16 == high) ++count[u & 0xffffu];
    }
    uint32_t low = 0;
    while (k >= count[low]) k -= count[low++];
    return std::bit_cast<float>(high << 16 | low);
}

}  // namespace crex::guidance
