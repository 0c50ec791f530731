// capict's interpolation (runtime/pipeline/component_subsample.h) on a film filled by hand:
// what a pixel that did not run a component gets from the corners that did.
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/pipeline/component_subsample.h"

namespace crex {
namespace {

constexpr int kW = 9, kH = 9;
constexpr size_t kD = static_cast<size_t>(Component::kD), kR = static_cast<size_t>(Component::kR);

uint32_t at(int x, int y) { return static_cast<uint32_t>(y * kW + x); }

// One sample per pixel: component c's first bounce has throughput `albedo(x)` everywhere, and
// at the corners of a spacing-8 grid (the four image corners) it ran and found albedo x L(x).
template <class Albedo, class Light>
Film film_with(size_t c, Albedo albedo, Light light) {
    Film film(kW, kH);
    film.track_branches(static_cast<uint8_t>(1u << c));
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const uint32_t p = at(x, y);
            film.add_sample(p, false);
            const bool corner = (x == 0 || x == kW - 1) && (y == 0 || y == kH - 1);
            const Vec3 beta = Vec3{1, 1, 1} * albedo(x);
            film.add_first_bounce(c, p, beta, corner);
            if (corner) film.add(aov_of(static_cast<Component>(c)), p, beta * light(x), static_cast<uint8_t>((1 + c) << kRayBranchShift));
        }
    return film;
}

ComponentSubsampling grid_of(Component c, const Film& film) {
    ComponentSubsampling s;
    s.build(c, kW, kH, std::vector<double>(kW * kH, 8.0), film);
    return s;
}

TEST(ComponentSubsample, ASharpComponentIsTheBilinearInterpolationOfItsCornersLight) {
    // R (glass reflection) takes its square's four corners: a light linear in x comes back exactly.
    auto light = [](int x) { return 1.0 + 0.25 * x; };
    Film film = film_with(kR, [](int) { return 0.5; }, light);
    ComponentSubsampling s = grid_of(Component::kR, film);
    ASSERT_EQ(s.grid(Component::kR)->rendered_count(), 4u);
    std::vector<double> add = s.stand_ins(film);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const uint32_t p = at(x, y);
            const double have = film.branch_sum(kR, p).y, want = 0.5 * light(x);
            EXPECT_NEAR(have + add[3 * p + 1], want, 1e-9) << x << "," << y;
        }
}

TEST(ComponentSubsample, TheHitsOwnMaterialMultipliesTheInterpolatedLight) {
    // An albedo edge down the middle: the light is the same everywhere, so each pixel gets its
    // own albedo times it, sharp, however wide the diffuse tent is (an albedo interpolated
    // between the corners would blur the edge to 0.5 in the middle).
    auto albedo = [](int x) { return x < 4 ? 0.8 : 0.2; };
    Film film = film_with(kD, albedo, [](int) { return 2.0; });
    ComponentSubsampling s = grid_of(Component::kD, film);
    std::vector<double> add = s.stand_ins(film);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const uint32_t p = at(x, y);
            EXPECT_NEAR(film.branch_sum(kD, p).x + add[3 * p], albedo(x) * 2.0, 1e-9) << x << "," << y;
        }
    // Only the pixels that did not run D change ...
    EXPECT_EQ(add[3 * at(0, 0)], 0.0);
    // ... and the component's image takes the change: the AOVs still add up to the image.
    EXPECT_EQ(s.stand_ins(film, Component::kR), std::vector<double>(3 * kW * kH, 0.0));
}

TEST(ComponentSubsample, LightIsNotTakenAcrossASilhouette) {
    // The right half of the image is another object, nearer: its pixels take light from the
    // right corners only, and the left half from the left ones.
    Film film = film_with(kR, [](int) { return 1.0; }, [](int x) { return x < 5 ? 1.0 : 3.0; });
    PixelProbe probe;
    probe.width = kW, probe.height = kH;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            probe.shape.push_back(x < 5 ? 0 : 1);
            probe.distance.push_back(x < 5 ? 10.0f : 4.0f);
            probe.normal.push_back({0, 0, 1});
            probe.detected.push_back(probe.shape.back());
        }
    ComponentSubsampling s;
    s.set_surfaces(probe);
    s.build(Component::kR, kW, kH, std::vector<double>(kW * kH, 8.0), film);
    std::vector<double> add = s.stand_ins(film);
    for (int y = 1; y < kH - 1; ++y)
        for (int x = 1; x < kW - 1; ++x) {
            const uint32_t p = at(x, y);
            EXPECT_NEAR(film.branch_sum(kR, p).z + add[3 * p + 2], x < 5 ? 1.0 : 3.0, 1e-9) << x << "," << y;
        }
}

