#include "runtime/driver/sample_passes.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace crex {

std::vector<SamplePass> plan_sample_passes(int width, int height, const SampleRanges& ranges, const PassLimits& limits) {
    const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
    const bool uniform = ranges.start_of.empty() && ranges.end_of.empty();
    uint32_t lo = ranges.first, hi = ranges.end;
    if (!uniform) {
        lo = UINT32_MAX, hi = 0;
        for (size_t p = 0; p < pixels; ++p)
            if (ranges.start(p) < ranges.stop(p)) lo = std::min(lo, ranges.start(p)), hi = std::max(hi, ranges.stop(p));
    }
    std::vector<SamplePass> passes;
    if (hi <= lo || pixels == 0) return passes;

    // count[k - lo]: pixels that ask for sample index k.
    std::vector<uint64_t> count(hi - lo, uniform ? pixels : 0);
    if (!uniform) {
        std::vector<int64_t> delta(hi - lo + 1, 0);
        for (size_t p = 0; p < pixels; ++p)
            if (ranges.start(p) < ranges.stop(p)) ++delta[ranges.start(p) - lo], --delta[ranges.stop(p) - lo];
        int64_t alive = 0;
        for (size_t k = 0; k < count.size(); ++k) count[k] = static_cast<uint64_t>(alive += delta[k]);
    }
    const uint64_t cap = limits.bytes && limits.bytes_per_sample
                             ? std::max<uint64_t>(1, limits.bytes / limits.bytes_per_sample)
                             : std::numeric_limits<uint64_t>::max();
    const uint32_t max_indices = limits.max_samples ? limits.max_samples : std::numeric_limits<uint32_t>::max();

    auto band_samples = [&](uint32_t k, int r0, int r1) -> uint64_t {
        if (uniform) return static_cast<uint64_t>(r1 - r0) * static_cast<uint64_t>(width);
        uint64_t n = 0;
        for (size_t p = static_cast<size_t>(r0) * width; p < static_cast<size_t>(r1) * width; ++p)
            n += ranges.start(p) <= k && k < ranges.stop(p);
        return n;
    };

    uint32_t k = lo;
    while (k < hi) {
        if (count[k - lo] == 0) {  // a gap between pixels' ranges
            ++k;
            continue;
        }
        uint64_t total = 0;
        uint32_t k1 = k;
        while (k1 < hi && k1 - k < max_indices && total + count[k1 - lo] <= cap) total += count[k1 - lo], ++k1;
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

uint64_t samples_in(const SamplePass& pass, const SampleRanges& ranges, int width) {
    uint64_t n = 0;
    const size_t p0 = static_cast<size_t>(pass.row_begin) * static_cast<size_t>(width);
    const size_t p1 = static_cast<size_t>(pass.row_end) * static_cast<size_t>(width);
    for (size_t p = p0; p < p1; ++p) {
        uint32_t first = std::max(ranges.start(p), pass.first), end = std::min(pass.end, ranges.stop(p));
        n += end > first ? end - first : 0;
    }
    return n;
}

std::optional<SamplePass> pass_within(const SamplePass& pass, const SampleRanges& ranges, int width, double seconds_per_sample,
                                      double remaining) {
    if (!(remaining > 0)) return std::nullopt;
    // Nothing is admitted on more than three quarters of what is left: rows hold about the
    // same number of samples but not the same work (a glass sphere's rows cost more), so the
    // bands that follow, each measured anew, close in on the budget instead of one band
    // overshooting it.
    const double predicted = seconds_per_sample * static_cast<double>(pass.samples);
    if (!(predicted > 0.75 * remaining)) return pass;
    // The first rows by their own samples: a selective pass's rows hold very different numbers
    // (none where no pixel asks for this sample index), and a band sized by the pass's mean
    // row that held only empty rows ended the stage with time left (a tc_rp render on the
    // room stopped at 0.386 s of 0.5). Rows without samples cost nothing and go with the band.
    const double allowed = 0.75 * remaining / seconds_per_sample;
    SamplePass band = pass, row = pass;
    band.samples = 0;
    for (band.row_end = pass.row_begin; band.row_end < pass.row_end; ++band.row_end) {
        row.row_begin = band.row_end, row.row_end = band.row_end + 1;
        const uint64_t n = samples_in(row, ranges, width);
        if (static_cast<double>(band.samples + n) > allowed) {
            // Not even this row fits: it still runs when its end lands nearer the budget than
            // stopping here would (its time past the budget under what is left), so the last
            // row's granularity costs at most half a row either way, not up to a row and a third.
            if (band.samples == 0 && seconds_per_sample * static_cast<double>(n) <= 2 * remaining) band.samples = n, ++band.row_end;
            break;
        }
        band.samples += n;
    }
    if (band.samples == 0) return std::nullopt;
    return band;
}

namespace {
// `ranges` with samples only in the rows `renders` says.
template <typename Renders>
SampleRanges rows_where(const SampleRanges& ranges, int width, int height, Renders renders) {
    const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
    SampleRanges out;
    out.start_of.resize(pixels);
    out.end_of.resize(pixels);
    for (size_t p = 0; p < pixels; ++p) {
        const int row = static_cast<int>(p / static_cast<size_t>(width));
        out.start_of[p] = ranges.start(p);
        out.end_of[p] = renders(row) ? ranges.stop(p) : ranges.start(p);
    }
    return out;
}
}  // namespace

SampleRanges only_rows(const SampleRanges& ranges, int width, int height, int row_begin, int row_end) {
    return rows_where(ranges, width, height, [&](int row) { return row >= row_begin && row < row_end; });
}

SampleRanges only_windows(const SampleRanges& ranges, int width, int height, const std::vector<PixelWindow>& windows) {
    const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
    SampleRanges out;
    out.start_of.resize(pixels);
    out.end_of.resize(pixels);
    for (size_t p = 0; p < pixels; ++p) out.start_of[p] = out.end_of[p] = ranges.start(p);
    for (const PixelWindow& w : windows)
        for (int y = std::max(w.y, 0); y < std::min(w.y + w.height, height); ++y)
            for (int x = std::max(w.x, 0); x < std::min(w.x + w.width, width); ++x) {
                const size_t p = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
                out.end_of[p] = ranges.stop(p);
            }
    return out;
}

SampleRanges without_rows(const SampleRanges& ranges, int width, int height, const std::vector<char>& skip) {
    return rows_where(ranges, width, height, [&](int row) { return static_cast<size_t>(row) >= skip.size() || !skip[static_cast<size_t>(row)]; });
}

}  // namespace crex
