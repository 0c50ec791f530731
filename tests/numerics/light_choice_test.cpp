// Choosing an emitter by what it brings to the shading point (runtime/render/render_scene.h):
// unbiased (the same irradiance as the choice by power), much less variance when one lamp is
// near and another far, never a lamp the point is behind, and, for a surface that only
// reflects, never an emitter below its horizon; a quad lamp is one emitter, sampled without a
// fold, and a lamp of any shape gives its irradiance.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "runtime/render/render_scene.h"
#include "runtime/render/shade.h"
#include "runtime/scene/sky_model.h"
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

// The mean and variance of samples, added one by one.
struct Estimate {
    double mean = 0, variance = 0;
    size_t on_b = 0;
    void add(double f) { sum += f, sum2 += f * f, ++n; }
    Estimate& finish() {
        mean = sum / static_cast<double>(n);
        variance = std::fmax(sum2 / static_cast<double>(n) - mean * mean, 0.0);
        return *this;
    }

private:
    double sum = 0, sum2 = 0;
    size_t n = 0;
};

// Irradiance at the origin (normal up) from n light samples, chosen locally or by power.
Estimate irradiance_at_origin(const RenderScene& rs, bool local, size_t n, bool horizon = false) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> U(0, 1);
    const Vec3 x = Vec3{0, 0, 0} - rs.embree->origin_offset(), up{0, 1, 0};
    Estimate e;
    for (size_t i = 0; i < n; ++i) {
        double a = U(rng), b = U(rng), c = U(rng);
        LightSample ls = local ? rs.lights->sample(rs.lights->weights_at(x, horizon ? &up : nullptr), a, b, c) : rs.lights->sample(a, b, c);
        double f = 0;
        if (ls.pdf_area > 0) {
            Vec3 to = ls.position - x;
            double d2 = dot(to, to);
            Vec3 wi = to / std::sqrt(d2);
            double cos_x = std::fmax(0.0, dot(wi, up)), cos_l = std::fmax(0.0, -dot(ls.normal, wi));
            f = ls.radiance.y * cos_x * cos_l / (d2 * ls.pdf_area);
            e.on_b += (ls.position + rs.embree->origin_offset()).x > 1;  // A is within 0.1 of x = 0
        }
        e.add(f);
    }
    return e.finish();
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

// Lamp A above the origin as in two_lamps, and lamp B 1 below it facing up, 2 to the side: the
// origin is in front of B (no "behind the lamp" test refuses it) but B is wholly below the
// plane of a surface at the origin facing up.
Scene lamp_above_and_lamp_below() {
    Scene s = two_lamps(true);
    s.shapes.pop_back();
    const double h = 0.1;
    s.shapes.push_back(testing::quad("lamp", {2 - h, -1, h}, {2 + h, -1, h}, {2 + h, -1, -h}, {2 - h, -1, -h}));
    return s;
}

TEST(LightChoice, ASurfaceThatOnlyReflectsNeverChoosesALampBelowItsHorizon) {
    Scene s = lamp_above_and_lamp_below();
    RenderScene rs(s);
    const size_t n = 200000;
    Estimate plain = irradiance_at_origin(rs, true, n), horizon = irradiance_at_origin(rs, true, n, true);
    // Without the horizon B weighs a fifth of A by distance, less by its cosine (seen at 63
    // degrees from its normal): about a tenth of the samples go to it, each worth 0; with the
    // horizon none do, and the irradiance is the same.
    EXPECT_GT(plain.on_b, n / 20);
    EXPECT_EQ(horizon.on_b, 0u);
    const double se = std::sqrt((plain.variance + horizon.variance) / static_cast<double>(n));
    EXPECT_NEAR(horizon.mean, plain.mean, 5 * se);
    EXPECT_NEAR(horizon.mean, 0.04, 0.002);
    EXPECT_LT(horizon.variance, 0.9 * plain.variance);
}

