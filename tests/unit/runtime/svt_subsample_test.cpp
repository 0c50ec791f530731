// Selective variables per pixel and the adaptive sub-sampling grid.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "runtime/pipeline/subsample.h"
#include "runtime/pipeline/svt.h"

namespace crex {
namespace {

TEST(Svt, AWhereTheMapIsZeroBWhereItIsOneInEitherOrder) {
    std::vector<float> map = {0.0f, 0.5f, 1.0f, NAN, 2.0f};
    auto spp = variable_values(1, 25, pipeline::ModulationFunction::kLinear, map, true);
    EXPECT_EQ(spp, (std::vector<double>{1, 13, 25, 1, 25}));
    auto radius = variable_values(0.75, 0.125, pipeline::ModulationFunction::kLinear, map, false);
    EXPECT_DOUBLE_EQ(radius[0], 0.75);
    EXPECT_DOUBLE_EQ(radius[1], 0.4375);
    EXPECT_DOUBLE_EQ(radius[2], 0.125);
    EXPECT_DOUBLE_EQ(variable_values(0, 10, pipeline::ModulationFunction::kQuadratic, {0.5f}, false)[0], 2.5);
    EXPECT_DOUBLE_EQ(variable_values(0, 10, pipeline::ModulationFunction::kStep, {0.49f}, false)[0], 0);
    EXPECT_FALSE(modulate("cubic", 0.5));
    EXPECT_DOUBLE_EQ(*modulate("sqrt", 0.25), 0.5);
    EXPECT_DOUBLE_EQ(*modulate("", 0.25), 0.25);
}

TEST(Subsample, UniformSpacingRendersTheLatticeAndInterpolatesLinearImagesExactly) {
    const int w = 33, h = 17;
    SubsampleGrid grid(w, h, std::vector<double>(w * h, 8));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            bool lattice = (x % 8 == 0 || x == w - 1) && (y % 8 == 0 || y == h - 1);
            EXPECT_EQ(grid.rendered(static_cast<uint32_t>(y * w + x)), lattice) << x << "," << y;
        }
    // Bilinear interpolation reproduces a linear image.
    std::vector<float> rgb(3 * w * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) rgb[3 * (y * w + x) + c] = static_cast<float>(0.5 * x + 0.25 * y + c);
    std::vector<float> filled = rgb;
    for (size_t p = 0; p < static_cast<size_t>(w * h); ++p)
        if (!grid.rendered(static_cast<uint32_t>(p)))
            for (int c = 0; c < 3; ++c) filled[3 * p + c] = -1;  // what the renderer did not compute
    grid.fill(filled);
    for (size_t i = 0; i < rgb.size(); ++i) EXPECT_NEAR(filled[i], rgb[i], 1e-4) << i;
}

// A strided preview's pixels without samples (issue 34): a linear image is rebuilt exactly from
// the corners that have samples, in every channel; a corner without samples is left out and
// the others' weights renormalised; a pixel none of whose corners has samples keeps its value;
// the weights made once give the same on a second buffer.
TEST(Subsample, UnsampledPixelsTakeTheirSampledCornersOnce) {
    const int w = 17, h = 9;
    SubsampleGrid grid(w, h, std::vector<double>(static_cast<size_t>(w * h), 8.0));
    std::vector<uint8_t> sampled(static_cast<size_t>(w * h), 0);
    for (uint32_t p = 0; p < sampled.size(); ++p) sampled[p] = grid.rendered(p);
    std::vector<float> two(sampled.size() * 2, -1.0f);  // two channels: 2x + y and 7
    for (uint32_t p = 0; p < sampled.size(); ++p)
        if (sampled[p]) two[2 * p] = static_cast<float>(2 * (p % w) + p / w), two[2 * p + 1] = 7.0f;
    const SubsampleGrid::Fill fill = grid.unsampled_fill(sampled);
    std::vector<float> again = two;
    SubsampleGrid::apply(fill, two);
    for (uint32_t p = 0; p < sampled.size(); ++p) {
        EXPECT_NEAR(two[2 * p], 2.0 * (p % w) + p / w, 1e-4) << p;
        EXPECT_NEAR(two[2 * p + 1], 7.0, 1e-5) << p;
    }
    grid.fill_unsampled(again, sampled);
    EXPECT_EQ(again, two);
    // The corner (8, 8) without samples: (4, 8) on the bottom edge between (0, 8) and (8, 8)
    // takes (0, 8) alone; with none of its corners sampled, (12, 4) keeps its value.
    std::vector<uint8_t> fewer = sampled;
    const auto at = [&](int x, int y) { return static_cast<size_t>(y * w + x); };
    for (int x : {8, 16})
        for (int y : {0, 8}) fewer[at(x, y)] = 0;
    fewer[at(8, 8)] = 0;
    std::vector<float> one(sampled.size(), 5.0f);
    one[at(0, 8)] = 3.0f;
    grid.fill_unsampled(one, fewer);
    EXPECT_FLOAT_EQ(one[at(4, 8)], 3.0f);
    EXPECT_FLOAT_EQ(one[at(12, 4)], 5.0f);
}

TEST(Subsample, SquaresSplitWhereAPixelAsksForFinerSpacing) {
    const int w = 17, h = 17;
    std::vector<double> spacing(w * h, 8);
    spacing[5 * w + 5] = 1;  // one pixel wants every pixel rendered around it
    SubsampleGrid grid(w, h, spacing);
    EXPECT_TRUE(grid.rendered(5 * w + 5));
    EXPECT_TRUE(grid.rendered(5 * w + 4));
    EXPECT_FALSE(grid.rendered(12 * w + 12));  // far away: still the coarse lattice
    EXPECT_TRUE(grid.rendered(16 * w + 16));
    SubsampleGrid all(w, h, std::vector<double>(w * h, 1));
    EXPECT_EQ(all.rendered_count(), static_cast<size_t>(w * h));
}

}  // namespace
}  // namespace crex
