// Choosing an emitter by what it brings to the shading point (runtime/render/render_scene.h):
// unbiased (the same irradiance as the choice by power), much less variance when one lamp is
// near and another far, and never a lamp the point is behind.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "runtime/render/render_scene.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

// Two 0.2 x 0.2 lamps of radiance 1 at height 1: A above the origin, B 20 to the side. B faces
// down, or up (then the origin is behind it).
Scene two_lamps(bool b_faces_down) {
    Scene s;
    s.materials.push_back(testing::make_material("lamp", MaterialType::kLight, {1, 1, 1}));
    const double h = 0.1;
    s.shapes.push_back(testing::quad("lamp", {-h, 1, -h}, {h, 1, -h}, {h, 1, h}, {-h, 1, h}));  // faces down
    if (b_faces_down)
        s.shapes.push_back(testing::quad("lamp", {20 - h, 1, -h}, {20 + h, 1, -h}, {20 + h, 1, h}, {20 - h, 1, h}));
    else
        s.shapes.push_back(testing::quad("lamp", {20 - h, 1, h}, {20 + h, 1, h}, {20 + h, 1, -h}, {20 - h, 1, -h}));
    s.camera.position = {0, 0.5, 3};
    s.camera.direction = {0, 0, -1};
    s.camera.up = {0, 1, 0};
    return s;
}

struct Estimate {
    double mean = 0, variance = 0;
    size_t on_b = 0;
};

// Irradiance at the origin (normal up) from n light samples, chosen locally or by power.
Estimate irradiance_at_origin(const RenderScene& rs, bool local, size_t n) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> U(0, 1);
    const Vec3 x = Vec3{0, 0, 0} - rs.embree->origin_offset(), up{0, 1, 0};
    double sum = 0, sum2 = 0;
    Estimate e;
    for (size_t i = 0; i < n; ++i) {
        double a = U(rng), b = U(rng), c = U(rng);
        LightSample ls = local ? rs.lights->sample(rs.lights->weights_at(x), a, b, c) : rs.lights->sample(a, b, c);
        double f = 0;
        if (ls.pdf_area > 0) {
            Vec3 to = ls.position - x;
            double d2 = dot(to, to);
            Vec3 wi = to / std::sqrt(d2);
            double cos_x = std::fmax(0.0, dot(wi, up)), cos_l = std::fmax(0.0, -dot(ls.normal, wi));
            f = ls.radiance.y * cos_x * cos_l / (d2 * ls.pdf_area);
            e.on_b += (ls.position + rs.embree->origin_offset()).x > 10;
        }
        sum += f, sum2 += f * f;
    }
    e.mean = sum / static_cast<double>(n);
    e.variance = sum2 / static_cast<double>(n) - e.mean * e.mean;
    return e;
}

TEST(LightChoice, SameIrradianceAsChoosingByPowerWithFarLessVariance) {
    Scene s = two_lamps(true);
    RenderScene rs(s);
    const size_t n = 400000;
    Estimate local = irradiance_at_origin(rs, true, n), power = irradiance_at_origin(rs, false, n);
    double se = std::sqrt((local.variance + power.variance) / static_cast<double>(n));
    EXPECT_NEAR(local.mean, power.mean, 5 * se);
    // A small lamp at distance 1 straight above: E close to L A / d^2 = 0.04 (B adds ~1e-7).
    EXPECT_NEAR(local.mean, 0.04, 0.002);
    EXPECT_LT(local.variance, 0.1 * power.variance);  // by power, half the samples went to B
    EXPECT_LT(local.on_b, n / 100);
}

TEST(LightChoice, NeverALampThePointIsBehind) {
    Scene s = two_lamps(false);  // B faces up: the origin is behind it
    RenderScene rs(s);
    Estimate local = irradiance_at_origin(rs, true, 10000);
    EXPECT_EQ(local.on_b, 0u);
    EXPECT_GT(local.mean, 0.03);
}

}  // namespace
}  // namespace crex
