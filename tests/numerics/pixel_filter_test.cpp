// The Gaussian pixel filter by filter importance sampling (issue 4).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "runtime/render/render_scene.h"
#include "runtime/scene/load_scene.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

TEST(GaussianFilter, OffsetsFollowTheTruncatedGaussian) {
    // u on a fine grid: the mapped offsets' moments are the truncated Gaussian's.
    const int n = 100000;
    double sum = 0, sum2 = 0, outside = 0, lo = 0, hi = 0;
    for (int i = 0; i < n; ++i) {
        double x = gaussian_filter_offset((i + 0.5) / n);
        sum += x, sum2 += x * x;
        outside += std::fabs(x) > 0.5;
        lo = std::min(lo, x), hi = std::max(hi, x);
    }
    double mean = sum / n, var = sum2 / n - mean * mean;
    EXPECT_NEAR(mean, 0.0, 1e-4);
    EXPECT_NEAR(var, 0.25 * (1 - 6 * 0.0044318 / 0.9973002), 5e-4);  // sigma^2 (1 - 2 r phi(r) / (2 Phi(r) - 1)), r = 3
    EXPECT_NEAR(outside / n, (0.3173105 - 0.0026998) / 0.9973002, 2e-3);
    EXPECT_GE(lo, -1.5);
    EXPECT_LE(hi, 1.5);
}

TEST(GaussianFilter, AnEdgeIsSpreadLikeTheFilterAndTheBoxKeepsItSharp) {
    // A glowing half-plane fills the left half of the view; the edge falls between columns 15
    // and 16 of a 32-pixel image.
    Scene s;
    Material glow = testing::make_material("glow", MaterialType::kGlow, {1, 1, 1});
    s.materials.push_back(glow);
    s.shapes.push_back(build::quad("glow", {-50, -50, 0}, {0, -50, 0}, {0, 50, 0}, {-50, 50, 0}));
    s.camera.position = {0, 0, 5};
    s.camera.direction = {0, 0, -1};
    auto run = [&](PixelFilter f) {
        RunSettings o;
        o.width = o.height = 32;
        o.spp = 256;
        o.filter = f;
        return render(s, testing::lower_or_die(""), o).image();
    };
    auto box = run(PixelFilter::kBox), gauss = run(PixelFilter::kGaussian);
    auto at = [](const std::vector<float>& img, int x) { return img[3 * (16 * 32 + x)]; };
    EXPECT_EQ(at(box, 16), 0.0f);
    EXPECT_EQ(at(box, 15), 1.0f);
    // P(offset < -0.5) of the truncated Gaussian: 0.1577; the sample mean of 256 Halton points.
    EXPECT_NEAR(at(gauss, 16), 0.1577, 0.02);
    EXPECT_NEAR(at(gauss, 15), 1 - 0.1577, 0.02);
    EXPECT_NEAR(at(gauss, 17), 0.0013, 0.01);  // P(offset < -1.5 + ...) is nearly 0
    EXPECT_EQ(at(gauss, 20), 0.0f);
    EXPECT_EQ(at(gauss, 10), 1.0f);
}

TEST(GaussianFilter, RaisingTheSampleCountStillContinuesTheSequence) {
    Scene s = *builtin_scene("cornell");
    RunSettings one;
    one.width = one.height = 16, one.spp = 1, one.filter = PixelFilter::kGaussian;
    RunSettings more = one;
    more.first_sample = 1, more.spp = 3;
    RunSettings all = one;
    all.spp = 4;
    auto p = testing::lower_or_die("(TTMRSGD)*");
    auto a = render(s, p, one), b = render(s, p, more), c = render(s, p, all);
    auto ia = a.image(), ib = b.image(), ic = c.image();
    for (size_t i = 0; i < ic.size(); ++i) EXPECT_NEAR((ia[i] * 1 + ib[i] * 3) / 4, ic[i], 1e-4 * std::max(1.0f, ic[i]));
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(Camera, PixelsAreSquareWhateverTheAspect) {
    // --size 128x64 on builtin:cornell (40 x 40 degrees) squashed its spheres into ellipses.
    // A pixel's step right and its step down subtend the same angle at the centre.
    for (auto [w, h] : {std::pair{128, 64}, std::pair{64, 128}, std::pair{100, 100}}) {
        Scene s = *builtin_scene("cornell");
        CameraRays cam(s.camera, w, h, {0, 0, 0});
        Vec3 o, centre, right, down;
        cam.generate(w / 2.0, h / 2.0, o, centre);
        cam.generate(w / 2.0 + 1, h / 2.0, o, right);
        cam.generate(w / 2.0, h / 2.0 + 1, o, down);
        double across = std::acos(std::clamp(dot(centre, right), -1.0, 1.0)), along = std::acos(std::clamp(dot(centre, down), -1.0, 1.0));
        EXPECT_NEAR(across / along, 1.0, 1e-9) << w << "x" << h;
        // The view never exceeds the scene's 40 degrees either way.
        Vec3 left_edge, top_edge;
        cam.generate(0, h / 2.0, o, left_edge);
        cam.generate(w / 2.0, 0, o, top_edge);
        EXPECT_LE(2 * std::acos(dot(centre, left_edge)) * 180 / kPi, 40 + 1e-9);
        EXPECT_LE(2 * std::acos(dot(centre, top_edge)) * 180 / kPi, 40 + 1e-9);
    }
}

}  // namespace
}  // namespace crex
