// Image metrics against values that can be worked out by hand (issue 8).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "runtime/metrics/metrics.h"

namespace crex::metrics {
namespace {

Image random_image(int w, int h, uint32_t seed, float lo = 0.1f, float hi = 0.9f) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(lo, hi);
    Image img{w, h, std::vector<float>(static_cast<size_t>(3 * w * h))};
    for (float& v : img.rgb) v = u(rng);
    return img;
}

TEST(Metrics, IdenticalImagesHaveNoError) {
    Image a = random_image(32, 24, 1);
    EXPECT_EQ(rmse(a, a), 0.0);
    EXPECT_EQ(relmse(a, a), 0.0);
    EXPECT_NEAR(*ssim(a, a), 1.0, 1e-12);
    auto f = flip_map(a, a);
    for (float v : f) EXPECT_EQ(v, 0.0f);
    EXPECT_EQ(perr(f), 0.0);
}

TEST(Metrics, KnownPerturbationsGiveKnownRmseAndRelmse) {
    Image r{4, 4, std::vector<float>(48, 0.5f)};
    Image t = r;
    for (float& v : t.rgb) v += 0.1f;  // everywhere +0.1
    EXPECT_NEAR(rmse(t, r), 0.1, 1e-6);
    EXPECT_NEAR(relmse(t, r), 0.01 / (0.25 + 0.01), 1e-6);
    Image one = r;
    one.rgb[5] += 2.0f;  // one channel of one pixel off by 2: sqrt(4 / 48)
    EXPECT_NEAR(rmse(one, r), std::sqrt(4.0 / 48), 1e-6);
    Image black{1, 1, {0, 0, 0}}, grey{1, 1, {0.1f, 0.1f, 0.1f}};
    EXPECT_NEAR(relmse(grey, black), 0.01 / 0.01, 1e-6);  // eps keeps a black reference finite
}

TEST(Metrics, SsimOfOneWindowMatchesTheFormulaWorkedByHand) {
    // An 11x11 image is exactly one window: SSIM is the formula on the Gaussian-weighted
    // means, variances and covariance of the two luminance images.
    Image x = random_image(11, 11, 2), y = random_image(11, 11, 3);
    double w1[11], total = 0;
    for (int i = 0; i < 11; ++i) total += w1[i] = std::exp(-0.5 * (i - 5) * (i - 5) / 2.25);
    double mx = 0, my = 0, xx = 0, yy = 0, xy = 0;
    for (int j = 0; j < 11; ++j)
        for (int i = 0; i < 11; ++i) {
            double wt = w1[i] * w1[j] / (total * total);
            size_t p = static_cast<size_t>(j * 11 + i);
            double lx = 0.2126 * x.rgb[3 * p] + 0.7152 * x.rgb[3 * p + 1] + 0.0722 * x.rgb[3 * p + 2];
            double ly = 0.2126 * y.rgb[3 * p] + 0.7152 * y.rgb[3 * p + 1] + 0.0722 * y.rgb[3 * p + 2];
            mx += wt * lx, my += wt * ly, xx += wt * lx * lx, yy += wt * ly * ly, xy += wt * lx * ly;
        }
    double c1 = 1e-4, c2 = 9e-4, vx = xx - mx * mx, vy = yy - my * my, cxy = xy - mx * my;
    double expect = (2 * mx * my + c1) * (2 * cxy + c2) / ((mx * mx + my * my + c1) * (vx + vy + c2));
    EXPECT_NEAR(*ssim(x, y), expect, 1e-9);
    // Two flat images a, b: (2ab + C1) / (a^2 + b^2 + C1).
    Image a{11, 11, std::vector<float>(363, 0.2f)}, b{11, 11, std::vector<float>(363, 0.6f)};
    EXPECT_NEAR(*ssim(a, b), (2 * 0.2 * 0.6 + c1) / (0.04 + 0.36 + c1), 1e-6);
    EXPECT_FALSE(ssim(Image{5, 5, std::vector<float>(75, 0.f)}, Image{5, 5, std::vector<float>(75, 0.f)}));
}

Image blurred(const Image& in, int r) {
    Image out = in;
    for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x)
            for (int c = 0; c < 3; ++c) {
                double s = 0;
                int n = 0;
                for (int dy = -r; dy <= r; ++dy)
                    for (int dx = -r; dx <= r; ++dx) {
                        int xx = std::clamp(x + dx, 0, in.width - 1), yy = std::clamp(y + dy, 0, in.height - 1);
                        s += in.rgb[3 * static_cast<size_t>(yy * in.width + xx) + static_cast<size_t>(c)], ++n;
                    }
                out.rgb[3 * static_cast<size_t>(y * in.width + x) + static_cast<size_t>(c)] = static_cast<float>(s / n);
            }
    return out;
}

