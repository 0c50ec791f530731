// The sampling helpers that shading calls at every hit: the inline min/max keep std::fmax's
// NaN rule, the per-hit random numbers equal random_at(), the inline sincos matches libm's, and
// the cosine and Phong samplers have the right moments.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "runtime/base/sampling.h"

namespace crex {
namespace {

TEST(Sampling, MaxOfAndMinOfFollowFmaxOnNaN) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double values[] = {-1.0, 0.0, 2.5, nan, std::numeric_limits<double>::infinity()};
    for (double a : values)
        for (double b : values) {
            double want_max = std::fmax(a, b), want_min = std::fmin(a, b);
            if (std::isnan(want_max)) EXPECT_TRUE(std::isnan(max_of(a, b)));
            else EXPECT_EQ(max_of(a, b), want_max) << a << " " << b;
            if (std::isnan(want_min)) EXPECT_TRUE(std::isnan(min_of(a, b)));
            else EXPECT_EQ(min_of(a, b), want_min) << a << " " << b;
        }
    EXPECT_EQ(max_component(Vec3{nan, 0.25, -3}), 0.25);
    EXPECT_EQ(min_component(Vec3{nan, 0.25, -3}), -3);
}

TEST(Sampling, HitRandomEqualsRandomAt) {
    for (uint64_t path : {0ull, 1ull, 0xdeadbeefcafeull})
        for (uint32_t depth : {0u, 3u, 255u}) {
            HitRandom r(path, depth);
            for (uint32_t i = 0; i < 4; ++i) {
                EXPECT_EQ(r(RandomUse::kLobeD, i), random_at(path, depth, RandomUse::kLobeD, i));
                EXPECT_EQ(r(RandomUse::kLight, i), random_at(path, depth, RandomUse::kLight, i));
            }
        }
}

TEST(Sampling, SincosIsAccurate) {
    double worst = 0;
    for (int k = 0; k < 10000; ++k) {
        double u = k / 10000.0, c, s;
        sincos_2pi(u, c, s);
        worst = std::fmax(worst, std::fmax(std::fabs(c - std::cos(2 * kPi * u)), std::fabs(s - std::sin(2 * kPi * u))));
    }
    EXPECT_LT(worst, 1e-9);
}

// Cosine-weighted: E[cos] = 2/3, E[cos^2] = 1/2; unit length; never below the surface.
TEST(Sampling, CosineSamplesHaveTheirMoments) {
    const Vec3 n = normalize_or_zero(Vec3{0.3, -0.5, 0.8});
    const int count = 200000;
    double sum = 0, sum2 = 0;
    for (int k = 0; k < count; ++k) {
        Vec3 d = sample_cosine(n, random_at(k, 0, RandomUse::kLobeD, 0), random_at(k, 0, RandomUse::kLobeD, 1));
        ASSERT_NEAR(length(d), 1.0, 1e-6);
        double c = dot(d, n);
        ASSERT_GE(c, -1e-7);
        sum += c, sum2 += c * c;
    }
    // Standard errors: sqrt(Var/N) with Var(cos) = 1/2 - 4/9 = 1/18; 5 sigma.
    EXPECT_NEAR(sum / count, 2.0 / 3.0, 5 * std::sqrt(1.0 / 18 / count));
    EXPECT_NEAR(sum2 / count, 0.5, 5 * std::sqrt((1.0 / 3 - 0.25) / count));
}

// Phong lobe with exponent e: E[cos] = (e + 1) / (e + 2).
TEST(Sampling, PhongSamplesHaveTheirMean) {
    const Vec3 axis = normalize_or_zero(Vec3{-0.2, 0.9, 0.1});
    for (double e : {1.0, 10.0, 200.0}) {
        const int count = 100000;
        double sum = 0, sum2 = 0;
        for (int k = 0; k < count; ++k) {
            Vec3 d = sample_phong(axis, e, random_at(k, 1, RandomUse::kLobeG, 0), random_at(k, 1, RandomUse::kLobeG, 1));
            ASSERT_NEAR(length(d), 1.0, 1e-6);
            double c = dot(d, axis);
            sum += c, sum2 += c * c;
        }
        double mean = (e + 1) / (e + 2), second = (e + 1) / (e + 3);
        EXPECT_NEAR(sum / count, mean, 5 * std::sqrt((second - mean * mean) / count)) << e;
    }
}

}  // namespace
}  // namespace crex
