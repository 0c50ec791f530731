// Stiff and extreme scenes: every image finite (no NaN or Inf anywhere) and every render
// terminating.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "runtime/scene/load_scene.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

using testing::make_material;
using testing::quad;

TEST(ExtremeScenes, AlbedoNearOneEnclosureTerminates) {
    RunResult r = testing::render_crex(testing::furnace_box(0.999, 1.0), "D*", 8, 1);
    std::vector<float> img = r.image();
    ASSERT_TRUE(testing::all_finite(img));
    // Roulette keeps it unbiased until max_depth (256) truncates: at least the first 256 terms.
    double partial = (1 - std::pow(0.999, 256)) / 0.001;
    EXPECT_GT(testing::mean_luminance(img), 0.95 * partial);
    EXPECT_LE(r.stats.components[static_cast<size_t>(Component::kD)].executions, 256u);
}

TEST(ExtremeScenes, TinyAndHugeEmittersStayFinite) {
    for (double radiance : {1e-8, 1e8}) {
        Scene s = *builtin_scene("cornell");
        for (auto& m : s.materials)
            if (m.type == MaterialType::kLight) m.color = {radiance, radiance, radiance};
        std::vector<float> img = testing::render_crex(s, "(TTMRSGD)*", 16, 2).image();
        ASSERT_TRUE(testing::all_finite(img)) << radiance;
        EXPECT_GT(testing::mean_luminance(img), 0) << radiance;
    }
}

TEST(ExtremeScenes, SceneFarFromTheOriginRendersLikeTheSameSceneAtTheOrigin) {
    // Coordinates around 1e6 would lose 6 decimal digits in float; the renderer recentres the
    // scene first, so the image must match the one at the origin closely.
    Scene near = *builtin_scene("cornell_diffuse");
    Scene far = testing::shifted(near, {1e6, -1e6, 1e6});
    std::vector<float> a = testing::render_crex(near, "D*", 16, 2).image();
    std::vector<float> b = testing::render_crex(far, "D*", 16, 2).image();
    ASSERT_TRUE(testing::all_finite(b));
    EXPECT_NEAR(testing::mean_luminance(b) / testing::mean_luminance(a), 1.0, 0.02);
}

TEST(ExtremeScenes, ASceneAtAnyAcceptedScaleRendersAsAtUnitScale) {
    // Ray offsets floored at 1e-11 units (1e-5 of an extent floored at 1e-6): the box scaled by
    // 1e-11 lost all its direct light (mean 0.21 against 0.40, the lamp alone lit), by 1e-10 2 %.
    Scene unit = *builtin_scene("cornell");
    const double reference = testing::mean_luminance(testing::render_crex(unit, "(TTMRSGD)*", 16, 2).image());
    for (double k : {1e-11, 1e-7, 1e7}) {
        std::vector<float> img = testing::render_crex(testing::scaled(unit, k), "(TTMRSGD)*", 16, 2).image();
        ASSERT_TRUE(testing::all_finite(img)) << k;
        EXPECT_NEAR(testing::mean_luminance(img) / reference, 1.0, 0.01) << k;
    }
}

TEST(ExtremeScenes, ASmallObjectBesideAHugeOneKeepsItsOwnScale) {
    // A ground 2e6 units across, 1e4 below the box (the box sees it only through its open
    // front, far away): ray offsets of 1e-5 of the whole scene's extent were 28 units, every
    // shadow ray in the 2-unit box ended before it started and only the lamp was lit (red
    // mean 0.206 against 0.394 at 128x128, 16 spp). Offsets scale with each hit's own
    // coordinates and distance.
    Scene box = *builtin_scene("cornell");
    const double reference = testing::mean_luminance(testing::render_crex(box, "(TTMRSGD)*", 16, 2).image());
    Scene with_ground = box;
    with_ground.shapes.push_back(quad(box.shapes.front().material, {-1e6, -1e4, 1e6}, {1e6, -1e4, 1e6}, {1e6, -1e4, -1e6}, {-1e6, -1e4, -1e6}));
    std::vector<float> img = testing::render_crex(with_ground, "(TTMRSGD)*", 16, 2).image();
    ASSERT_TRUE(testing::all_finite(img));
    EXPECT_NEAR(testing::mean_luminance(img) / reference, 1.0, 0.02);
}

