// A homogeneous participating medium against closed forms (issue 18):
//  - Beer-Lambert: an emitter seen through an absorbing medium is exp(-sigma_t d) as bright,
//    per channel, and direct light on a surface loses exp(-sigma_t) over both of its legs;
//  - single scattering: a camera ray passing a small sphere lamp in an unbounded medium
//    gathers the integral of sigma_s p(theta) I / r^2 exp(-sigma_t (t + r)) along the ray,
//    computed here by a 1-D quadrature;
//  - equiangular sampling's pdf integrates to one over finite and infinite segments;
//  - a medium in a box (RADIANCE's mist on a genbox) acts only on the parts of rays inside it.
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/cache/irradiance_cache.h"
#include "runtime/render/medium.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

TEST(Medium, EquiangularPdfIntegratesToOne) {
    const Vec3 o{0, 0, 0}, dir{0, 0, -1}, light{0.3, 0.2, -2};
    for (double tmax : {1.0, 5.0, double(INFINITY)}) {
        // The density over t, integrated by the midpoint rule on t = Delta + D tan(theta).
        const double delta = 2, d = std::sqrt(0.13);
        const double a = std::atan2(-delta, d), b = std::isfinite(tmax) ? std::atan2(tmax - delta, d) : kPi / 2;
        double sum = 0;
        const int n = 20000;
        for (int k = 0; k < n; ++k) {
            double theta = a + (k + 0.5) / n * (b - a);
            double t = delta + d * std::tan(theta);
            double dt = d / (std::cos(theta) * std::cos(theta)) * (b - a) / n;
            DistanceSample s = sample_equiangular(o, dir, tmax, light, (k + 0.5) / n);
            EXPECT_NEAR(s.t, t, 1e-9 * std::max(1.0, t));
            sum += s.pdf * dt;
        }
        EXPECT_NEAR(sum, 1.0, 1e-6) << "tmax " << tmax;
    }
    // On the light's own line there is no angle to sample.
    EXPECT_EQ(sample_equiangular(o, dir, 5, Vec3{0, 0, -3}, 0.5).pdf, 0.0);
}

Medium mist(Vec3 extinction, Vec3 albedo, double g) {
    Medium m;
    m.extinction = extinction;
    m.albedo = albedo;
    m.eccentricity = g;
    return m;
}

// A wall of radiance 1 at distance 2 filling a 1-degree view from the origin along -z.
Scene wall_ahead() {
    Scene s;
    s.materials.push_back(testing::make_material("wall", MaterialType::kLight, {1, 1, 1}));
    s.shapes.push_back(testing::quad("wall", {-5, -5, -2}, {5, -5, -2}, {5, 5, -2}, {-5, 5, -2}));
    s.camera.position = {0, 0, 0};
    s.camera.direction = {0, 0, -1};
    s.camera.vfov_deg = 1;
    return s;
}

TEST(Medium, BeerLambertThroughTheMediumToAnEmitter) {
    // A wall of radiance 1 at distance 2 fills a 1-degree view; an absorbing medium (albedo 0)
    // between: each channel is exp(-2 sigma_t), to 3e-4 at sigma_t 2 (the corner rays are
    // 7.6e-5 longer).
    Scene s = wall_ahead();
    const Vec3 sigma{0.1, 0.5, 2.0};
    s.medium = mist(sigma, {0, 0, 0}, 0);
    RunResult r = testing::render_crex(s, "", 8, 1);
    std::vector<float> img = r.image();
    for (size_t p = 0; p < img.size() / 3; ++p)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(img[3 * p + c] / std::exp(-2 * sigma[c]), 1.0, 4e-4) << "pixel " << p << " channel " << c;
}

