// Direct light from a sphere lamp against the closed form (issue 16): a diffuse floor under a
// sphere of radiance L and radius r whose centre is h above it receives E = pi L (r / h)^2
// directly below the centre, so the floor's radiance there is rho L (r / h)^2. Checked with
// the ray epsilon much smaller than the sphere (a small scene around a big lamp, and the same
// at 1e-3 and 1e3 scale) and much larger relative to it (a small lamp in a big scene).
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/base/sampling.h"
#include "runtime/render/render_scene.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

Scene sphere_light_over_plane(double rho, double L, double r, double h, double floor_half, double scale) {
    Scene s;
    s.materials.push_back(testing::make_material("floor", MaterialType::kPlastic, {rho, rho, rho}));
    s.materials.push_back(testing::make_material("lamp", MaterialType::kLight, {L, L, L}));
    const double w = floor_half * scale;
    s.shapes.push_back(testing::quad("floor", {-w, 0, w}, {w, 0, w}, {w, 0, -w}, {-w, 0, -w}));
    Shape lamp;
    lamp.type = ShapeType::kSphere;
    lamp.material = "lamp";
    lamp.center = {0, h * scale, 0};
    lamp.radius = r * scale;
    s.shapes.push_back(lamp);
    s.camera.position = {0, (h - r) * scale / 2, 0};  // between the floor and the lamp
    s.camera.direction = {0, -1, 0};
    s.camera.up = {0, 0, -1};
    s.camera.vfov_deg = 1;
    return s;
}

struct Case {
    double r, floor_half, scale;
};

class SphereLight : public ::testing::TestWithParam<Case> {};

TEST_P(SphereLight, FloorUnderTheLampMatchesTheClosedForm) {
    const double rho = 0.5, L = 4.0, h = 1.0;
    const Case c = GetParam();
    Scene s = sphere_light_over_plane(rho, L, c.r, h, c.floor_half, c.scale);
    // Camera rays only (empty crex): the image is the direct light at the floor. 128 x 128
    // pixels at 64 spp: a million light samples, about 0.2 % standard error of the mean, and
    // low-discrepancy. Before the fix the big lamp's cases measured 0.978; an exact shadow
    // test (rays ended at 0.9 of the distance) 0.9989, 0.9999 and 0.9953.
    RunResult img = testing::render_crex(s, "", 128, 64, 0, 1);
    double expected = rho * L * (c.r / h) * (c.r / h);
    EXPECT_NEAR(testing::mean_luminance(img.image()) / expected, 1.0, 0.007)
        << "r " << c.r << ", floor half-width " << c.floor_half << ", scale " << c.scale;
}

INSTANTIATE_TEST_SUITE_P(EpsilonAgainstTheSphere, SphereLight,
                         ::testing::Values(Case{0.3, 2, 1}, Case{0.3, 2, 1e-3}, Case{0.3, 2, 1e3},  // epsilon << sphere
                                           Case{0.05, 2, 1}, Case{0.05, 2000, 1}),                  // small lamp, small or big scene
                         [](const auto& p) { return "case" + std::to_string(p.index); });

TEST(SphereLight, ASampleSeenFromAPointLiesOnTheSideItSeesAndEstimatesItsIrradiance) {
    // Seen from a point of the floor under the lamp, a sample is uniform in the cone the sphere
    // fills, so none falls on its far side, and each sample's estimate of the irradiance,
    // L cos_x / pdf per steradian, varies only with the floor's cosine: area sampling over the
    // whole sphere gave half its samples nothing (a relative spread above 1).
    const double rho = 0.5, L = 4.0, r = 0.3, h = 1.0;
    Scene s = sphere_light_over_plane(rho, L, r, h, 2, 1);
    RenderScene rs(s);
    const Vec3 x = Vec3{0, 0, 0} - rs.embree->origin_offset(), up{0, 1, 0};
    const LightSampler::LocalWeights weights = rs.lights->weights_at(x);
    const int n = 4096;
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        double u, v;
        rotated_halton(static_cast<uint32_t>(i), 0.25, 0.5, u, v);
        const LightSample ls = rs.lights->sample(weights, 0.5, u, v);
        ASSERT_GT(ls.pdf_area, 0.0);
        const Vec3 to = ls.position - x;
        const double d2 = dot(to, to), d = std::sqrt(d2);
        const Vec3 wi = to / d;
        const double cos_l = -dot(ls.normal, wi), cos_x = dot(up, wi);
        ASSERT_GT(cos_l, 0.0) << "sample " << i << " on the far side";
        const double e = ls.radiance.x * cos_x * cos_l / (d2 * ls.pdf_area);
        sum += e, sum2 += e * e;
    }
    const double mean = sum / n, spread = std::sqrt(std::fmax(0.0, sum2 / n - mean * mean)) / mean;
    EXPECT_NEAR(mean / (kPi * L * (r / h) * (r / h)), 1.0, 0.01);
    EXPECT_LT(spread, 0.1);
}

}  // namespace
}  // namespace crex
