// The fast guidance operators (issue 34) against the textbook per-pixel loops they replaced,
// kept here as the reference: filters, percentiles, distance maps and edges must agree to
// float rounding; saliency agrees exactly where it works at image size (up to 64 pixels) and
// closely where it works on the pyramid's finer level.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "stdlib/guidance/filters.h"
#include "stdlib/guidance/operators.h"

namespace crex::guidance {
namespace {

namespace ref {

Raster gaussian_blur(const Raster& in, double sigma) {
    int r = std::max(1, static_cast<int>(std::ceil(3 * sigma)));
    std::vector<float> k(static_cast<size_t>(2 * r + 1));
    double sum = 0;
    for (int i = -r; i <= r; ++i) sum += k[static_cast<size_t>(i + r)] = static_cast<float>(std::exp(-0.5 * i * i / (sigma * sigma)));
    for (float& x : k) x = static_cast<float>(x / sum);
    Raster tmp(in.width, in.height, in.channels), out(in.width, in.height, in.channels);
    for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x)
            for (int c = 0; c < in.channels; ++c) {
                float s = 0;
                for (int i = -r; i <= r; ++i) s += k[static_cast<size_t>(i + r)] * in.clamped(x + i, y, c);
                tmp.at(x, y, c) = s;
            }
    for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x)
            for (int c = 0; c < in.channels; ++c) {
                float s = 0;
                for (int i = -r; i <= r; ++i) s += k[static_cast<size_t>(i + r)] * tmp.clamped(x, y + i, c);
                out.at(x, y, c) = s;
            }
    return out;
}

std::vector<Raster> gaussian_pyramid(const Raster& in, int max_levels) {
    std::vector<Raster> levels{in};
    while (static_cast<int>(levels.size()) < max_levels && levels.back().width > 1 && levels.back().height > 1) {
        Raster b = ref::gaussian_blur(levels.back(), 1.0);
        Raster half((b.width + 1) / 2, (b.height + 1) / 2, b.channels);
        for (int y = 0; y < half.height; ++y)
            for (int x = 0; x < half.width; ++x)
                for (int c = 0; c < b.channels; ++c) half.at(x, y, c) = b.clamped(2 * x, 2 * y, c);
        levels.push_back(std::move(half));
    }
    return levels;
}

Raster resize_bilinear(const Raster& in, int w, int h) {
    Raster out(w, h, in.channels);
    double sx = static_cast<double>(in.width) / w, sy = static_cast<double>(in.height) / h;
    for (int y = 0; y < h; ++y) {
        double fy = (y + 0.5) * sy - 0.5;
        int y0 = static_cast<int>(std::floor(fy));
        float ty = static_cast<float>(fy - y0);
        for (int x = 0; x < w; ++x) {
            double fx = (x + 0.5) * sx - 0.5;
            int x0 = static_cast<int>(std::floor(fx));
            float tx = static_cast<float>(fx - x0);
            for (int c = 0; c < in.channels; ++c) {
                float a = in.clamped(x0, y0, c) * (1 - tx) + in.clamped(x0 + 1, y0, c) * tx;
                float b = in.clamped(x0, y0 + 1, c) * (1 - tx) + in.clamped(x0 + 1, y0 + 1, c) * tx;
                out.at(x, y, c) = a * (1 - ty) + b * ty;
            }
        }
    }
    return out;
}

void sobel(const Raster& in, Raster& gx, Raster& gy) {
    gx = Raster(in.width, in.height, 1);
    gy = Raster(in.width, in.height, 1);
    for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x) {
            auto p = [&](int dx, int dy) { return in.clamped(x + dx, y + dy, 0); };
            gx.at(x, y) = (p(1, -1) + 2 * p(1, 0) + p(1, 1)) - (p(-1, -1) + 2 * p(-1, 0) + p(-1, 1));
            gy.at(x, y) = (p(-1, 1) + 2 * p(0, 1) + p(1, 1)) - (p(-1, -1) + 2 * p(0, -1) + p(1, -1));
        }
}

// Itti-Koch with every feature map at image size: the implementation before issue 34.
Raster itti_normalise(Raster m) {
    float mx = 0;
    for (float x : m.v) mx = std::max(mx, std::isfinite(x) ? x : 0.0f);
    if (mx < 1e-4f) return Raster(m.width, m.height, 1);
    normalise_max(m);
    double sum = 0;
    int count = 0;
    for (int y = 0; y < m.height; ++y)
        for (int x = 0; x < m.width; ++x) {
            float c = m.at(x, y);
            if (c <= 0 || c >= 1) continue;
            bool peak = true;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    if ((dx || dy) && m.clamped(x + dx, y + dy) > c) peak = false;
            if (peak) sum += c, ++count;
        }
    double mean = count ? sum / count : 0;
    float w = static_cast<float>((1 - mean) * (1 - mean));
    for (float& x : m.v) x *= w;
    return m;
}