TEST(Medium, DirectLightLosesTheTransmittanceOfBothLegs) {
    // A diffuse floor under a small sphere lamp h above it, seen from straight above the point
    // below the lamp from height hc: E = pi L (r / h)^2 at that point, attenuated along the
    // shadow ray (h - r) and the camera ray (hc). Grey absorbing medium.
    const double rho = 0.5, L = 4, r = 0.05, h = 1, hc = 0.4, sigma = 0.7;
    Scene s;
    s.materials.push_back(testing::make_material("floor", MaterialType::kPlastic, {rho, rho, rho}));
    s.materials.push_back(testing::make_material("lamp", MaterialType::kLight, {L, L, L}));
    s.shapes.push_back(testing::quad("floor", {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, {-2, 0, -2}));
    Shape lamp;
    lamp.type = ShapeType::kSphere;
    lamp.material = "lamp";
    lamp.center = {0, h, 0};
    lamp.radius = r;
    s.shapes.push_back(lamp);
    s.camera.position = {0, hc, 0};
    s.camera.direction = {0, -1, 0};
    s.camera.up = {0, 0, -1};
    s.camera.vfov_deg = 1;
    s.medium = mist({sigma, sigma, sigma}, {0, 0, 0}, 0);
    RunResult img = testing::render_crex(s, "", 32, 16, 0, 1);
    // Rays to the lamp at angle t from the vertical cross d(t) = h cos t - sqrt(r^2 - h^2 sin^2 t)
    // of medium: E = 2 pi L int_0^asin(r/h) exp(-sigma d(t)) cos t sin t dt by quadrature
    // (exp(-sigma (h - r)) for every ray, the nearest point's, is 1.1 % too bright: the
    // pixel-stratified light samples are accurate enough to tell).
    const double alpha = std::asin(r / h);
    const int n = 20000;
    double integral = 0;
    for (int i = 0; i < n; ++i) {
        const double t = (i + 0.5) / n * alpha;
        const double d = h * std::cos(t) - std::sqrt(std::max(0.0, r * r - h * h * std::sin(t) * std::sin(t)));
        integral += std::exp(-sigma * d) * std::cos(t) * std::sin(t) * (alpha / n);
    }
    const double expected = rho / kPi * (2 * kPi * L * integral) * std::exp(-sigma * hc);
    EXPECT_NEAR(testing::mean_luminance(img.image()) / expected, 1.0, 0.01);
}

// Single scattering from a point-like lamp of intensity I into the segment o + t d, t in
// [0, tmax] (d unit), seen from o, by quadrature: t = tc + hd tan(theta) about the point
// nearest the lamp keeps the integrand smooth.
double scatter_along(const Vec3& o, const Vec3& d, double tmax, const Vec3& light, double I, double sigma_t, double sigma_s, double g) {
    const double tc = dot(light - o, d), hd = length(light - (o + d * tc));
    const double a0 = std::atan2(-tc, hd), a1 = std::isinf(tmax) ? kPi / 2 : std::atan2(tmax - tc, hd);
    const int n = 200000;
    double sum = 0;
    for (int k = 0; k < n; ++k) {
        const double th = a0 + (k + 0.5) / n * (a1 - a0);
        const double t = tc + hd * std::tan(th), dt = hd / (std::cos(th) * std::cos(th)) * (a1 - a0) / n;
        const Vec3 to = light - (o + d * t);
        const double r = length(to);
        sum += sigma_s * henyey_greenstein(dot(to / r, d), g) * I / (r * r) * std::exp(-sigma_t * (t + r)) * dt;
    }
    return sum;
}

// Single scattering toward the eye from a point-like lamp: the camera ray along -z from the
// origin, the lamp at (0, hl, -zl); intensity of a sphere lamp of radiance L and radius a in
// every direction is L pi a^2.
double single_scatter_quadrature(double sigma_t, double sigma_s, double g, double L, double a, double hl, double zl) {
    return scatter_along({0, 0, 0}, {0, 0, -1}, INFINITY, {0, hl, -zl}, L * kPi * a * a, sigma_t, sigma_s, g);
}

// A sphere lamp of radiance L and radius a at (0, hl, -zl), the camera at the origin looking
// down -z through a 0.2-degree view (every pixel's ray within 0.002 of the axis at the lamp);
// 8 x 8 pixels, 64 samples of 8 single-scatter samples each.
Scene small_lamp_beside_the_view(double L, double a, double hl, double zl) {
    Scene s;
    s.materials.push_back(testing::make_material("lamp", MaterialType::kLight, {L, L, L}));
    Shape lamp;
    lamp.type = ShapeType::kSphere;
    lamp.material = "lamp";
    lamp.center = {0, hl, -zl};
    lamp.radius = a;
    s.shapes.push_back(lamp);
    s.camera.position = {0, 0, 0};
    s.camera.direction = {0, 0, -1};
    s.camera.vfov_deg = 0.2;
    return s;
}

RunSettings single_scatter_settings() {
    RunSettings o;
    o.width = o.height = 8;
    o.spp = 64;
    o.executor.shade.media_samples = 8;
    return o;
}

TEST(Medium, SingleScatterFromASmallLampMatchesTheQuadrature) {
    const double sigma_t = 0.4, albedo = 0.8, g = 0.3, L = 50, a = 0.01, hl = 0.5, zl = 2;
    Scene s = small_lamp_beside_the_view(L, a, hl, zl);
    s.medium = mist({sigma_t, sigma_t, sigma_t}, {albedo, albedo, albedo}, g);
    const RunSettings o = single_scatter_settings();
    RunResult img = render(s, testing::lower_or_die(""), o);
    const double expected = single_scatter_quadrature(sigma_t, sigma_t * albedo, g, L, a, hl, zl);
    ASSERT_GT(expected, 0);
    // 8 x 8 x 64 x 8 samples, equiangular: a standard error of about 0.1 %.
    EXPECT_NEAR(testing::mean_luminance(img.image()) / expected, 1.0, 0.01);
    // Without scattering (albedo 0) the lamp lights nothing the camera sees.
    s.medium = mist({sigma_t, sigma_t, sigma_t}, {0, 0, 0}, g);
    EXPECT_EQ(testing::mean_luminance(render(s, testing::lower_or_die(""), o).image()), 0.0);
}

TEST(Medium, LightScattersIntoRaysAfterTheFirstToo) {
    // The small lamp of the test above, the camera turned to look along +z at a mirror
    // (reflectance R) one away: what the eye sees is the light scattered into its own ray up to
    // the mirror, and R exp(-sigma_t) times that scattered into the reflected ray, which passes
    // the lamp at 0.5 (RADIANCE scatters into every ray). Before the reflected ray scattered
    // too, the image held the first term only, a sixth of the sum.
    const double sigma_t = 0.4, albedo = 0.8, g = 0.3, L = 50, a = 0.01, hl = 0.5, zl = 2, R = 0.9, m = 1;
    Scene s = small_lamp_beside_the_view(L, a, hl, zl);
    s.camera.direction = {0, 0, 1};
    s.materials.push_back(testing::make_material("mirror", MaterialType::kMirror, {R, R, R}));
    s.shapes.push_back(testing::quad("mirror", {-5, 5, m}, {5, 5, m}, {5, -5, m}, {-5, -5, m}));  // facing -z
    s.medium = mist({sigma_t, sigma_t, sigma_t}, {albedo, albedo, albedo}, g);
    RunSettings o = single_scatter_settings();
    o.spp = 256;
    const double I = L * kPi * a * a, sigma_s = sigma_t * albedo;
    const Vec3 light{0, hl, -zl};
    const double eye = scatter_along({0, 0, 0}, {0, 0, 1}, m, light, I, sigma_t, sigma_s, g);
    const double reflected = R * std::exp(-sigma_t * m) * scatter_along({0, 0, m}, {0, 0, -1}, INFINITY, light, I, sigma_t, sigma_s, g);
    ASSERT_GT(reflected, 4 * eye) << eye << " " << reflected;
    // 8 x 8 x 256 reflected rays of one equiangular sample each: a standard error near 0.3 %.
    EXPECT_NEAR(testing::mean_luminance(render(s, testing::lower_or_die("M"), o).image()) / (eye + reflected), 1.0, 0.015);
}

TEST(Medium, TheCachesHemisphereRaysGatherTheFogsGlowAsPathTracingDoes) {
    // A small lamp in a fogged closed box (the furnace's, its walls not glowing): the cache with
    // one bounce and path tracing whose D rays stop at depth 1 estimate the same D AOV, the
    // lamp's light off the walls and (most of it) the light scattered once into the rays the
    // surfaces send out. Before the cache's hemisphere rays gathered the latter, its D AOV was
    // the former alone.
    Scene s = testing::furnace_box(0.5, 0);  // the closed box [-1, 1]^3, y up
    s.materials[0].emission.reset();
    s.materials.push_back(testing::make_material("lamp", MaterialType::kLight, {2000, 2000, 2000}));
    Shape lamp;
    lamp.type = ShapeType::kSphere;
    lamp.material = "lamp";
    lamp.center = {0, 0.4, 0};
    lamp.radius = 0.02;
    s.shapes.push_back(lamp);
    s.camera.position = {0, 0.9, 0.9};
    s.camera.direction = {0, -1, -1};
    s.camera.vfov_deg = 70;
    auto d_mean = [&](const RunSettings& o) {
        return testing::mean_luminance(render(s, testing::lower_or_die("(TTMRSGD)*"), o).film.aov_image(aov_of(Component::kD)));
    };
    RunSettings pt;
    pt.width = pt.height = 16;
    pt.spp = 512;
    pt.executor.shade.max_depth = 1;
    pt.executor.shade.roulette = false;
    RunSettings ic = pt;
    ic.spp = 4;
    IcSettings cache;
    cache.accuracy = 0.2, cache.divisions = 512, cache.bounces = 1;
    ic.irradiance_cache = cache;
    s.medium = mist({0.4, 0.4, 0.4}, {0, 0, 0}, 0.3);
    const double walls = d_mean(pt);
    s.medium = mist({0.4, 0.4, 0.4}, {0.9, 0.9, 0.9}, 0.3);
    const double gold = d_mean(pt);
    EXPECT_GT(gold, 1.5 * walls);  // measured 2.18x
    EXPECT_NEAR(d_mean(ic) / gold, 1.0, 0.04);  // measured 0.988 (0.992 at aa 0.1, 0.993 at 0.05)
}

TEST(Medium, ABoxOfMediumAttenuatesOnlyWhatCrossesIt) {
    // The wall of radiance 1 two away, the medium only in z in [-1.5, -0.5] (1 of the 2): each
    // channel is exp(-sigma_t); moved aside off the view, the box leaves the wall at 1.
    Scene s = wall_ahead();
    const Vec3 sigma{0.1, 0.5, 2.0};
    Medium m = mist(sigma, {0, 0, 0}, 0);
    m.bounded = true;
    m.box_min = {-3, -3, -1.5};
    m.box_max = {3, 3, -0.5};
    s.medium = m;
    std::vector<float> img = testing::render_crex(s, "", 8, 1).image();
    for (size_t p = 0; p < img.size() / 3; ++p)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(img[3 * p + c] / std::exp(-sigma[c]), 1.0, 4e-4) << "pixel " << p << " channel " << c;
    s.medium->box_min.x = 4, s.medium->box_max.x = 6;
    img = testing::render_crex(s, "", 8, 1).image();
    for (float v : img) EXPECT_FLOAT_EQ(v, 1.0f);
}

TEST(Medium, OnlyTheBoxScattersTheLampsLight) {
    // The small lamp of the single-scatter test, inside a box of medium that holds the camera
    // ray's part t in [1, 3] only: the quadrature over that part, each point seen through
    // exp(-sigma_t (t - 1)) and lit through exp(-sigma_t r) (the lamp is inside the box).
    const double sigma_t = 0.4, albedo = 0.8, g = 0.3, L = 50, a = 0.01, hl = 0.5, zl = 2;
    Scene s = small_lamp_beside_the_view(L, a, hl, zl);
    Medium m = mist({sigma_t, sigma_t, sigma_t}, {albedo, albedo, albedo}, g);
    m.bounded = true;
    m.box_min = {-2, -2, -3};
    m.box_max = {2, 2, -1};
    s.medium = m;
    const RunSettings o = single_scatter_settings();
    const double intensity = L * kPi * a * a;
    const int n = 400000;
    double expected = 0;
    for (int k = 0; k < n; ++k) {
        const double t = 1 + (k + 0.5) / n * 2, dt = 2.0 / n;
        const Vec3 to = Vec3{0, hl, -zl} - Vec3{0, 0, -t};
        const double r = length(to);
        expected += sigma_t * albedo * henyey_greenstein(dot(to / r, Vec3{0, 0, -1}), g) * intensity / (r * r) * std::exp(-sigma_t * (t - 1 + r)) * dt;
    }
    EXPECT_NEAR(testing::mean_luminance(render(s, testing::lower_or_die(""), o).image()) / expected, 1.0, 0.01);
}

}  // namespace
}  // namespace crex