// RADIANCE's sky and ground (gensky's two glow sources over the upper and lower hemispheres)
// and a sun at 45 degrees up toward +x.
TEST(LightChoice, DistantSourcesWhollyBelowTheHorizonWeighNothing) {
    Scene s = two_lamps(true);
    s.shapes.clear();  // a grey floor only, for the scene's bounds
    s.materials.push_back(testing::make_material("grey", MaterialType::kPlastic, {0.5, 0.5, 0.5}));
    s.materials.push_back(testing::make_material("skyglow", MaterialType::kGlow, {1, 1, 1}));
    s.materials.push_back(testing::make_material("sunlight", MaterialType::kLight, {1e5, 1e5, 1e5}));
    s.shapes.push_back(testing::quad("grey", {-1, -1, 1}, {1, -1, 1}, {1, -1, -1}, {-1, -1, -1}));
    s.distant_lights.push_back({"sky", "skyglow", {0, 1, 0}, 180, std::nullopt});
    s.distant_lights.push_back({"ground", "skyglow", {0, -1, 0}, 180, std::nullopt});
    s.distant_lights.push_back({"sun", "sunlight", {1, 1, 0}, 0.5, std::nullopt});
    RenderScene rs(s);
    const Vec3 x{0, 0, 0};
    auto total = [&](Vec3 n) {
        n = normalize_or_zero(n);
        return rs.lights->weights_at(x, &n).total;
    };
    const double hemisphere = 2 * kPi, sun = 1e5 * 2 * kPi * (1 - std::cos(0.25 * kPi / 180));
    EXPECT_NEAR(rs.lights->weights_at(x).total, 2 * hemisphere + sun, 1e-6 * sun);
    EXPECT_NEAR(total({0, 1, 0}), hemisphere + sun, 1e-6 * sun);      // a floor: no ground
    EXPECT_NEAR(total({0, -1, 0}), hemisphere, 1e-9);                 // a ceiling: the ground only
    EXPECT_NEAR(total({1, 0, 0}), 2 * hemisphere + sun, 1e-6 * sun);  // a wall sees half of each
    EXPECT_NEAR(total({-1, 0, 0}), 2 * hemisphere, 1e-9);             // and this one no sun
    // The sun's disc is 0.25 degrees wide each side of its axis: a surface tipped 0.2 degrees
    // past facing it edge-on still sees its edge, one tipped 0.3 degrees does not. (Such a
    // surface sees half of the sky and of the ground whatever its tip.)
    const double tip = kPi / 180;
    auto tipped = [&](double angle) { return total({std::cos(angle), std::sin(angle), 0}) - 2 * hemisphere; };
    EXPECT_NEAR(tipped(0.75 * kPi + 0.2 * tip), sun, 1e-6 * sun);
    EXPECT_NEAR(tipped(0.75 * kPi + 0.3 * tip), 0, 1e-9);
    // On a floor no sample goes down into the ground; without the horizon a third did.
    auto down_share = [&](const LightSampler::LocalWeights& w) {
        size_t down = 0;
        for (int i = 0; i < 256; ++i) down += rs.lights->sample(w, (i + 0.5) / 256, 0.5, 0.37).direction.y < 0;
        return static_cast<double>(down) / 256;
    };
    const Vec3 floor_normal{0, 1, 0};
    EXPECT_EQ(down_share(rs.lights->weights_at(x, &floor_normal)), 0.0);
    EXPECT_GT(down_share(rs.lights->weights_at(x)), 0.25);
}

// A sky of radiance 1 over the upper hemisphere and a ground of 0.3 below (z up, gensky's
// pair), optionally with a CIE clear sky's pattern, and a floor under them for the bounds.
Scene sky_and_ground(bool clear_sky) {
    Scene s;
    s.materials.push_back(testing::make_material("grey", MaterialType::kPlastic, {0.5, 0.5, 0.5}));
    s.materials.push_back(testing::make_material("skyglow", MaterialType::kGlow, {1, 1, 1}));
    s.materials.push_back(testing::make_material("groundglow", MaterialType::kGlow, {0.3, 0.3, 0.3}));
    s.shapes.push_back(testing::quad("grey", {-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}));
    std::optional<SkyModel> sky;
    if (clear_sky) {
        SkyModel m;
        m.type = SkyModel::Type::kClear;
        m.sun = normalize_or_zero(Vec3{0.5, 0.2, 0.4});
        m.normalization = sky_normalization(m.type, m.sun);
        sky = m;
    }
    s.distant_lights.push_back({"sky", "skyglow", {0, 0, 1}, 180, sky});
    s.distant_lights.push_back({"ground", "groundglow", {0, 0, -1}, 180, std::nullopt});
    s.camera.position = {0, -3, 0};
    s.camera.direction = {0, 1, 0};
    s.camera.up = {0, 0, 1};
    return s;
}