TEST(Metrics, FlipIsSymmetricAndRanksABlurWorseThanAnImperceptibleChange) {
    // A sharp test pattern: checks of 4 pixels in two colours.
    Image ref{64, 64, std::vector<float>(64 * 64 * 3)};
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            bool on = ((x / 4) + (y / 4)) % 2 == 0;
            for (int c = 0; c < 3; ++c) ref.rgb[3 * static_cast<size_t>(y * 64 + x) + static_cast<size_t>(c)] = on ? 0.85f : (c == 2 ? 0.3f : 0.15f);
        }
    Image tiny = ref;
    for (float& v : tiny.rgb) v = std::min(1.0f, v + 1.0f / 255);  // one 8-bit step
    Image blur = blurred(ref, 2);
    auto ft = flip_map(tiny, ref), fb = flip_map(blur, ref), fb_swapped = flip_map(ref, blur);
    double mt = mean(ft), mb = mean(fb);
    EXPECT_LT(mt, 0.05);  // a uniform step of 1/255 is about 0.5 L*: FLIP ~0.03
    EXPECT_GT(mb, 0.1);
    EXPECT_GT(mb, 5 * mt);
    for (size_t i = 0; i < fb.size(); ++i) ASSERT_NEAR(fb[i], fb_swapped[i], 1e-6);
    for (float v : fb) ASSERT_TRUE(v >= 0 && v <= 1);
    EXPECT_GT(perr(fb), perr(ft));
    EXPECT_EQ(perr(ft), 0.0);
}

TEST(Metrics, DisplayViewIsStated) {
    Image lin{1, 1, {0.5f, 0.5f, 0.5f}};
    Image ldr = display_view(lin, {false, 1});
    EXPECT_NEAR(ldr.rgb[0], 0.7354, 1e-3);  // sRGB encoding of 0.5
    Image hdr = display_view(lin, {true, 2.0});
    EXPECT_NEAR(hdr.rgb[0], std::pow(0.5, 1 / 2.4) * 1.055 - 0.055, 1e-5);  // Reinhard(1) = 0.5, then sRGB
    EXPECT_NE(DisplayView({true, 2.0}).describe().find("exposure 2"), std::string::npos);
}

}  // namespace
}  // namespace crex::metrics

namespace crex::metrics {
namespace {

// A firefly is a pixel over 10x the median of its 3x3 neighbourhood: three spikes on a
// gradient are counted, a 5x bump, the gradient's own steps, a spike in the corner (its
// clamped neighbourhood) and dark noise below a hundredth of the mean are judged as such.
TEST(Metrics, FirefliesAreThePixelsFarOverTheirNeighbourhoodsMedian) {
    Image img{32, 24, std::vector<float>(32 * 24 * 3)};
    auto set = [&](int x, int y, float v) {
        for (int c = 0; c < 3; ++c) img.rgb[3 * static_cast<size_t>(y * 32 + x) + static_cast<size_t>(c)] = v;
    };
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 32; ++x) set(x, y, 0.5f + 0.02f * static_cast<float>(x));
    EXPECT_EQ(firefly_count(img), 0u);
    set(5, 5, 40), set(20, 10, 30), set(0, 0, 100);  // fireflies
    set(10, 20, 4);                                   // 5x its neighbours: not one
    EXPECT_EQ(firefly_count(img), 3u);
    for (int y = 12; y < 24; ++y)
        for (int x = 0; x < 8; ++x) set(x, y, 0);  // a black region with a faint speck
    set(3, 18, 0.002f);                             // under a hundredth of the mean: noise, not a firefly
    EXPECT_EQ(firefly_count(img), 3u);
    set(3, 18, 5);  // a bright speck in the black: a firefly
    EXPECT_EQ(firefly_count(img), 4u);
}

}  // namespace
}  // namespace crex::metrics
