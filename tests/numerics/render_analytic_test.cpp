// The renderer against closed forms: a white furnace and a plane under a square light.
#include <gtest/gtest.h>

#include "runtime/base/sampling.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

class WhiteFurnace : public ::testing::TestWithParam<double> {};

TEST_P(WhiteFurnace, ConvergesToEmissionOverOneMinusAlbedo) {
    double a = GetParam(), le = 0.25;
    Scene s = testing::furnace_box(a, le);
    RunResult r = testing::render_crex(s, "D*", 16, 4);
    std::vector<float> img = r.image();
    ASSERT_TRUE(testing::all_finite(img));
    double expected = le / (1 - a);
    EXPECT_NEAR(testing::mean_luminance(img) / expected, 1.0, 0.01) << "albedo " << a;
    // Every pixel, not only the mean: lobe splitting makes the diffuse weights deterministic,
    // so only roulette adds noise.
    for (size_t i = 0; i < img.size(); ++i) ASSERT_NEAR(img[i] / expected, 1.0, 0.03) << "pixel " << i / 3;
    EXPECT_EQ(r.stats.camera.rays, 16u * 16u * 4u);
}

INSTANTIATE_TEST_SUITE_P(Albedo, WhiteFurnace, ::testing::Values(0.5, 0.95));

TEST(WhiteFurnace, WithoutRouletteTheTruncationBiasIsTheGeometricTail) {
    // Dropping rays below lw = 1e-3 (no roulette) stops the series once a^k < 1e-3:
    // the image is the partial sum, not le / (1 - a).
    double a = 0.5, le = 1;
    Scene s = testing::furnace_box(a, le);
    RunSettings o;
    o.width = o.height = 8;
    o.spp = 1;
    o.executor.shade.roulette = false;
    RunResult r = render(s, testing::lower_or_die("D*"), o);
    int k = 0;
    double partial = 0, w = 1;
    while (w >= 1e-3) partial += w * le, w *= a, ++k;  // terms whose weight is at least lw
    EXPECT_NEAR(testing::mean_luminance(r.image()), partial, 1e-6);
}

TEST(SquareLight, DiffusePlaneMatchesTheAnalyticIrradiance) {
    double rho = 0.6, L = 3.0, half = 0.5, h = 1.0;
    Scene s = testing::square_light_over_plane(rho, L, half, h);
    // Camera rays only: the crex is empty, so the image is direct light at the primary hits.
    RunResult r = testing::render_crex(s, "", 16, 16, 0, 16);
    double expected = rho / kPi * testing::irradiance_under_square(L, half, h);
    EXPECT_NEAR(testing::mean_luminance(r.image()) / expected, 1.0, 0.01);
}

TEST(SquareLight, FarAwayItActsLikeAPointSource) {
    // Sanity of the closed form itself: for h >> half, E -> L * area / h^2.
    double L = 2, half = 0.01, h = 10;
    EXPECT_NEAR(testing::irradiance_under_square(L, half, h) / (L * 4 * half * half / (h * h)), 1.0, 1e-4);
}

}  // namespace
}  // namespace crex