void add_to(Raster& acc, const Raster& m) {
    for (size_t i = 0; i < acc.v.size(); ++i) acc.v[i] += m.v[i];
}

Raster centre_surround(const std::vector<Raster>& pyr, const std::vector<std::pair<int, int>>& pairs, int w, int h) {
    Raster acc(w, h, 1);
    for (auto [c, s] : pairs) {
        Raster centre = ref::resize_bilinear(pyr[static_cast<size_t>(c)], w, h), surround = ref::resize_bilinear(pyr[static_cast<size_t>(s)], w, h);
        Raster diff(w, h, 1);
        for (size_t i = 0; i < diff.v.size(); ++i) diff.v[i] = std::fabs(centre.v[i] - surround.v[i]);
        ref::add_to(acc, ref::itti_normalise(std::move(diff)));
    }
    return acc;
}

Raster saliency(const Raster& rgb) {
    const int w = rgb.width, h = rgb.height;
    Raster intensity(w, h), rg(w, h), by(w, h);
    for (size_t i = 0; i < intensity.pixels(); ++i) {
        const float* p = &rgb.v[i * 3];
        float r = p[0], g = p[1], b = p[2];
        float in = (r + g + b) / 3;
        intensity.v[i] = in;
        float R = r - (g + b) / 2, G = g - (r + b) / 2, B = b - (r + g) / 2, Y = (r + g) / 2 - std::fabs(r - g) / 2 - b;
        float norm = in > 0.1f ? 1.0f / in : 0.0f;
        rg.v[i] = (std::max(R, 0.0f) - std::max(G, 0.0f)) * norm;
        by.v[i] = (std::max(B, 0.0f) - std::max(Y, 0.0f)) * norm;
    }
    auto pi = ref::gaussian_pyramid(intensity, 9), prg = ref::gaussian_pyramid(rg, 9), pby = ref::gaussian_pyramid(by, 9);
    int shift = std::max(0, 9 - static_cast<int>(pi.size()));
    std::vector<std::pair<int, int>> pairs;
    for (int c = 2; c <= 4; ++c)
        for (int d = 3; d <= 4; ++d)
            if (c - shift >= 0 && c + d - shift < static_cast<int>(pi.size())) pairs.push_back({c - shift, c + d - shift});
    if (pairs.empty()) pairs.push_back({0, static_cast<int>(pi.size()) - 1});  // tiny images: one pair
    Raster ibar = ref::centre_surround(pi, pairs, w, h);
    Raster cbar = ref::centre_surround(prg, pairs, w, h);
    ref::add_to(cbar, ref::centre_surround(pby, pairs, w, h));
    Raster obar(w, h, 1);
    for (int theta = 0; theta < 4; ++theta) {
        std::vector<Raster> po;
        for (const auto& level : pi) {
            Raster gx, gy;
            ref::sobel(level, gx, gy);
            Raster o(level.width, level.height, 1);
            for (size_t i = 0; i < o.v.size(); ++i) {
                float a = gx.v[i], b = gy.v[i];
                o.v[i] = std::fabs(theta == 0 ? a : theta == 1 ? (a + b) * 0.70710678f : theta == 2 ? b : (a - b) * 0.70710678f);
            }
            po.push_back(std::move(o));
        }
        ref::add_to(obar, ref::itti_normalise(ref::centre_surround(po, pairs, w, h)));
    }
    Raster s(w, h, 1);
    ref::add_to(s, ref::itti_normalise(std::move(ibar)));
    ref::add_to(s, ref::itti_normalise(std::move(cbar)));
    ref::add_to(s, ref::itti_normalise(std::move(obar)));
    normalise_max(s);
    return s;
}

float percentile_scale(Raster& m, size_t k) {
    std::vector<float> sorted = m.v;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
    return sorted[k];
}

Raster edges(const Raster& display) {
    Raster y = ref::gaussian_blur(luminance(display), 1.0), gx, gy;
    ref::sobel(y, gx, gy);
    Raster m(y.width, y.height, 1);
    for (size_t i = 0; i < m.v.size(); ++i) m.v[i] = std::hypot(gx.v[i], gy.v[i]);
    float scale = ref::percentile_scale(m, (m.v.size() - 1) * 99 / 100);
    for (float& x : m.v) x /= scale;
    clamp01(m);
    return m;
}