TEST(ComponentSubsample, APixelWithNoCornerOnItsSurfaceBecomesACorner) {
    // The preview ran R in the middle pixel only (a small glossy object): no corner of the
    // spacing-8 square has R, so the grid splits until that pixel is rendered itself.
    Film film(kW, kH);
    film.track_branches(1u << kR);
    film.add_sample(at(4, 4), false);
    film.add_first_bounce(kR, at(4, 4), {1, 1, 1}, true);
    ComponentSubsampling s = grid_of(Component::kR, film);
    EXPECT_TRUE(s.grid(Component::kR)->rendered(at(4, 4)));
    EXPECT_GT(s.grid(Component::kR)->rendered_count(), 4u);
    // The executor's gate: R's first bounces run at the corners only; other components everywhere.
    std::vector<uint8_t> runs = s.first_bounce_runs(kW * kH);
    EXPECT_EQ(runs[at(4, 4)], 0x3f);
    EXPECT_EQ(runs[at(1, 0)] & (1u << kR), 0u);
    EXPECT_EQ(runs[at(1, 0)] | (1u << kR), 0x3f);
}

TEST(ComponentSubsample, RefinementSplitsTheSquaresWhoseCornersDiffer) {
    // 17 pixels wide, spacing 8: two squares side by side. The left one's corners see the same
    // light, the right one's differ by 3x: only the right square splits, once per call.
    constexpr int w = 17, h = 9;
    Film film(w, h);
    film.track_branches(1u << kR);
    auto light = [](int x) { return x >= 16 ? 3.0 : 1.0; };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const uint32_t p = static_cast<uint32_t>(y * w + x);
            film.add_sample(p, false);
            const bool corner = x % 8 == 0 && y % 8 == 0;
            film.add_first_bounce(kR, p, {1, 1, 1}, corner);
            if (corner) film.add(aov_of(Component::kR), p, Vec3{1, 1, 1} * light(x), static_cast<uint8_t>((1 + kR) << kRayBranchShift));
        }
    ComponentSubsampling s;
    s.build(Component::kR, w, h, std::vector<double>(w * h, 8.0), film);
    ASSERT_EQ(s.grid(Component::kR)->rendered_count(), 6u);
    EXPECT_TRUE(s.refine(Component::kR, 10.0, film).empty());  // 3x is within a threshold of 10 means
    std::vector<uint8_t> added = s.refine(Component::kR, 0.5, film);
    ASSERT_FALSE(added.empty());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool right_square_midpoint = x >= 8 && x % 4 == 0 && y % 4 == 0 && !(x % 8 == 0 && y % 8 == 0);
            EXPECT_EQ(added[static_cast<size_t>(y * w + x)], right_square_midpoint ? 1 : 0) << x << "," << y;
        }
}

TEST(ComponentSubsample, CornersThatDifferOnlyByTheirNoiseDoNotSplit) {
    // Two corners of light 1 and 3 each from two samples: when each corner's two samples agree
    // the difference is light and the square splits; when each corner's samples are 0 and twice
    // its light (standard error = its light) the difference is within their noise.
    for (bool noisy : {false, true}) {
        constexpr int w = 9, h = 9;
        Film film(w, h);
        film.track_branches(1u << kR);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const uint32_t p = static_cast<uint32_t>(y * w + x);
                const bool corner = (x == 0 || x == w - 1) && (y == 0 || y == h - 1);
                const double light = x == 0 ? 1.0 : 3.0;
                for (bool odd : {false, true}) {
                    film.add_sample(p, odd);
                    film.add_first_bounce(kR, p, {1, 1, 1}, corner, false, odd);
                    const double found = noisy ? (odd ? 2 * light : 0.0) : light;
                    const uint8_t flags = static_cast<uint8_t>(((1 + kR) << kRayBranchShift) | (odd ? kRayOddSample : 0));
                    if (corner) film.add(aov_of(Component::kR), p, Vec3{1, 1, 1} * found, flags);
                }
            }
        ComponentSubsampling s;
        s.build(Component::kR, w, h, std::vector<double>(w * h, 8.0), film);
        EXPECT_EQ(s.refine(Component::kR, 0.1, film).empty(), noisy) << (noisy ? "noisy" : "certain");
    }
}

}  // namespace
}  // namespace crex
