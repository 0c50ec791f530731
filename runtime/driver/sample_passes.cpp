#include "runtime/driver/sample_passes.h"

#include <algorithm>
#include <limits>

namespace crex {

std::vector<SamplePass> plan_sample_passes(int width, int height, uint32_t first, uint32_t end,
                                           const std::vector<uint32_t>& end_of, const PassLimits& limits) {
    const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
    const bool uniform = end_of.empty();
    uint32_t last = end;
    if (!uniform) last = end_of.empty() ? first : *std::max_element(end_of.begin(), end_of.end());
    std::vector<SamplePass> passes;
    if (last <= first || pixels == 0) return passes;

    // count[k - first]: pixels that ask for sample index k (non-increasing in k).
    std::vector<uint64_t> count(last - first, uniform ? pixels : 0);
    if (!uniform) {
        std::vector<uint64_t> ending(last - first + 1, 0);
        for (uint32_t e : end_of)
            if (e > first) ++ending[e - first];
        uint64_t alive = 0;
        for (size_t k = count.size(); k-- > 0;) count[k] = alive += ending[k + 1];
    }
    const uint64_t cap = limits.bytes && limits.bytes_per_sample
                             ? std::max<uint64_t>(1, limits.bytes / limits.bytes_per_sample)
                             : std::numeric_limits<uint64_t>::max();
    const uint32_t max_indices = limits.max_samples ? limits.max_samples : std::numeric_limits<uint32_t>::max();

    auto band_samples = [&](uint32_t k, int r0, int r1) -> uint64_t {
        if (uniform) return static_cast<uint64_t>(r1 - r0) * static_cast<uint64_t>(width);
        uint64_t n = 0;
        for (size_t p = static_cast<size_t>(r0) * width; p < static_cast<size_t>(r1) * width; ++p) n += end_of[p] > k;
        return n;
    };

    uint32_t k = first;
    while (k < last && count[k - first] > 0) {
        uint64_t total = 0;
        uint32_t k1 = k;
        while (k1 < last && count[k1 - first] > 0 && k1 - k < max_indices && total + count[k1 - first] <= cap)
            total += count[k1 - first], ++k1;
        if (k1 > k) {
            passes.push_back({k, k1, 0, height, total});
            k = k1;
            continue;
        }
        // Not even one sample of every pixel fits: this sample index goes in bands of rows.
        const int rows = static_cast<int>(std::clamp<uint64_t>(cap / static_cast<uint64_t>(width), 1, static_cast<uint64_t>(height)));
        for (int r0 = 0; r0 < height; r0 += rows) {
            int r1 = std::min(height, r0 + rows);
            if (uint64_t n = band_samples(k, r0, r1)) passes.push_back({k, k + 1, r0, r1, n});
        }
        ++k;
    }
    return passes;
}

}  // namespace crex
