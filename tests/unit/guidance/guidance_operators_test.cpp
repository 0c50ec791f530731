// The guidance operators on synthetic images whose answers are known (issue 6).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "stdlib/guidance/filters.h"
#include "stdlib/guidance/operators.h"

namespace crex::guidance {
namespace {

Raster flat_rgb(int w, int h, float v) { return Raster(w, h, 3, v); }

size_t argmax(const Raster& m) { return static_cast<size_t>(std::max_element(m.v.begin(), m.v.end()) - m.v.begin()); }

void expect_in_unit_interval(const Raster& m) {
    for (float x : m.v) {
        ASSERT_TRUE(std::isfinite(x));
        ASSERT_GE(x, 0.0f);
        ASSERT_LE(x, 1.0f);
    }
}

class SaliencyBlob : public ::testing::TestWithParam<std::tuple<int, int, int>> {};

TEST_P(SaliencyBlob, ASingleBrightBlobOnAFlatFieldIsTheMaximum) {
    auto [size, cx, cy] = GetParam();
    Raster img = flat_rgb(size, size, 0.3f);
    const int r = 3;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r)
                for (int c = 0; c < 3; ++c) img.at(x, y, c) = 0.9f;
    Raster s = saliency(img);
    ASSERT_EQ(s.width, size);
    expect_in_unit_interval(s);
    size_t m = argmax(s);
    int mx = static_cast<int>(m % static_cast<size_t>(size)), my = static_cast<int>(m / static_cast<size_t>(size));
    EXPECT_LE(std::hypot(mx - cx, my - cy), r + 1.0) << "maximum at " << mx << "," << my;
    EXPECT_FLOAT_EQ(s.v[m], 1.0f);
    // Far from the blob the field is not salient.
    int fx = cx < size / 2 ? size - 4 : 3, fy = cy < size / 2 ? size - 4 : 3;
    EXPECT_LT(s.at(fx, fy), 0.2f);
}

INSTANTIATE_TEST_SUITE_P(Positions, SaliencyBlob,
                         ::testing::Values(std::make_tuple(64, 20, 40), std::make_tuple(128, 90, 30), std::make_tuple(96, 48, 48)));

TEST(Saliency, AFlatImageHasNoSalientPixelAndAColouredBlobWins) {
    Raster flat = saliency(flat_rgb(64, 64, 0.5f));
    for (float x : flat.v) EXPECT_EQ(x, 0.0f);
    // Equal luminance, different hue: only the colour channel can find it.
    Raster img = flat_rgb(64, 64, 0.5f);
    for (int y = 40; y < 46; ++y)
        for (int x = 10; x < 16; ++x) img.at(x, y, 0) = 0.9f, img.at(x, y, 1) = 0.35f, img.at(x, y, 2) = 0.35f;
    Raster s = saliency(img);
    size_t m = argmax(s);
    EXPECT_NEAR(static_cast<double>(m % 64), 12.5, 4);
    EXPECT_NEAR(static_cast<double>(m / 64), 42.5, 4);
}

TEST(Edges, AStepEdgePeaksOnTheEdge) {
    Raster img = flat_rgb(40, 20, 0.1f);
    for (int y = 0; y < 20; ++y)
        for (int x = 20; x < 40; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = 0.8f;
    Raster e = edges(img);
    expect_in_unit_interval(e);
    for (int y = 0; y < 20; ++y) {
        int best = 0;
        for (int x = 0; x < 40; ++x)
            if (e.at(x, y) > e.at(best, y)) best = x;
        EXPECT_TRUE(best == 19 || best == 20) << "row " << y << " peaks at " << best;
        EXPECT_FLOAT_EQ(e.at(best, y), 1.0f);
        EXPECT_EQ(e.at(5, y), 0.0f);  // flat: no edge
        EXPECT_EQ(e.at(34, y), 0.0f);
        for (int x = 20; x + 1 < 30; ++x) EXPECT_GE(e.at(x, y), e.at(x + 1, y));  // falls away from it
    }
}

TEST(RadianceDifference, IsLargestWhereNeighboursDisagree) {
    Raster img = flat_rgb(16, 16, 0.2f);
    for (int c = 0; c < 3; ++c) img.at(8, 8, c) = 0.9f;
    Raster d = radiance_difference(img);
    EXPECT_FLOAT_EQ(d.at(8, 8), 1.0f);
    EXPECT_FLOAT_EQ(d.at(7, 8), 1.0f);
    EXPECT_EQ(d.at(2, 2), 0.0f);
    EXPECT_EQ(d.at(7, 7), 0.0f);  // diagonal neighbours are not compared
}

TEST(DistanceTransform, MatchesBruteForce) {
    std::mt19937 rng(7);
    const int w = 37, h = 23;
    std::vector<bool> f(w * h);
    for (size_t i = 0; i < f.size(); ++i) f[i] = rng() % 50 == 0;
    f[5] = true;
    auto d2 = squared_distance_transform(f, w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double best = 1e30;
            for (int q = 0; q < w * h; ++q)
                if (f[static_cast<size_t>(q)]) best = std::min(best, double((q % w - x) * (q % w - x) + (q / w - y) * (q / w - y)));
            ASSERT_EQ(d2[static_cast<size_t>(y * w + x)], best) << x << "," << y;
        }
}

TEST(TaskMap, OneOnTheObjectFallingWithVisualAngleToTheBaseAtTheRadius) {
    const int w = 200, h = 50;
    std::vector<bool> object(w * h, false);
    for (int y = 20; y < 30; ++y)
        for (int x = 40; x < 50; ++x) object[static_cast<size_t>(y * w + x)] = true;
    ViewGeometry view{w, h, 1.0};
    const double fovea = 5 * std::numbers::pi / 180;
    const double base = 0.1;
    Raster m = task_map({object}, {1.0}, view, fovea, base);
    expect_in_unit_interval(m);
    for (int y = 20; y < 30; ++y)
        for (int x = 40; x < 50; ++x) EXPECT_FLOAT_EQ(m.at(x, y), 1.0f);
    // Along row 25 to the right of the object: monotone, base at the foveal radius.
    double radius_px = std::tan(fovea) * view.view_distance * w;  // 17.5 pixels
    for (int x = 49; x + 1 < w; ++x) EXPECT_GE(m.at(x, 25), m.at(x + 1, 25));
    int inside = 49 + static_cast<int>(std::floor(radius_px)) - 1, outside = 49 + static_cast<int>(std::ceil(radius_px));
    EXPECT_GT(m.at(inside, 25), base + 1e-3);
    EXPECT_FLOAT_EQ(m.at(outside, 25), static_cast<float>(base));
    EXPECT_FLOAT_EQ(m.at(199, 0), static_cast<float>(base));
    // Halfway in angle, halfway in value.
    double half_px = std::tan(fovea / 2) * w;
    int hx = 49 + static_cast<int>(std::lround(half_px));
    double expect = 1 + (base - 1) * view.visual_angle(hx - 49) / fovea;
    EXPECT_NEAR(m.at(hx, 25), expect, 1e-5);
}

TEST(QBuffer, OverlappingRequestsNeverExceedTheHighestRequest) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> q(0, 1);
    const size_t n = 64;
    QBuffer buffer(n);
    std::vector<float> granted(n, 0), highest(n, 0);
    for (int k = 0; k < 5000; ++k) {
        size_t p = rng() % n;
        float want = q(rng);
        granted[p] += buffer.request(p, want);
        highest[p] = std::max(highest[p], want);
    }
    for (size_t p = 0; p < n; ++p) {
        EXPECT_NEAR(granted[p], highest[p], 1e-5);
        EXPECT_NEAR(buffer.qualities()[p], highest[p], 1e-5);
    }
    buffer.request(0, 2.0f);  // clamped to 1
    EXPECT_EQ(buffer.qualities()[0], 1.0f);
    EXPECT_EQ(buffer.request(0, 1.0f), 0.0f);
}

TEST(DistractorMap, OverlappingGradientsShootNoPixelTwice) {
    const int w = 64, h = 32;
    std::vector<bool> seen(w * h, false);
    for (int y = 10; y < 20; ++y)
        for (int x = 20; x < 26; ++x) seen[static_cast<size_t>(y * w + x)] = true;  // a detected object: many overlapping discs
    ViewGeometry view{w, h, 1.0};
    std::vector<float> granted;
    Raster m = distractor_map(seen, view, 8 * std::numbers::pi / 180, &granted);
    expect_in_unit_interval(m);
    for (size_t p = 0; p < m.v.size(); ++p) {
        EXPECT_LE(granted[p], m.v[p] + 1e-6f);
        EXPECT_NEAR(granted[p], m.v[p], 1e-5);
        if (seen[p]) {
            EXPECT_FLOAT_EQ(m.v[p], 1.0f);
        }
    }
    EXPECT_EQ(m.at(63, 0), 0.0f);
}

TEST(Importance, MatchesTheFormulaForEachOperator) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0, 1);
    Raster t(8, 8), s(8, 8);
    for (auto& x : t.v) x = u(rng);
    for (auto& x : s.v) x = u(rng);
    const double wt = 0.6, ws = 0.4;
    Raster plus = importance({&t, &s}, {wt, ws}, "+"), mx = importance({&t, &s}, {wt, ws}, "max"),
           prod = importance({&t, &s}, {wt, ws}, "*");
    for (size_t i = 0; i < t.v.size(); ++i) {
        EXPECT_NEAR(plus.v[i], std::min(1.0, wt * t.v[i] + ws * s.v[i]), 1e-6);
        EXPECT_NEAR(mx.v[i], std::max(wt * t.v[i], ws * s.v[i]), 1e-6);
        EXPECT_NEAR(prod.v[i], wt * t.v[i] * ws * s.v[i], 1e-6);
    }
    Raster over = importance({&t, &s}, {1.0, 1.0}, "+");  // clamped
    for (float x : over.v) EXPECT_LE(x, 1.0f);
}

