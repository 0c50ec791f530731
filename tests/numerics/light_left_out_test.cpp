// Light the path limits leave out is measured and said (issue 37): in a closed box of
// high albedo lit from inside (the white furnace, radiance le / (1 - a) everywhere) the
// renderer converges to the closed form once the user raises the limits, and with the
// defaults the share it left out is reported, large enough at albedo 0.999 for W404.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/support/test_scenes.h"

namespace crex {
namespace {

RunResult render_furnace(double albedo, uint32_t max_depth, bool cache = false, uint32_t bounces = 8) {
    Scene s = testing::furnace_box(albedo, 0.25);
    RunSettings o;
    o.width = o.height = 8;
    o.spp = 4;
    o.executor.shade.max_depth = max_depth;
    if (cache) {
        IcSettings ic;
        ic.divisions = 64, ic.bounces = bounces, ic.caustic_photons = 0;
        o.irradiance_cache = ic;
    }
    return render(s, testing::lower_or_die("D*"), o);
}

class FurnaceWithRaisedLimits : public ::testing::TestWithParam<double> {};

// At albedo 0.9 and 0.99 a path needs about 70 and 700 bounces before Russian roulette ends it
// without bias: with --max-depth 65535 the image is the closed form, and nothing is said lost.
TEST_P(FurnaceWithRaisedLimits, ConvergesToTheClosedForm) {
    const double a = GetParam(), expected = 0.25 / (1 - a);
    RunResult r = render_furnace(a, 65535);
    ASSERT_TRUE(testing::all_finite(r.image()));
    EXPECT_NEAR(testing::mean_luminance(r.image()) / expected, 1.0, 0.02) << "albedo " << a;
    EXPECT_LT(r.light_cut_by_depth, 1e-3);
    EXPECT_EQ(r.light_cut_by_weight, 0.0);  // roulette ends paths without losing their light
}

INSTANTIATE_TEST_SUITE_P(Albedo, FurnaceWithRaisedLimits, ::testing::Values(0.9, 0.99));

// The default depth 256 keeps a^257 of every path's throughput: 0.2 % at 0.99 ... 77 % at
// 0.999, where the image is a fifth of the closed form. The estimate T / (1 + T), T that
// throughput per camera sample, is then 0.44: more than the 1 % that W404 warns at, and a
// lower bound of the true share (the light beyond the cut is brighter than the light before it).
TEST(FurnaceWithDefaultLimits, ReportsTheLightLeftOutByTheDepth) {
    const double a = 0.999, expected = 0.25 / (1 - a);
    RunResult r = render_furnace(a, 256);
    const double rendered = testing::mean_luminance(r.image()) / expected;
    const double kept = (1 - std::pow(a, 257)) / (1 - a) * (1 - a);  // the partial sum of the series
    EXPECT_NEAR(rendered, kept, 0.01);
    const double t = std::pow(a, 257);
    EXPECT_NEAR(r.light_cut_by_depth, t / (1 + t), 0.01);
    EXPECT_GT(r.light_cut_by_depth, 0.01);
    EXPECT_LE(r.light_cut_by_depth, 1 - rendered);  // never more than the truth
}

// At albedo 0.9 the default limits leave out nothing worth a word.
TEST(FurnaceWithDefaultLimits, SaysNothingWhenLittleIsLost) {
    RunResult r = render_furnace(0.9, 256);
    EXPECT_LT(r.light_cut_by_depth, 1e-6);
    EXPECT_EQ(r.light_cut_by_cache, 0.0);
}

// The cache's 8 bounces at albedo 0.999 keep about 8 of the series' 1000 terms: the share of the
// D light past the last bounce is measured as the product of the levels' mean albedos.
TEST(FurnaceWithDefaultLimits, ReportsTheLightLeftOutByTheCacheBounces) {
    RunResult r = render_furnace(0.999, 256, true, 8);
    ASSERT_TRUE(testing::all_finite(r.image()));
    EXPECT_GT(r.light_cut_by_cache, 0.01);
    EXPECT_LT(testing::mean_luminance(r.image()) / (0.25 / (1 - 0.999)), 0.05);  // what it is about
}

}  // namespace
}  // namespace crex
