// Distributed rendering's bands of rows (issue 19): equal bands where nothing is known, bands
// of about the same cost where the stage's camera samples are known; never an empty band when
// there are rows enough, the same split every time.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "runtime/driver/row_bands.h"

namespace crex {
namespace {

// The cost each band of `bounds` carries.
std::vector<uint64_t> band_costs(const std::vector<uint64_t>& row_cost, const std::vector<int>& bounds) {
    std::vector<uint64_t> costs;
    for (size_t b = 0; b + 1 < bounds.size(); ++b)
        costs.push_back(std::accumulate(row_cost.begin() + bounds[b], row_cost.begin() + bounds[b + 1], uint64_t{0}));
    return costs;
}

void expect_a_split_of(const std::vector<int>& bounds, int height, int bands) {
    ASSERT_EQ(bounds.size(), static_cast<size_t>(bands) + 1);
    EXPECT_EQ(bounds.front(), 0);
    EXPECT_EQ(bounds.back(), height);
    EXPECT_TRUE(std::is_sorted(bounds.begin(), bounds.end()));
}

TEST(RowBands, EqualBandsStartAtTheNearestRow) {
    EXPECT_EQ(equal_row_bands(25, 2), (std::vector<int>{0, 12, 25}));  // 12.5: halves down
    EXPECT_EQ(equal_row_bands(17, 3), (std::vector<int>{0, 6, 11, 17}));  // 5.67, 11.33
    EXPECT_EQ(equal_row_bands(64, 1), (std::vector<int>{0, 64}));
    EXPECT_EQ(equal_row_bands(2, 4), (std::vector<int>{0, 0, 1, 1, 2}));  // fewer rows than bands: some empty
}

TEST(RowBands, EqualCostsGiveEqualRows) {
    for (int height : {1, 7, 17, 25, 64, 97})
        for (int bands : {1, 2, 3, 4, 7}) {
            if (height < bands) continue;
            EXPECT_EQ(balanced_row_bands(std::vector<uint64_t>(static_cast<size_t>(height), 5), bands), equal_row_bands(height, bands))
                << height << " rows, " << bands << " bands";
        }
}

TEST(RowBands, NoCostAtAllGivesEqualRows) {
    EXPECT_EQ(balanced_row_bands(std::vector<uint64_t>(30, 0), 4), equal_row_bands(30, 4));
    EXPECT_EQ(balanced_row_bands(SampleRanges{3, 3, {}, {}}, 8, 30, 4), equal_row_bands(30, 4));
}

TEST(RowBands, ACostInAFewRowsGetsNarrowBandsThere) {
    // 64 rows of cost 1, rows 40..47 of cost 100 each: 856 in all, 214 a band of 4.
    std::vector<uint64_t> cost(64, 1);
    std::fill(cost.begin() + 40, cost.begin() + 48, 100);
    const std::vector<int> bounds = balanced_row_bands(cost, 4);
    expect_a_split_of(bounds, 64, 4);
    // The first band takes the cheap rows before the costly ones and two of them, the next two
    // bands two costly rows each, the last band the other two and the cheap tail.
    EXPECT_EQ(bounds, (std::vector<int>{0, 42, 44, 46, 64}));
    const std::vector<uint64_t> costs = band_costs(cost, bounds);
    const uint64_t share = 856 / 4;
    for (uint64_t c : costs) {
        EXPECT_LE(c, share + 100) << "within a costly row of its share";
        EXPECT_GE(c + 100, share);
    }
    // The equal split's third band carried all eight costly rows.
    const std::vector<uint64_t> equal = band_costs(cost, equal_row_bands(64, 4));
    EXPECT_EQ(*std::max_element(equal.begin(), equal.end()), 808u);
    EXPECT_EQ(*std::max_element(costs.begin(), costs.end()), 240u);
}

TEST(RowBands, EveryBandHasARowWhenThereAreRowsEnough) {
    // All the cost in the first row: the other bands still get a row each.
    std::vector<uint64_t> cost(10, 0);
    cost[0] = 1000;
    std::vector<int> bounds = balanced_row_bands(cost, 4);
    expect_a_split_of(bounds, 10, 4);
    for (size_t b = 0; b + 1 < bounds.size(); ++b) EXPECT_LT(bounds[b], bounds[b + 1]) << "band " << b;
    // All of it in the last row.
    std::fill(cost.begin(), cost.end(), 0);
    cost[9] = 1000;
    bounds = balanced_row_bands(cost, 4);
    expect_a_split_of(bounds, 10, 4);
    for (size_t b = 0; b + 1 < bounds.size(); ++b) EXPECT_LT(bounds[b], bounds[b + 1]) << "band " << b;
    // As many rows as bands: a row each.
    EXPECT_EQ(balanced_row_bands(std::vector<uint64_t>{9, 0, 0, 1}, 4), (std::vector<int>{0, 1, 2, 3, 4}));
}

TEST(RowBands, TheCostIsTheCameraSamplesOfEachRow) {
    // 4x3: row 0 asks for nothing, row 1 for 2 samples a pixel, row 2 for 6 in one pixel; an
    // end below the start counts as none.
    SampleRanges r{0, 0, std::vector<uint32_t>(12, 1), std::vector<uint32_t>(12, 1)};
    for (size_t p = 4; p < 8; ++p) r.end_of[p] = 3;
    r.end_of[9] = 7;
    r.end_of[10] = 0;
    EXPECT_EQ(samples_per_row(r, 4, 3), (std::vector<uint64_t>{0, 8, 6}));
    EXPECT_EQ(balanced_row_bands(r, 4, 3, 2), (std::vector<int>{0, 2, 3}));
}

TEST(RowBands, TheSameSplitEveryTime) {
    std::vector<uint64_t> cost(200);
    for (size_t r = 0; r < cost.size(); ++r) cost[r] = (r * 7919) % 97;
    const std::vector<int> first = balanced_row_bands(cost, 6);
    expect_a_split_of(first, 200, 6);
    for (int k = 0; k < 5; ++k) EXPECT_EQ(balanced_row_bands(cost, 6), first);
}

}  // namespace
}  // namespace crex