// Irradiance at the origin of a surface facing n, estimated from n_samples light samples
// (stratified picks), with or without the surface's horizon given to the sampler.
Estimate sky_irradiance(const RenderScene& rs, Vec3 n, bool horizon, size_t n_samples) {
    n = normalize_or_zero(n);
    const LightSampler::LocalWeights w = rs.lights->weights_at({0, 0, 0}, horizon ? &n : nullptr);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U(0, 1);
    Estimate out;
    for (size_t i = 0; i < n_samples; ++i) {
        const LightSample ls = rs.lights->sample(w, (static_cast<double>(i) + U(rng)) / static_cast<double>(n_samples), U(rng), U(rng));
        double e = 0;
        if (ls.distant && ls.pdf_direction > 0) e = ls.radiance.y * std::fmax(dot(ls.direction, n), 0.0) / ls.pdf_direction;
        out.add(e);
    }
    return out.finish();
}

TEST(LightChoice, AUniformSkyLightsAFloorWithoutNoise) {
    Scene s = sky_and_ground(false);
    RenderScene rs(s);
    // Cosine sampling above the floor: every sample is the exact irradiance pi x 1.
    const Estimate floor = sky_irradiance(rs, {0, 0, 1}, true, 4000);
    EXPECT_NEAR(floor.mean, kPi, 1e-9);
    EXPECT_LT(floor.variance, 1e-12);
    // Without the horizon: the same mean, with noise (the ground's samples, and uniform ones).
    const Estimate plain = sky_irradiance(rs, {0, 0, 1}, false, 400000);
    EXPECT_NEAR(plain.mean, kPi, 5 * std::sqrt(plain.variance / 400000));
    EXPECT_GT(plain.variance, 1.0);
    // A wall sees half of each: pi/2 x (1 + 0.3), and less noise than without its horizon.
    const size_t n = 400000;
    const Estimate wall = sky_irradiance(rs, {1, 0, 0}, true, n), wall_plain = sky_irradiance(rs, {1, 0, 0}, false, n);
    EXPECT_NEAR(wall.mean, 0.5 * kPi * 1.3, 5 * std::sqrt(wall.variance / static_cast<double>(n)));
    EXPECT_NEAR(wall_plain.mean, 0.5 * kPi * 1.3, 5 * std::sqrt(wall_plain.variance / static_cast<double>(n)));
    EXPECT_LT(wall.variance, 0.8 * wall_plain.variance);
}

// A CIE clear sky is sampled by its brightness 70 % of the time and by the cosine 30 % (one
// sample of the mixture): the same irradiance as sampling by brightness alone, on surfaces
// facing up, tipped toward the sun, away from it and down. Less noise where much of the sky is
// behind the surface or far from the sun; a little more (at most a fifth) on a surface facing
// the sun, where the brightness alone is already close to the product with the cosine.
TEST(LightChoice, APatternedSkyAboveASurfaceHasTheSameIrradiance) {
    Scene s = sky_and_ground(true);
    RenderScene rs(s);
    const size_t n = 400000;
    struct Case {
        Vec3 normal;
        double most_variance;  // the ratio to the variance without the horizon it stays below
    };
    for (const Case c : {Case{{0, 0, 1}, 0.5}, Case{{0.5, 0.2, 0.3}, 1.2}, Case{{-0.7, 0.1, 0.2}, 0.8}, Case{{0.1, 0.9, -0.2}, 1.0}}) {
        const Estimate above = sky_irradiance(rs, c.normal, true, n), plain = sky_irradiance(rs, c.normal, false, n);
        const double se = std::sqrt((above.variance + plain.variance) / static_cast<double>(n));
        EXPECT_NEAR(above.mean, plain.mean, 5 * se) << c.normal.x << " " << c.normal.y << " " << c.normal.z;
        EXPECT_GT(above.mean, 1.0);
        EXPECT_LT(above.variance, c.most_variance * plain.variance) << c.normal.x << " " << c.normal.y << " " << c.normal.z;
    }
}

// Light from behind reaches a translucent surface (a lampshade, a blind): only a surface that
// reflects alone is given a horizon.
TEST(LightChoice, OnlyASurfaceThatReflectsAloneHasAHorizon) {
    HitFrame f;
    f.normal = f.geometric = f.shading = {0, 0, 1};
    Material plastic = testing::make_material("p", MaterialType::kPlastic, {0.5, 0.5, 0.5});
    EXPECT_EQ(horizon_of(Bsdf::of(plastic), f), &f.normal);
    Material shade = testing::make_material("t", MaterialType::kTrans, {0.5, 0.5, 0.5});
    shade.transmissivity = 0.5;
    EXPECT_EQ(horizon_of(Bsdf::of(shade), f), nullptr);
    shade.transmitted_specular = 1;  // all of it straight through: shadow rays cross it, it is lit from the front only
    EXPECT_EQ(horizon_of(Bsdf::of(shade), f), &f.normal);
    Material lamp = testing::make_material("l", MaterialType::kLight, {1, 1, 1});
    EXPECT_EQ(horizon_of(Bsdf::of(lamp), f), nullptr);  // direct light does not reach it at all
}