Raster task_map(const std::vector<std::vector<bool>>& covered, const std::vector<double>& value, const ViewGeometry& view,
                double fovea, double base) {
    Raster m(view.width, view.height, 1, static_cast<float>(base));
    for (size_t s = 0; s < covered.size(); ++s) {
        for (int y = 0; y < view.height; ++y)
            for (int x = 0; x < view.width; ++x) {
                double d2 = 1e30;  // brute force: the nearest covered pixel
                for (int q = 0; q < view.width * view.height; ++q)
                    if (covered[s][static_cast<size_t>(q)]) {
                        double dx = q % view.width - x, dy = q / view.width - y;
                        d2 = std::min(d2, dx * dx + dy * dy);
                    }
                double angle = view.visual_angle(std::sqrt(d2));
                double t = fovea > 0 ? std::clamp(angle / fovea, 0.0, 1.0) : (d2 > 0 ? 1.0 : 0.0);
                float& out = m.v[static_cast<size_t>(y * view.width + x)];
                out = std::max(out, static_cast<float>(value[s] + (base - value[s]) * t));
            }
    }
    return m;
}

// Every detectable pixel's foveal disc requested through a q-buffer, as thesis 4.5 has it.
Raster distractor_map(const std::vector<bool>& detectable, const ViewGeometry& view, double fovea, std::vector<float>& granted) {
    const int w = view.width, h = view.height;
    QBuffer qbuffer(static_cast<size_t>(w * h));
    granted.assign(static_cast<size_t>(w * h), 0.0f);
    int r = static_cast<int>(std::ceil(std::tan(std::max(fovea, 0.0)) * view.view_distance * w));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (!detectable[static_cast<size_t>(y * w + x)]) continue;
            for (int dy = -r; dy <= r; ++dy)
                for (int dx = -r; dx <= r; ++dx) {
                    int qx = x + dx, qy = y + dy;
                    if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
                    double quality = fovea > 0 ? 1 - view.visual_angle(std::hypot(dx, dy)) / fovea : (dx == 0 && dy == 0 ? 1 : 0);
                    if (quality <= 0) continue;
                    size_t p = static_cast<size_t>(qy * w + qx);
                    granted[p] += qbuffer.request(p, static_cast<float>(quality));
                }
        }
    Raster m(w, h, 1);
    m.v = qbuffer.qualities();
    return m;
}

}  // namespace ref

Raster random_raster(int w, int h, int channels, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0, 1);
    Raster r(w, h, channels);
    for (float& x : r.v) x = u(rng);
    return r;
}

// A picture with structure at several scales: gradients, discs and boxes of random colours
// and sizes, and a little grain.
Raster scene_rgb(int w, int h, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    Raster img(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            img.at(x, y, 0) = static_cast<float>(0.2 + 0.5 * x / w);
            img.at(x, y, 1) = static_cast<float>(0.3 + 0.4 * y / h);
            img.at(x, y, 2) = static_cast<float>(0.6 - 0.4 * x * y / (w * h));
        }
    for (int k = 0; k < 8; ++k) {
        double cx = u(rng) * w, cy = u(rng) * h, r = (0.03 + 0.12 * u(rng)) * std::min(w, h);
        float rgb[3] = {static_cast<float>(u(rng)), static_cast<float>(u(rng)), static_cast<float>(u(rng))};
        bool box = k % 2;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                double dx = x + 0.5 - cx, dy = y + 0.5 - cy;
                if (box ? std::fabs(dx) <= r && std::fabs(dy) <= r / 2 : dx * dx + dy * dy <= r * r)
                    for (int c = 0; c < 3; ++c) img.at(x, y, c) = rgb[c];
            }
    }
    for (float& x : img.v) x = std::clamp(x + static_cast<float>(0.02 * (u(rng) - 0.5)), 0.0f, 1.0f);
    return img;
}

double max_abs_difference(const Raster& a, const Raster& b) {
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    EXPECT_EQ(a.v.size(), b.v.size());
    double d = 0;
    for (size_t i = 0; i < std::min(a.v.size(), b.v.size()); ++i) d = std::max(d, std::fabs(static_cast<double>(a.v[i]) - b.v[i]));
    return d;
}

// Sizes around the kernel radius and odd sizes: the borders are where a fast path goes wrong.
class FilterSizes : public ::testing::TestWithParam<std::tuple<int, int, int>> {};