TEST(ExtremeScenes, DegenerateAndSliverTrianglesAreHarmless) {
    Scene s = testing::furnace_box(0.5, 0.2);
    Shape mesh;
    mesh.type = ShapeType::kMesh;
    mesh.material = "wall";
    mesh.vertices = {{-0.5, -0.5, -0.5}, {0.5, -0.5, -0.5}, {0.5, -0.5, -0.5}, {0, 0.5, -0.5}, {0.5, -0.5 + 1e-9, -0.5}};
    mesh.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}};  // zero area, fine, sliver
    s.shapes.push_back(mesh);
    std::vector<float> img = testing::render_crex(s, "D*", 16, 2).image();
    EXPECT_TRUE(testing::all_finite(img));
}

TEST(ExtremeScenes, GrazingAngleGlassStaysFinite) {
    Scene s;
    Material glass = make_material("glass", MaterialType::kDielectric, {1, 1, 1});
    glass.ior = 1.5;
    s.materials.push_back(glass);
    s.materials.push_back(make_material("lamp", MaterialType::kLight, {4, 4, 4}));
    s.materials.push_back(make_material("floor", MaterialType::kPlastic, {0.5, 0.5, 0.5}));
    s.shapes.push_back(quad("glass", {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}, {-10, 0, -10}));
    s.shapes.push_back(quad("floor", {-10, -1, 10}, {10, -1, 10}, {10, -1, -10}, {-10, -1, -10}));
    s.shapes.push_back(quad("lamp", {-1, 3, -1}, {1, 3, -1}, {1, 3, 1}, {-1, 3, 1}));
    s.camera.position = {0, 1e-4, 5};
    s.camera.direction = {0, -1e-5, -1};  // skimming the glass at about 89.999 degrees
    s.camera.vfov_deg = 2;
    RunResult r = testing::render_crex(s, "(TRD)*", 16, 2);
    EXPECT_TRUE(testing::all_finite(r.image()));
    for (size_t a = 0; a < kAovCount; ++a) EXPECT_TRUE(testing::all_finite(r.film.aov_image(a)));
}

TEST(Determinism, ImagesDoNotDependOnTheThreadCount) {
    Scene s = *builtin_scene("cornell");
    std::vector<float> one, two;
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
        one = testing::render_crex(s, "(TTMRSGD)*", 24, 2, 3).image();
    }
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
        two = testing::render_crex(s, "(TTMRSGD)*", 24, 2, 3).image();
    }
    EXPECT_EQ(one, two);
}

TEST(ProgressiveSampling, OneThenFifteenMoreIsExactlySixteen) {
    // Sample k of a pixel is the same whether drawn in a preview or later: the film sums of
    // samples [0, 1) and [1, 16) add up to those of a direct 16-sample render.
    Scene s = *builtin_scene("cornell_diffuse");
    sched::Program p = testing::lower_or_die("D*");
    RunSettings o;
    o.width = o.height = 12;
    o.spp = 16;
    RunResult all = render(s, p, o);
    o.spp = 1;
    RunResult first = render(s, p, o);
    o.first_sample = 1;
    o.spp = 15;
    RunResult rest = render(s, p, o);
    std::vector<float> a = all.image(), f = first.image(), r = rest.image();
    for (size_t i = 0; i < a.size(); ++i) ASSERT_NEAR(a[i], (f[i] + 15 * r[i]) / 16, 1e-5 * std::fabs(a[i]) + 1e-7) << i;
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(RenderExtreme, AZeroWeightLimitStillEndsGlassPaths) {
    // --lw 0 used to split glass into T and R at every interface without end (2^depth rays
    // until bad_alloc). Roulette now starts at 1e-4 of a camera ray's weight at the latest.
    Scene s = *builtin_scene("cornell");
    RunSettings o;
    o.width = o.height = 8;
    o.spp = 2;
    o.executor.shade.weight_limit = 0;
    RunResult r = render(s, testing::lower_or_die("(TTMRSGD)*"), o);
    uint64_t rays = total_rays(r.stats);
    EXPECT_LT(rays, uint64_t{200000}) << rays;  // about 30 rays per camera ray at lw 1e-3
    EXPECT_TRUE(testing::all_finite(r.image()));
    // The same mean as the default lw (both unbiased), within the noise of 128 samples.
    o.executor.shade.weight_limit = 1e-3;
    o.spp = 64;
    double with_default = testing::mean_luminance(render(s, testing::lower_or_die("(TTMRSGD)*"), o).image());
    o.executor.shade.weight_limit = 0;
    double with_zero = testing::mean_luminance(render(s, testing::lower_or_die("(TTMRSGD)*"), o).image());
    EXPECT_NEAR(with_zero, with_default, 0.05 * with_default);
}

}  // namespace
}  // namespace crex
