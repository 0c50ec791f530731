// What a frame inherits from the frame before (issue 36, --reuse-frames): the samples it
// takes itself, how the image blends what it inherited, and which surfaces may inherit.
#include <gtest/gtest.h>

#include "runtime/api/frame_reuse.h"
#include "runtime/driver/pixel_history.h"

namespace crex {
namespace {

TEST(PixelHistory, APixelTakesWhatItDoesNotInheritAndAlwaysOneSample) {
    EXPECT_EQ(own_samples(8, 0, 8), 8u);
    EXPECT_EQ(own_samples(8, 3, 8), 5u);
    EXPECT_EQ(own_samples(8, 2.5f, 8), 6u);  // a part of a sample is not one
    EXPECT_EQ(own_samples(8, 7.9f, 8), 1u);
    EXPECT_EQ(own_samples(8, 100, 8), 1u);
    EXPECT_EQ(own_samples(1, 5, 8), 1u);
    EXPECT_EQ(own_samples(0, 5, 8), 0u);
    EXPECT_EQ(own_samples(4, -3, 8), 4u);
    EXPECT_EQ(own_samples(8, 100, 0), 1u);  // no cap
}

// A pixel asking for more than frames + 1 samples takes at least spp / (frames + 1) of its
// own, however much it carries: so its own samples keep a weight of 1 / (frames + 1).
TEST(PixelHistory, APixelAskingForManyTakesAShareOfThemEveryFrame) {
    EXPECT_EQ(own_samples(16, 8, 8), 8u);    // the rest: 8 beside 8 inherited
    EXPECT_EQ(own_samples(16, 16, 8), 2u);   // 16 / 9, up: 2 beside 16
    EXPECT_EQ(own_samples(18, 100, 8), 2u);  // at the cap
    EXPECT_EQ(own_samples(27, 24, 8), 3u);
    EXPECT_EQ(own_samples(9, 100, 8), 1u);   // up to frames + 1 as before
    EXPECT_EQ(own_samples(16, 100, 0), 1u);  // no cap: no share
}

// The inherited value counts as at most `frames` times the pixel's own samples.
TEST(PixelHistory, TheInheritedCountIsCappedAtFramesTimesTheOwnSamples) {
    PixelHistory h;
    h.weight = {20, 4, 0};
    h.frames = 8;
    EXPECT_DOUBLE_EQ(h.counted(0, 1), 8.0);
    EXPECT_DOUBLE_EQ(h.counted(0, 2), 16.0);
    EXPECT_DOUBLE_EQ(h.counted(0, 3), 20.0);
    EXPECT_DOUBLE_EQ(h.counted(1, 1), 4.0);
    EXPECT_DOUBLE_EQ(h.counted(2, 1), 0.0);
    EXPECT_DOUBLE_EQ(h.counted(7, 1), 0.0);  // beyond the image
    h.frames = 0;
    EXPECT_DOUBLE_EQ(h.counted(0, 1), 20.0);
}

// Pixels 0 and 1 have two samples each of their own, means 1 and 3; pixel 2 none. Each
// neighbourhood is pixels 0 and 1 (mean 2, standard deviation 1), so an inherited value may
// lie within 2 +- 1.5. Pixel 0 inherits 3 at 2 samples: (2 * 1 + 2 * 3) / 4. Pixel 1 inherits
// 9 at 1, clipped to 3.5: (2 * 3 + 3.5) / 3. Pixel 2 has no sample of its own: what it
// inherited is not its image.
TEST(PixelHistory, TheImageWeighsOwnAndInheritedSamplesByTheirCountsAfterClipping) {
    Film film(3, 1);
    for (int s = 0; s < 2; ++s) {
        film.add_sample(0, s % 2 == 1);
        film.add(kCameraAov, 0, Vec3{1, 1, 1});
        film.add_sample(1, s % 2 == 1);
        film.add(kCameraAov, 1, Vec3{3, 3, 3});
    }
    std::vector<float> rgb = film.composite();
    PixelHistory h;
    h.rgb = {3, 3, 3, 9, 9, 9, 5, 5, 5};
    h.weight = {2, 1, 3};
    blend_history(rgb, film, h);
    EXPECT_FLOAT_EQ(rgb[0], 2.0f);
    EXPECT_FLOAT_EQ(rgb[3], (6.0f + 3.5f) / 3.0f);
    EXPECT_FLOAT_EQ(rgb[6], 0.0f);
    // The next frame inherits the blend at own + inherited samples; nothing where none was own.
    const PixelHistory next = history_of(rgb, film, &h);
    EXPECT_FLOAT_EQ(next.weight[0], 4.0f);
    EXPECT_FLOAT_EQ(next.weight[1], 3.0f);
    EXPECT_FLOAT_EQ(next.weight[2], 0.0f);
    EXPECT_FLOAT_EQ(next.rgb[0], 2.0f);
}

TEST(FrameReuse, OnlySurfacesWhoseLightHoldsAsTheEyeMovesInherit) {
    Scene scene;
    auto material = [&](const std::string& name, MaterialType type, double specularity, double roughness) {
        Material m;
        m.name = name, m.type = type, m.specularity = specularity, m.roughness = roughness;
        scene.materials.push_back(m);
        Shape s;
        s.material = name;
        scene.shapes.push_back(s);
    };
    material("matte", MaterialType::kPlastic, 0, 0);
    material("glossy", MaterialType::kPlastic, 0.05, 0.15);
    material("polished", MaterialType::kPlastic, 0.05, 0);
    material("mirror", MaterialType::kMirror, 0, 0);
    material("glass", MaterialType::kGlass, 0, 0);
    material("lamp", MaterialType::kLight, 0, 0);
    EXPECT_EQ(shapes_that_inherit(scene), (std::vector<char>{1, 1, 0, 0, 0, 1}));
}

// Pixel p blends its taps' values and counts by their weights, over the taps whose pixel had
// samples of its own; the count carried uncapped with the cap beside it. Nothing across a
// shape that may not inherit, nor where no tap matched.
TEST(FrameReuse, APixelBlendsItsTapsAndCarriesTheirCountAndTheCap) {
    PixelHistory before;
    before.rgb = {1, 1, 1, 2, 2, 2, 3, 3, 3};
    before.weight = {20, 4, 0};
    auto taps = [](std::vector<std::pair<int32_t, float>> list) {
        PixelTaps t;
        for (size_t i = 0; i < list.size(); ++i) t.pixel[i] = list[i].first, t.weight[i] = list[i].second;
        return t;
    };
    const std::vector<PixelTaps> from = {taps({{0, 0.25f}, {1, 0.75f}}), taps({{1, 0.5f}, {2, 0.5f}}), taps({})};
    const PixelHistory h = inherited_history(before, from, {0, 0, 0}, {1}, 8);
    EXPECT_FLOAT_EQ(h.rgb[0], 1.75f);
    EXPECT_FLOAT_EQ(h.weight[0], 8.0f);  // 0.25 * 20 + 0.75 * 4 = 8
    EXPECT_FLOAT_EQ(h.rgb[3], 2.0f);     // pixel 2 had no samples: pixel 1 alone
    EXPECT_FLOAT_EQ(h.weight[1], 4.0f);
    EXPECT_FLOAT_EQ(h.weight[2], 0.0f);  // no tap
    const PixelHistory capped = inherited_history(before, {taps({{0, 1}}), taps({}), taps({})}, {0, 0, 0}, {1}, 5);
    EXPECT_FLOAT_EQ(capped.weight[0], 20.0f);
    EXPECT_FLOAT_EQ(capped.frames, 5.0f);
    EXPECT_DOUBLE_EQ(capped.counted(0, 1), 5.0);
    // What the frame says it inherited: the count beside the fewest own samples that carry it
    // on (20 at a cap of 5 frames is ceil(20 / 6) = 4 own samples, 20 counted).
    EXPECT_DOUBLE_EQ(inherited_share(capped).second, 20.0);
    EXPECT_FLOAT_EQ(inherited_history(before, from, {1, 1, 1}, {1, 0}, 8).weight[0], 0.0f) << "shape 1 may not inherit";
}

}  // namespace
}  // namespace crex
