// Lobe directions stratified across a pixel's camera samples (HitRandom::camera_hit): the first
// bounce of a pixel's samples follows its own scrambled (0,2)-sequence, so a floor lit only by
// what its diffuse lobe finds is far closer to the converged image at 16 samples than 16
// independent directions would bring it, and unbiased.
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/base/sampling.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

// A diffuse floor under a 1 x 1 glow of radius 0 at height 1: no direct lighting samples it
// (radius 0), so the floor's light is what its D lobe's rays meet. Seen from above.
Scene floor_under_a_glow() {
    Scene s;
    s.materials.push_back(testing::make_material("floor", MaterialType::kPlastic, {0.6, 0.6, 0.6}));
    s.materials.push_back(testing::make_material("glow", MaterialType::kGlow, {4, 4, 4}));
    s.shapes.push_back(testing::quad("floor", {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, {-2, 0, -2}));
    s.shapes.push_back(testing::quad("glow", {-0.5, 1, -0.5}, {0.5, 1, -0.5}, {0.5, 1, 0.5}, {-0.5, 1, 0.5}));
    s.camera.position = {0, 0.6, 0};
    s.camera.direction = {0, -1, 0};
    s.camera.up = {0, 0, -1};
    s.camera.vfov_deg = 90;
    return s;
}

TEST(PixelLobeSamples, SixteenCameraSamplesBounceBetterThanSixteenIndependentOnes) {
    // Against a 1024-sample render: 1 sample's error is the per-sample variance v; 16
    // independent ones would leave v / 16. The pixel's stratified directions must do at least
    // twice as well (they do 0.32 of it; independent ones, as before this, did 1.1), and agree
    // in the mean.
    Scene s = floor_under_a_glow();
    const std::vector<float> ref = testing::render_crex(s, "D", 24, 1024, 5).image();
    const std::vector<float> one = testing::render_crex(s, "D", 24, 1, 1).image();
    const std::vector<float> sixteen = testing::render_crex(s, "D", 24, 16, 1).image();
    const double v = testing::mean_squared_difference(one, ref), e16 = testing::mean_squared_difference(sixteen, ref);
    ASSERT_GT(v, 0);
    EXPECT_LT(e16, 0.5 * v / 16) << "ratio " << e16 / (v / 16) << ", 1 sample " << v << ", 16 samples " << e16;
    EXPECT_NEAR(testing::mean_luminance(sixteen) / testing::mean_luminance(ref), 1.0, 0.01);
}

TEST(PixelLobeSamples, OnlyACameraHitsLobesFollowThePixelsSequence) {
    // The same path and depth: a deeper hit's numbers are its hash's; a camera hit's lobes are
    // point `sample` of the pixel's sequence, its other numbers unchanged.
    const HitRandom deep(42, 0), camera = HitRandom::camera_hit(42, 0, 7, 3);
    double u0, v0, u1, v1;
    deep.pair(RandomUse::kLobeD, u0, v0);
    camera.pair(RandomUse::kLobeD, u1, v1);
    EXPECT_TRUE(u0 != u1 || v0 != v1);
    deep.pair(RandomUse::kLight, u0, v0);
    camera.pair(RandomUse::kLight, u1, v1);
    EXPECT_EQ(u0, u1);
    EXPECT_EQ(v0, v1);
    EXPECT_EQ(deep(RandomUse::kRoulette, 2), camera(RandomUse::kRoulette, 2));
    // The pixel's 16 first directions stratify the unit square: one in each 4 x 4 cell.
    std::vector<int> cells(16, 0);
    for (uint32_t k = 0; k < 16; ++k) {
        double u, v;
        HitRandom::camera_hit(1000 + k, 0, 7, k).pair(RandomUse::kLobeD, u, v);
        ++cells[static_cast<size_t>(u * 4) * 4 + static_cast<size_t>(v * 4)];
    }
    for (int c : cells) EXPECT_EQ(c, 1);
}

}  // namespace
}  // namespace crex
