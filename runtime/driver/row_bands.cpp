#include "runtime/driver/row_bands.h"

#include <algorithm>
#include <numeric>

namespace crex {

std::vector<int> equal_row_bands(int height, int bands) {
    // b height / bands to the nearest row, halves down: 2 bands of 25 rows are 12 and 13 rows.
    std::vector<int> bounds(static_cast<size_t>(bands) + 1);
    for (int b = 0; b <= bands; ++b)
        bounds[static_cast<size_t>(b)] = static_cast<int>((2LL * height * b + bands - 1) / (2LL * bands));
    return bounds;
}

std::vector<uint64_t> samples_per_row(const SampleRanges& ranges, int width, int height) {
    std::vector<uint64_t> samples(static_cast<size_t>(height), 0);
    for (size_t row = 0; row < samples.size(); ++row)
        for (size_t p = row * static_cast<size_t>(width); p < (row + 1) * static_cast<size_t>(width); ++p)
            if (ranges.stop(p) > ranges.start(p)) samples[row] += ranges.stop(p) - ranges.start(p);
    return samples;
}

std::vector<int> balanced_row_bands(const std::vector<uint64_t>& row_cost, int bands) {
    const int height = static_cast<int>(row_cost.size());
    std::vector<int> bounds = equal_row_bands(height, bands);
    // before[r]: the cost of rows [0, r).
    std::vector<uint64_t> before(row_cost.size() + 1, 0);
    std::partial_sum(row_cost.begin(), row_cost.end(), before.begin() + 1);
    const uint64_t total = before.back();
    if (total == 0 || height < bands) return bounds;
    const uint64_t n = static_cast<uint64_t>(bands);
    for (int b = 1; b < bands; ++b) {
        // Band b starts at the row r where the cost before it is nearest b shares of the total,
        // in units of 1 / bands: before[r] * bands against b * total (halves to the lower row,
        // so that equal costs give equal_row_bands).
        const uint64_t shares = static_cast<uint64_t>(b) * total;
        const auto past = std::upper_bound(before.begin(), before.end(), shares, [&](uint64_t s, uint64_t cost) { return s < cost * n; });
        int r = static_cast<int>(past - before.begin()) - 1;  // the last with before[r] * bands <= shares
        if (r < height && before[static_cast<size_t>(r) + 1] * n - shares < shares - before[static_cast<size_t>(r)] * n) ++r;
        // A row at least for this band and each band after it.
        bounds[static_cast<size_t>(b)] = std::clamp(r, bounds[static_cast<size_t>(b) - 1] + 1, height - (bands - b));
    }
    return bounds;
}

std::vector<int> balanced_row_bands(const SampleRanges& ranges, int width, int height, int bands) {
    return balanced_row_bands(samples_per_row(ranges, width, height), bands);
}

}  // namespace crex
