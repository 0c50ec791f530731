// Splitting camera samples into passes (issue 13): every requested sample exactly once, no
// pass over its memory, bands of rows when one sample of every pixel does not fit.
#include <gtest/gtest.h>

#include <map>

#include "runtime/driver/pass_sizing.h"
#include "runtime/driver/sample_passes.h"

namespace crex {
namespace {

// How often each (pixel, sample) is covered by the passes.
std::map<std::pair<size_t, uint32_t>, int> coverage(int w, int h, uint32_t first, uint32_t end, const std::vector<uint32_t>& end_of,
                                                    const std::vector<SamplePass>& passes) {
    std::map<std::pair<size_t, uint32_t>, int> seen;
    for (const auto& p : passes) {
        uint64_t n = 0;
        for (int y = p.row_begin; y < p.row_end; ++y)
            for (int x = 0; x < w; ++x) {
                size_t px = static_cast<size_t>(y) * w + x;
                uint32_t e = end_of.empty() ? end : end_of[px];
                for (uint32_t k = std::max(first, p.first); k < std::min(p.end, e); ++k) ++seen[{px, k}], ++n;
            }
        EXPECT_EQ(n, p.samples);
        EXPECT_GT(p.samples, 0u);
    }
    (void)h;
    return seen;
}

void expect_exact_cover(int w, int h, uint32_t first, uint32_t end, const std::vector<uint32_t>& end_of,
                        const std::vector<SamplePass>& passes) {
    auto seen = coverage(w, h, first, end, end_of, passes);
    size_t want = 0;
    for (size_t p = 0; p < static_cast<size_t>(w) * h; ++p) {
        uint32_t e = end_of.empty() ? end : end_of[p];
        for (uint32_t k = first; k < e; ++k) {
            ++want;
            ASSERT_EQ((seen[{p, k}]), 1) << "pixel " << p << " sample " << k;
        }
    }
    EXPECT_EQ(seen.size(), want);
}

TEST(SamplePasses, WithoutALimitOnePassHoldsEverySample) {
    auto passes = plan_sample_passes(8, 4, {0, 16, {}, {}}, {});
    ASSERT_EQ(passes.size(), 1u);
    EXPECT_EQ(passes[0].samples, 8u * 4 * 16);
    expect_exact_cover(8, 4, 0, 16, {}, passes);
}

TEST(SamplePasses, AMemoryLimitSplitsSampleIndicesAndNoPassExceedsIt) {
    PassLimits limits{8 * 4 * 3 * 100, 100, 0};  // three samples of every pixel
    auto passes = plan_sample_passes(8, 4, {2, 16, {}, {}}, limits);
    ASSERT_EQ(passes.size(), 5u);  // 14 samples in passes of 3
    for (const auto& p : passes) EXPECT_LE(p.samples * limits.bytes_per_sample, limits.bytes);
    expect_exact_cover(8, 4, 2, 16, {}, passes);
}

TEST(SamplePasses, FixedSamplesPerPass) {
    auto passes = plan_sample_passes(5, 3, {0, 7, {}, {}}, {0, 0, 3});
    ASSERT_EQ(passes.size(), 3u);
    EXPECT_EQ(passes[0].end - passes[0].first, 3u);
    EXPECT_EQ(passes[2].end - passes[2].first, 1u);
    expect_exact_cover(5, 3, 0, 7, {}, passes);
}

TEST(SamplePasses, BandsOfRowsWhenOneSampleOfEveryPixelIsTooMuch) {
    PassLimits limits{10 * 3 * 64, 64, 0};  // three rows of ten pixels
    auto passes = plan_sample_passes(10, 8, {0, 2, {}, {}}, limits);
    ASSERT_EQ(passes.size(), 6u);  // two sample indices, each in bands of 3, 3 and 2 rows
    for (const auto& p : passes) {
        EXPECT_EQ(p.end - p.first, 1u);
        EXPECT_LE(p.row_end - p.row_begin, 3);
        EXPECT_LE(p.samples * limits.bytes_per_sample, limits.bytes);
    }
    expect_exact_cover(10, 8, 0, 2, {}, passes);
}

// A frame too large for one sample of every pixel in the first pass's eighth of the room:
// after it, the later passes (planned at an eighth too) merge up to the whole room, each
// pixel still taking its samples in order, every sample once. (Before, they stayed at an
// eighth: 5,568 passes at 3840x2160, 64 spp, the process at 385 MB of 1 GiB.)
TEST(StagePasses, AfterAFirstBandTheLaterPassesMergeUpToTheRoom) {
    const int w = 10, h = 64;
    PassLimits limits{static_cast<size_t>(w) * 8 * kBytesPerSample, 0, 0};  // eight rows of one sample
    StagePasses stage(w, h, {0, 3, {}, {}}, limits, false, 0);
    const size_t planned = stage.passes().size();
    ASSERT_EQ(stage.passes()[0].row_end - stage.passes()[0].row_begin, 1);  // an eighth: one row
    const SamplePass first = stage.passes()[0];
    EXPECT_EQ(stage.replan_after_first(/*peak_rays_held=*/w, static_cast<size_t>(w) * h), kBytesPerSample);
    const std::vector<SamplePass>& passes = stage.passes();
    EXPECT_EQ(passes[0].row_end, first.row_end);
    EXPECT_LT(passes.size(), planned / 4);
    for (size_t i = 1; i < passes.size(); ++i) EXPECT_LE(passes[i].samples * kBytesPerSample, limits.bytes);
    expect_exact_cover(w, h, 0, 3, {}, passes);
    std::vector<uint32_t> next(static_cast<size_t>(w) * h, 0);  // each pixel's samples in order
    for (const SamplePass& p : passes)
        for (int y = p.row_begin; y < p.row_end; ++y) {
            ASSERT_EQ(next[static_cast<size_t>(y) * w], p.first) << "row " << y;
            next[static_cast<size_t>(y) * w] = p.end;
        }
}

TEST(SamplePasses, PerPixelEndsContinueFromTheFirstSampleAndSkipPixelsThatAskForNone) {
    const int w = 6, h = 5;
    std::vector<uint32_t> end_of(w * h);
    for (size_t p = 0; p < end_of.size(); ++p) end_of[p] = static_cast<uint32_t>((p * 7) % 11);  // 0..10, some below first
    PassLimits limits{40 * 32, 32, 0};
    auto passes = plan_sample_passes(w, h, {2, 0, {}, end_of}, limits);
    for (const auto& p : passes) EXPECT_LE(p.samples * limits.bytes_per_sample, limits.bytes);
    expect_exact_cover(w, h, 2, 0, end_of, passes);
    // Nothing asked for: no pass.
    EXPECT_TRUE(plan_sample_passes(w, h, {20, 0, {}, end_of}, limits).empty());
}

TEST(SamplePasses, PerPixelStartsAsInALaterRound) {
    // Each pixel continues from the samples it has (a round of the cyclic process): every
    // (pixel, k) with start <= k < end is covered once, nothing else.
    const int w = 7, h = 3;
    std::vector<uint32_t> start_of(w * h), end_of(w * h);
    for (size_t p = 0; p < start_of.size(); ++p) start_of[p] = static_cast<uint32_t>(p % 5), end_of[p] = static_cast<uint32_t>(p % 5 + p % 3);
    for (uint32_t most : {0u, 1u, 2u}) {
        auto passes = plan_sample_passes(w, h, {0, 0, start_of, end_of}, {0, 0, most});
        std::map<std::pair<size_t, uint32_t>, int> seen;
        for (const auto& pass : passes) {
            uint64_t n = 0;
            for (size_t p = static_cast<size_t>(pass.row_begin) * w; p < static_cast<size_t>(pass.row_end) * w; ++p)
                for (uint32_t k = std::max(start_of[p], pass.first); k < std::min(end_of[p], pass.end); ++k) ++seen[{p, k}], ++n;
            EXPECT_EQ(n, pass.samples);
        }
        size_t want = 0;
        for (size_t p = 0; p < start_of.size(); ++p)
            for (uint32_t k = start_of[p]; k < end_of[p]; ++k, ++want) EXPECT_EQ((seen[{p, k}]), 1) << p << " " << k;
        EXPECT_EQ(seen.size(), want);
    }
}

// --resume: the rows a partial image holds get no samples, the others all they asked for;
// only_rows and without_rows of complementary rows add up to the whole.
TEST(SamplePasses, WithoutRowsLeavesOutExactlyTheFinalRows) {
    const int w = 5, h = 6;
    const SampleRanges all{2, 7, {}, {}};
    const std::vector<char> final_rows = {1, 1, 0, 1, 0, 0};
    const SampleRanges rest = without_rows(all, w, h, final_rows);
    uint64_t samples = 0;
    for (size_t p = 0; p < static_cast<size_t>(w * h); ++p) {
        const bool final_row = final_rows[p / w] != 0;
        EXPECT_EQ(rest.start(p), 2u);
        EXPECT_EQ(rest.stop(p), final_row ? 2u : 7u) << p;
        samples += rest.stop(p) - rest.start(p);
    }
    EXPECT_EQ(samples, 3u * w * 5);
    const SampleRanges band = only_rows(all, w, h, 2, 3);
    for (size_t p = 0; p < static_cast<size_t>(w * h); ++p) EXPECT_EQ(band.stop(p) > band.start(p), p / w == 2) << p;
    auto passes = plan_sample_passes(w, h, rest, {0, 0, 0});
    uint64_t planned = 0;
    for (const auto& pass : passes) planned += pass.samples;
    EXPECT_EQ(planned, samples);
}

// Under a budget a pass is cut to the band of rows its samples fit (3/4 of the time left). A
// selective pass's first rows may ask for no sample of it: they cost nothing and go with the
// band, which ends at rows that do (the band used to be sized by the mean row, and a band of
// empty rows ended the stage with a fifth of a 0.5 s budget left).
TEST(PassWithin, RowsWithoutSamplesGoWithTheBandAndDoNotEndTheStage) {
    const int w = 4, h = 10;
    SampleRanges ranges{0, 0, std::vector<uint32_t>(w * h, 0), std::vector<uint32_t>(w * h, 0)};
    for (size_t p = 6 * w; p < static_cast<size_t>(w * h); ++p) ranges.end_of[p] = 2;  // rows 6-9: samples 0 and 1
    const SamplePass pass{0, 2, 0, h, samples_in({0, 2, 0, h, 0}, ranges, w)};
    ASSERT_EQ(pass.samples, 32u);
    // 1 s a sample, 12 s left: 9 samples fit in 3/4 of it, so row 6 (8 samples) and not row 7.
    const auto band = pass_within(pass, ranges, w, 1.0, 12.0);
    ASSERT_TRUE(band.has_value());
    EXPECT_EQ(band->row_begin, 0);
    EXPECT_EQ(band->row_end, 7);
    EXPECT_EQ(band->samples, 8u);
    EXPECT_EQ(band->samples, samples_in(*band, ranges, w));
    // Time for all of it: the pass whole.
    EXPECT_EQ(pass_within(pass, ranges, w, 1.0, 100.0)->row_end, h);
}

// When not one row fits in 3/4 of the time left, the first row with samples still runs if its
// end lands nearer the budget than stopping now would: the last band's granularity costs at
// most half a row either way.
TEST(PassWithin, ARowTooLongRunsOnlyWhenItEndsNearerTheBudgetThanStopping) {
    const int w = 8, h = 3;
    const SampleRanges ranges{0, 1, {}, {}};
    const SamplePass pass{0, 1, 0, h, 24};
    // A row takes 8 s. 5 s left: past the budget by 3 s against stopping 5 s early: it runs.
    const auto ran = pass_within(pass, ranges, w, 1.0, 5.0);
    ASSERT_TRUE(ran.has_value());
    EXPECT_EQ(ran->row_end - ran->row_begin, 1);
    EXPECT_EQ(ran->samples, 8u);
    EXPECT_TRUE(pass_within(pass, ranges, w, 1.0, 4.0).has_value());   // 4 s over against 4 s early
    EXPECT_FALSE(pass_within(pass, ranges, w, 1.0, 3.9).has_value());  // 4.1 s over against 3.9 s early
    EXPECT_FALSE(pass_within(pass, ranges, w, 1.0, 0.0).has_value());
}

}  // namespace
}  // namespace crex