TEST_P(FilterSizes, BlurPyramidResizeAndSobelMatchThePerPixelLoops) {
    auto [w, h, channels] = GetParam();
    Raster in = random_raster(w, h, channels, static_cast<unsigned>(w * 131 + h));
    for (double sigma : {0.6, 1.0, 2.0, 4.5}) EXPECT_LE(max_abs_difference(gaussian_blur(in, sigma), ref::gaussian_blur(in, sigma)), 1e-6) << sigma;
    auto fast = gaussian_pyramid(in, 9), slow = ref::gaussian_pyramid(in, 9);
    ASSERT_EQ(fast.size(), slow.size());
    for (size_t l = 0; l < fast.size(); ++l) EXPECT_LE(max_abs_difference(fast[l], slow[l]), 1e-6) << "level " << l;
    for (auto [ow, oh] : {std::pair{3 * w + 1, 2 * h}, std::pair{std::max(1, w / 3), h + 5}, std::pair{1, 1}})
        EXPECT_LE(max_abs_difference(resize_bilinear(in, ow, oh), ref::resize_bilinear(in, ow, oh)), 1e-6) << ow << "x" << oh;
    Raster gx, gy, rx, ry;
    sobel(in, gx, gy);
    ref::sobel(in, rx, ry);
    EXPECT_LE(max_abs_difference(gx, rx), 1e-6);
    EXPECT_LE(max_abs_difference(gy, ry), 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Sizes, FilterSizes,
                         ::testing::Values(std::make_tuple(1, 1, 1), std::make_tuple(2, 7, 1), std::make_tuple(13, 1, 3), std::make_tuple(5, 4, 3),
                                           std::make_tuple(37, 23, 1), std::make_tuple(64, 48, 3)));

TEST(NthSmallest, IsTheValueNthElementPicks) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0, 2);
    for (int trial = 0; trial < 20; ++trial) {
        std::vector<float> v(1 + rng() % 5000);
        for (float& x : v) x = rng() % 4 == 0 ? 0.0f : u(rng);  // many ties at 0, as in a flat map
        if (trial % 5 == 1) v[0] = INFINITY;
        if (trial % 5 == 2) v[v.size() / 2] = -0.5f;  // not a map: the general route
        for (size_t k : {size_t{0}, v.size() / 2, v.size() * 98 / 100, v.size() - 1}) {
            std::vector<float> sorted = v;
            std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
            EXPECT_EQ(nth_smallest(v, k), sorted[k]) << "trial " << trial << " k " << k;
        }
    }
}

TEST(DistanceTransform, NoFeatureAndThinImages) {
    for (auto d : squared_distance_transform(std::vector<bool>(12, false), 4, 3)) EXPECT_EQ(d, kNoFeature);
    std::vector<bool> row(9, false);
    row[6] = true;
    auto d = squared_distance_transform(row, 9, 1);
    for (int x = 0; x < 9; ++x) EXPECT_EQ(d[static_cast<size_t>(x)], (x - 6) * (x - 6));
    auto column = squared_distance_transform(row, 1, 9);
    for (int y = 0; y < 9; ++y) EXPECT_EQ(column[static_cast<size_t>(y)], (y - 6) * (y - 6));
}

TEST(SaliencyReference, AtImageSizeItIsThePerPixelAlgorithm) {
    // Up to 64 pixels the finest centre level is the image itself: same maps, same arithmetic.
    for (auto [w, h] : {std::pair{64, 64}, std::pair{50, 37}, std::pair{9, 6}}) {
        Raster img = scene_rgb(w, h, static_cast<unsigned>(w + h));
        EXPECT_LE(max_abs_difference(saliency(img), ref::saliency(img)), 1e-5) << w << "x" << h;
    }
}

TEST(SaliencyReference, OnThePyramidItFindsTheSameSalientPlaces) {
    // 200x150 works at 50x38. Interpolating the final map, rather than each feature map, moves
    // values by about 0.01 on average and 0.12 at most (measured on these seeds); where the
    // salient places are, what guidance uses, stays: the top tenths overlap by 90% or more.
    for (unsigned seed : {1u, 2u, 3u}) {
        Raster img = scene_rgb(200, 150, seed);
        Raster fast = saliency(img), slow = ref::saliency(img);
        double sum = 0;
        for (size_t i = 0; i < fast.v.size(); ++i) sum += std::fabs(fast.v[i] - slow.v[i]);
        EXPECT_LT(sum / static_cast<double>(fast.v.size()), 0.02) << "seed " << seed;
        EXPECT_LT(max_abs_difference(fast, slow), 0.2) << "seed " << seed;
        // The most salient tenth of one is mostly the most salient tenth of the other.
        auto top = [](const Raster& m) {
            std::vector<float> s = m.v;
            std::nth_element(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(s.size() * 9 / 10), s.end());
            return s[s.size() * 9 / 10];
        };
        float tf = top(fast), ts = top(slow);
        size_t both = 0, either = 0;
        for (size_t i = 0; i < fast.v.size(); ++i) {
            bool a = fast.v[i] >= tf, b = slow.v[i] >= ts;
            both += a && b, either += a || b;
        }
        EXPECT_GT(static_cast<double>(both) / static_cast<double>(either), 0.85) << "seed " << seed;
    }
}