TEST(Importance, AMapZeroEverywhereHandsItsWeightToTheOthersInASum) {
    // cbtcr's importance(task 0.5, sal 0.5, op "+") on a scene with nothing tagged: saliency
    // alone, so its `{TTMRSGD}2` reaches D (at half weight it never passed 4/7).
    Raster task(4, 4), sal(4, 4);
    for (size_t i = 0; i < sal.v.size(); ++i) sal.v[i] = static_cast<float>(i) / 15.0f;
    Raster plus = importance({&task, &sal}, {0.5, 0.5}, "+");
    for (size_t i = 0; i < sal.v.size(); ++i) EXPECT_NEAR(plus.v[i], sal.v[i], 1e-6) << i;
    // Three maps, one empty: the other two share the total weight in their own proportion.
    Raster other(4, 4, 1, 0.25f);
    Raster three = importance({&task, &sal, &other}, {0.2, 0.3, 0.1}, "+");
    for (size_t i = 0; i < sal.v.size(); ++i) EXPECT_NEAR(three.v[i], std::min(1.0, 1.5 * (0.3 * sal.v[i] + 0.1 * 0.25)), 1e-6) << i;
    // Products and maxima are as written: a zero map there means what it says.
    Raster prod = importance({&task, &sal}, {0.5, 0.5}, "*");
    for (float x : prod.v) EXPECT_EQ(x, 0.0f);
    Raster mx = importance({&task, &sal}, {0.5, 0.5}, "max");
    for (size_t i = 0; i < sal.v.size(); ++i) EXPECT_NEAR(mx.v[i], 0.5 * sal.v[i], 1e-6);
    // Every map empty: zero, not a division by zero.
    Raster none = importance({&task, &task}, {0.5, 0.5}, "+");
    for (float x : none.v) EXPECT_EQ(x, 0.0f);
}

TEST(Utilities, ConstantThresholdBlurAndNormalise) {
    Raster c = constant_map(4, 3, 0.25);
    for (float x : c.v) EXPECT_EQ(x, 0.25f);
    EXPECT_EQ(constant_map(2, 2, 7).v[0], 1.0f);  // maps stay in [0, 1]
    Raster m(5, 1);
    m.v = {0.1f, 0.5f, 0.49f, 0.9f, 0.0f};
    Raster th = threshold(m, 0.5);
    EXPECT_EQ(th.v, (std::vector<float>{0, 1, 0, 1, 0}));
    Raster b = gaussian_blur(Raster(9, 9, 1, 0.5f), 2.0);  // blur keeps a constant
    for (float x : b.v) EXPECT_NEAR(x, 0.5f, 1e-6);
    normalise_max(m);
    EXPECT_FLOAT_EQ(m.v[3], 1.0f);
    EXPECT_FLOAT_EQ(m.v[1], 0.5f / 0.9f);
    Raster nan(2, 1);
    nan.v = {NAN, 0.5f};
    normalise_max(nan);
    EXPECT_EQ(nan.v[0], 0.0f);
    EXPECT_EQ(nan.v[1], 1.0f);
}

}  // namespace
}  // namespace crex::guidance
