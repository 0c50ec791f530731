/// \file sample_passes.h
/// Splitting a stage's camera samples into passes that fit a memory limit (issue 13). A pass
/// traces samples [first, end) of every pixel of rows [row_begin, row_end) that asks for them
/// and runs the crex over its own bins to the end; the film accumulates. Because every random
/// number of a path is keyed by its pixel and sample index, the image does not depend on how
/// the samples are split, up to the order of the film's sums.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace crex {

struct SamplePass {
    uint32_t first = 0, end = 0;  ///< sample indices [first, end)
    int row_begin = 0, row_end = 0;
    uint64_t samples = 0;         ///< camera samples this pass traces
};

struct PassLimits {
    size_t bytes = 0;             ///< memory the passes' rays may take; 0: one pass
    size_t bytes_per_sample = 0;  ///< what one camera sample and its rays in flight take
    uint32_t max_samples = 0;     ///< samples per pixel per pass at most (0: no limit; tests)
};

/// Which samples each pixel asks for: [start_of[p], end_of[p]), either vector empty meaning
/// `first` or `end` for every pixel.
struct SampleRanges {
    uint32_t first = 0, end = 0;
    std::vector<uint32_t> start_of, end_of;
    uint32_t start(size_t p) const { return start_of.empty() ? first : start_of[p]; }
    uint32_t stop(size_t p) const { return end_of.empty() ? end : end_of[p]; }
};

/// A rectangle of pixels of the full frame: columns [x, x + width), rows [y, y + height).
struct PixelWindow {
    int x = 0, y = 0, width = 0, height = 0;
    bool contains(int px, int py) const { return px >= x && px < x + width && py >= y && py < y + height; }
    bool operator==(const PixelWindow&) const = default;
};

/// `ranges` with samples only in the pixels of `windows` (windowed references: the pixels of
/// the full frame a reference is rendered for, each with the samples it would have there).
SampleRanges only_windows(const SampleRanges& ranges, int width, int height, const std::vector<PixelWindow>& windows);

/// `ranges` with no samples outside rows [row_begin, row_end) (distributed rendering: the
/// rows this process renders).
SampleRanges only_rows(const SampleRanges& ranges, int width, int height, int row_begin, int row_end);
/// `ranges` with no samples in the rows `skip` marks (non-zero; --resume: rows already final).
SampleRanges without_rows(const SampleRanges& ranges, int width, int height, const std::vector<char>& skip);

/// The passes for the samples `ranges` asks for. Passes go over sample indices, as many per
/// pass as fit; when even one sample index of every pixel does not fit, a pass covers a band
/// of rows instead. The passes cover every requested sample exactly once; none is empty.
std::vector<SamplePass> plan_sample_passes(int width, int height, const SampleRanges& ranges, const PassLimits& limits);

/// The camera samples `pass` traces for `ranges` (its rows, its sample indices).
uint64_t samples_in(const SamplePass& pass, const SampleRanges& ranges, int width);

/// Under a time budget, camera samples are scheduled work (issue 15): the part of `pass` whose
/// predicted time fits in `remaining` seconds at `seconds_per_sample`: the whole pass, the band
/// of its first rows whose samples are predicted to take 3/4 of `remaining` (`samples`
/// recounted; the caller admits the next band on a fresh measurement), its first row with
/// samples alone when that row ends nearer the budget than stopping would, else nullopt.
std::optional<SamplePass> pass_within(const SamplePass& pass, const SampleRanges& ranges, int width, double seconds_per_sample,
                                      double remaining);

}  // namespace crex