TEST(SaliencyReference, ABrightDotOnGreyIsTheMostSalientPointOfALargeImage) {
    const int w = 640, h = 360, cx = 470, cy = 95, r = 5;
    Raster img(w, h, 3, 0.4f);
    for (int y = cy - r; y <= cy + r; ++y)
        for (int x = cx - r; x <= cx + r; ++x)
            if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r)
                for (int c = 0; c < 3; ++c) img.at(x, y, c) = 0.95f;
    Raster s = saliency(img);
    size_t m = static_cast<size_t>(std::max_element(s.v.begin(), s.v.end()) - s.v.begin());
    EXPECT_LE(std::hypot(static_cast<double>(m % w) - cx, static_cast<double>(m / w) - cy), r + 2.0);
    EXPECT_FLOAT_EQ(s.v[m], 1.0f);
    EXPECT_LT(s.at(40, 300), 0.05f);
}

TEST(EdgesReference, MatchesThePerPixelAlgorithm) {
    Raster img = scene_rgb(97, 61, 4);
    EXPECT_LE(max_abs_difference(edges(img), ref::edges(img)), 1e-6);
}

TEST(NoiseReference, IsTheBlurredDifferenceOverIts98thPercentile) {
    Raster high = scene_rgb(71, 40, 5), low = high;
    std::mt19937 rng(9);
    for (float& x : low.v) x = std::max(0.0f, x - 0.1f * static_cast<float>(rng() % 1000) / 1000);
    Raster d(71, 40, 1);
    Raster yh = luminance(high), yl = luminance(low);
    for (size_t i = 0; i < d.v.size(); ++i) d.v[i] = std::fabs(yh.v[i] - yl.v[i]);
    Raster b = ref::gaussian_blur(d, 1.0);
    float scale = ref::percentile_scale(b, static_cast<size_t>(0.98 * static_cast<double>(b.v.size())));
    for (float& x : b.v) x = std::clamp(x / scale, 0.0f, 1.0f);
    EXPECT_LE(max_abs_difference(noise_map(high, low), b), 1e-6);
}

class FoveaSizes : public ::testing::TestWithParam<double> {};

TEST_P(FoveaSizes, TaskAndDistractorMapsMatchBruteForce) {
    const double fovea = GetParam() * std::numbers::pi / 180;
    const int w = 48, h = 30;
    ViewGeometry view{w, h, 0.8};
    std::mt19937 rng(21);
    std::vector<std::vector<bool>> covered(3, std::vector<bool>(w * h, false));
    for (int s = 0; s < 2; ++s)  // the third set is empty: no object of that task
        for (int k = 0; k < 3; ++k) {
            int x0 = static_cast<int>(rng() % w), y0 = static_cast<int>(rng() % h);
            for (int y = y0; y < std::min(h, y0 + 4); ++y)
                for (int x = x0; x < std::min(w, x0 + 3); ++x) covered[static_cast<size_t>(s)][static_cast<size_t>(y * w + x)] = true;
        }
    std::vector<double> value{0.4, 1.0, 0.7};
    EXPECT_LE(max_abs_difference(task_map(covered, value, view, fovea, 0.1), ref::task_map(covered, value, view, fovea, 0.1)), 1e-6);
    std::vector<float> granted, ref_granted;
    Raster fast = distractor_map(covered[0], view, fovea, &granted), slow = ref::distractor_map(covered[0], view, fovea, ref_granted);
    EXPECT_LE(max_abs_difference(fast, slow), 1e-6);
    for (size_t p = 0; p < granted.size(); ++p) ASSERT_NEAR(granted[p], ref_granted[p], 1e-5) << p;
}

// 0: only the objects themselves; 2: the runtime's default; 40: wider than this image.
INSTANTIATE_TEST_SUITE_P(Degrees, FoveaSizes, ::testing::Values(0.0, 2.0, 10.0, 40.0));

}  // namespace
}  // namespace crex::guidance