// One lamp over the origin, facing down at height 1: a square (two triangles of one
// parallelogram) or a trapezoid (two triangles that are not).
Scene one_lamp(bool square) {
    Scene s;
    s.materials.push_back(testing::make_material("lamp", MaterialType::kLight, {1, 1, 1}));
    const double h = 0.1, top = square ? h : 0.04;
    s.shapes.push_back(testing::quad("lamp", {-h, 1, -h}, {h, 1, -h}, {top, 1, h}, {-top, 1, h}));
    s.camera.position = {0, 0.5, 3};
    s.camera.direction = {0, 0, -1};
    s.camera.up = {0, 1, 0};
    return s;
}

// Irradiance at the origin (normal up) from the lamp of one_lamp, integrated by the midpoint
// rule over a fine grid of its plane, cells outside it left out.
double irradiance_by_grid(bool square) {
    const double h = 0.1, top = square ? h : 0.04;
    const int n = 2000;
    const double cell = 2 * h / n;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        const double z = -h + (i + 0.5) * cell, half_width = h + (top - h) * (z + h) / (2 * h);
        for (int j = 0; j < n; ++j) {
            const double x = -h + (j + 0.5) * cell;
            if (std::fabs(x) > half_width) continue;
            const double d2 = x * x + 1 + z * z;
            sum += 1 / (d2 * d2);  // cos at the point and at the lamp both 1 / d; over d^2
        }
    }
    return sum * cell * cell;
}

TEST(LightChoice, AQuadLampIsOneEmitterWhosePointsKeepTheirStrata) {
    Scene s = one_lamp(true);
    RenderScene rs(s);
    const Vec3 x = Vec3{0, 0, 0} - rs.embree->origin_offset(), up{0, 1, 0};
    const LightSampler::LocalWeights w = rs.lights->weights_at(x, &up);
    // A 16 x 16 grid of (u, v) puts one point in each 16 x 16th of the lamp: its two triangles
    // sampled as one parallelogram, without a choice between them or a fold within each.
    const int n = 16;
    std::vector<int> count(n * n, 0);
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            const LightSample ls = rs.lights->sample_reusing(w, (i + 0.5) / n, (j + 0.5) / n);
            ASSERT_GT(ls.pdf_area, 0);
            EXPECT_NEAR(ls.pdf_area, 1 / 0.04, 1e-9);
            const Vec3 p = ls.position + rs.embree->origin_offset();
            const int cx = static_cast<int>((p.x + 0.1) / 0.2 * n), cz = static_cast<int>((p.z + 0.1) / 0.2 * n);
            ASSERT_TRUE(cx >= 0 && cx < n && cz >= 0 && cz < n) << p.x << " " << p.z;
            ++count[cx * n + cz];
            const Vec3 to = ls.position - x;
            const double d2 = dot(to, to), inv_d = 1 / std::sqrt(d2);
            sum += dot(to, up) * inv_d * -dot(ls.normal, to) * inv_d / (d2 * ls.pdf_area);
        }
    }
    for (int c : count) EXPECT_EQ(c, 1);
    // The grid's estimate is the midpoint rule over the lamp: 5e-5 from the integral (the two
    // triangles sampled apart, each folded: 2.9e-4).
    const double exact = irradiance_by_grid(true);
    EXPECT_NEAR(sum / (n * n), exact, 1.5e-4 * exact);
    // A point behind the lamp has nothing to choose.
    EXPECT_EQ(rs.lights->weights_at(Vec3{0, 2, 0} - rs.embree->origin_offset()).total, 0.0);
}

TEST(LightChoice, LampsOfEitherShapeGiveTheirIrradiance) {
    for (bool square : {true, false}) {
        Scene s = one_lamp(square);
        RenderScene rs(s);
        const size_t n = 200000;
        Estimate local = irradiance_at_origin(rs, true, n, true), power = irradiance_at_origin(rs, false, n);
        const double exact = irradiance_by_grid(square);
        EXPECT_NEAR(local.mean, exact, 5 * std::sqrt(local.variance / n)) << (square ? "square" : "trapezoid");
        EXPECT_NEAR(power.mean, exact, 5 * std::sqrt(power.variance / n)) << (square ? "square" : "trapezoid");
    }
}

}  // namespace
}  // namespace crex
