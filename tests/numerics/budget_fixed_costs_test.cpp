// A pipeline's preview and guidance inside its budget (issue 34): the preview sized from the
// stage costs a profile holds, a budget below the floor refused with the figure, and a
// strided preview that still leaves an image in every pixel. Time comes from an injected
// clock (the rays executed so far times 1 us), so every decision is deterministic.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/api/fixed_costs.h"
#include "runtime/api/run_options.h"
#include "runtime/api/run_outputs.h"
#include "runtime/driver/run_plan.h"
#include "runtime/pipeline/subsample.h"
#include "runtime/scene/census.h"
#include "runtime/scene/scene_builders.h"
#include "tests/support/fake_clock.h"
#include "tests/support/plan_helpers.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

using testing::FakeClock;

RunSettings with_clock(FakeClock& clock, Profile* profile, int w, int h) {
    RunSettings o;
    o.width = w, o.height = h;
    o.spp = 1;
    o.executor.clock = [&clock] { return clock.now(); };
    o.executor.progress = [&clock](const std::string&, uint64_t rays) { clock.rays = rays; };
    o.executor.profile = profile;
    return o;
}

using testing::plan_for;

// A `width` x `height` run under a budget of `seconds`, with a profile of a 4 s full render
// whose stages cost `stages`.
RunOptions budgeted_options(int width, int height, const StageCosts& stages, double seconds) {
    RunOptions o;
    o.width = width, o.height = height;
    ProfileInput profile;
    profile.full_render_seconds = 4;
    profile.stages = stages;
    o.profile = profile;
    PlanBudget budget;
    budget.amount = seconds;
    o.budget = budget;
    return o;
}

const char* kProgressive =
    "pipeline p {\n preselective { crex \"(TTMRSGD)*\" spp 1 }\n guidance { c = constant(0.5) }\n"
    " selective { vary spp 1 .. 4 by c }\n}\n";

TEST(FixedCosts, APreviewsSamplesAreItsGridsCorners) {
    for (auto [w, h] : {std::pair{1, 1}, {7, 5}, {32, 24}, {33, 17}, {128, 96}, {960, 540}})
        for (uint32_t k : {1u, 2u, 4u, 8u}) {
            const SubsampleGrid grid(w, h, std::vector<double>(static_cast<size_t>(w) * static_cast<size_t>(h), k));
            EXPECT_EQ(preview_samples_at(w, h, 1, k), grid.rendered_count()) << w << "x" << h << " every " << k;
            EXPECT_EQ(preview_samples_at(w, h, 3, k), 3 * grid.rendered_count());
        }
}

TEST(FixedCosts, TheFloorIsTheCoarsestPreviewAndGuidanceAtTheProfilesCosts) {
    const int w = 128, h = 96;
    const StageCosts stages{1.0, uint64_t{w} * h, 0.05, uint64_t{w} * h};  // 1 s for a preview of every pixel
    const FixedCosts c = *predict_fixed_costs(stages, w, h, 1);
    EXPECT_NEAR(c.coarsest_preview_seconds, double(preview_samples_at(w, h, 1, kCoarsestPreviewStride)) / double(w * h), 1e-12);
    EXPECT_NEAR(c.guidance_seconds, 0.05, 1e-12);
    EXPECT_NEAR(c.predicted_seconds, c.coarsest_preview_seconds + 0.05, 1e-12);
    // The floor leaves room for the fixed costs to run long, as they do from run to run.
    EXPECT_NEAR(c.floor_seconds, (1 + kFixedCostSpread) * c.predicted_seconds, 1e-12);
    // Another size: guidance scales with the pixels, the preview with its samples.
    const FixedCosts big = *predict_fixed_costs(stages, 2 * w, 2 * h, 2);
    EXPECT_NEAR(big.guidance_seconds, 0.2, 1e-12);
    EXPECT_NEAR(big.coarsest_preview_seconds, 2.0 * double(preview_samples_at(2 * w, 2 * h, 1, 8)) / double(w * h), 1e-12);
    // No stage costs (a plain crex's profile, or an older one): no floor is known.
    EXPECT_FALSE(predict_fixed_costs(StageCosts{}, w, h, 1));
    // The render's end after its last stage is in the floor too, and goes with the pixels.
    StageCosts with_end = stages;
    with_end.end_seconds = 0.01;
    EXPECT_NEAR(predict_fixed_costs(with_end, w, h, 1)->predicted_seconds, c.predicted_seconds + 0.01, 1e-12);
    EXPECT_NEAR(predict_fixed_costs(with_end, 2 * w, 2 * h, 2)->end_seconds, 0.04, 1e-12);
    // So is a strided preview's work per pixel of the frame, in its coarsest preview.
    StageCosts with_bookkeeping = stages;
    with_bookkeeping.strided_preview_seconds = 0.003;
    EXPECT_NEAR(predict_fixed_costs(with_bookkeeping, 2 * w, 2 * h, 2)->coarsest_preview_seconds,
                big.coarsest_preview_seconds + 4 * 0.003, 1e-12);
}

// With an irradiance cache a sparse preview pays its caustic map whole and a record for each of
// its samples (up to the full preview's records), not the full preview's cost per sample.
TEST(FixedCosts, ACachedPreviewPaysItsMapAndARecordASample) {
    const int w = 128, h = 96;
    const uint64_t n = preview_samples_at(w, h, 1, kCoarsestPreviewStride);
    // 1 s for every pixel: 0.2 s the caustic map, 0.6 s 2,000 records, 0.2 s the rest.
    StageCosts stages{1.0, uint64_t{w} * h, 0.05, uint64_t{w} * h, 0.2, 2000, 0.6};
    const FixedCosts c = *predict_fixed_costs(stages, w, h, 1);
    const double expected = 0.2 + 0.2 / double(w * h) * double(n) + 0.6 / 2000 * double(std::min<uint64_t>(n, 2000));
    EXPECT_NEAR(c.coarsest_preview_seconds, expected, 1e-12);
    const double per_sample_alone = 1.0 / double(w * h) * double(n);  // what the old prediction said
    EXPECT_GT(c.coarsest_preview_seconds, 2 * per_sample_alone);
    // Fewer records than sparse samples: each is paid once.
    stages.preview_records = 10;
    EXPECT_NEAR(predict_fixed_costs(stages, w, h, 1)->coarsest_preview_seconds, 0.2 + 0.2 / double(w * h) * double(n) + 0.6, 1e-12);
    // Parts that add up to more than the preview (a damaged profile) are clamped to it.
    stages.preview_fixed_seconds = 5, stages.preview_record_seconds = 5;
    EXPECT_NEAR(predict_fixed_costs(stages, w, h, 1)->coarsest_preview_seconds, 1.0, 1e-12);
}

TEST(FixedCosts, ASavedProfileKeepsTheCachesPreviewCosts) {
    const StageCosts stages{1.5, 1000, 0.05, 1000, 0.25, 300, 0.75, 0.125, 0.0625};
    Profile profile, back;
    double full = 0;
    StageCosts read;
    ASSERT_EQ(Profile::from_json_text(profile_json_text(profile, 4.0, stages), back, &full, "p.json", &read), "");
    EXPECT_EQ(full, 4.0);
    EXPECT_EQ(read.preview_fixed_seconds, 0.25);
    EXPECT_EQ(read.preview_records, 300u);
    EXPECT_EQ(read.preview_record_seconds, 0.75);
    EXPECT_EQ(read.end_seconds, 0.125);
    EXPECT_EQ(read.strided_preview_seconds, 0.0625);
    // A profile saved before them reads as no cache: the floor is the cost per sample alone.
    StageCosts old;
    ASSERT_EQ(Profile::from_json_text(R"({"format": "crex-profile", "version": 1, "seconds_per_ray": {}, "full_render_seconds": 4,
        "stages": {"preview_seconds": 1.5, "preview_samples": 1000, "guidance_seconds": 0.05, "pixels": 1000}})", back, &full, "p.json", &old), "");
    EXPECT_EQ(old.preview_records, 0u);
    EXPECT_EQ(old.preview_fixed_seconds, 0.0);
    EXPECT_EQ(old.end_seconds, 0.0);
    EXPECT_EQ(old.strided_preview_seconds, 0.0);
}

// A full render whose profile is saved times a strided preview's bookkeeping after its clock
// stopped, on copies: the image and the render's time are those of a run that does not.
TEST(FixedCosts, AProfiledFullRenderTimesAStridedPreviewWithoutTouchingTheImage) {
    Scene scene = *builtin_scene("cornell");
    PipelinePlan plan = plan_for(kProgressive, scene);
    RunOptions o;
    o.width = 40, o.height = 24;
    EXPECT_FALSE(resolve_run(plan, o).settings.time_strided_preview);
    o.saves_profile = true;
    EXPECT_TRUE(resolve_run(plan, o).settings.time_strided_preview);
    const RunResult plain = run_plan(scene, plan, [&] {
        RunSettings s = resolve_run(plan, o).settings;
        s.time_strided_preview = false;
        return s;
    }());
    const RunResult timed = run_plan(scene, plan, resolve_run(plan, o).settings);
    EXPECT_EQ(plain.strided_preview_seconds, 0.0);
    EXPECT_GT(timed.strided_preview_seconds, 0.0);
    EXPECT_EQ(timed.image(), plain.image());
    EXPECT_GT(measured_stage_costs(timed, 40, 24).strided_preview_seconds, 0.0);
    // So is the end a budgeted render of the frame would have (every component's light left
    // standing in), which the profile keeps as the end instead of the full render's own.
    if (timed.budgeted_end_seconds > 0) {
        EXPECT_EQ(plain.budgeted_end_seconds, 0.0);
        EXPECT_EQ(measured_stage_costs(timed, 40, 24).end_seconds, timed.budgeted_end_seconds);
        EXPECT_EQ(measured_stage_costs(plain, 40, 24).end_seconds, plain.end_seconds);
    } else {
        ADD_FAILURE() << "a profiled full render with automatic stand-ins timed no budgeted end";
    }
    // Under a budget nothing is timed: the budget's own preview is what it is.
    o.budget = PlanBudget{};
    o.budget->amount = 10;
    EXPECT_FALSE(resolve_run(plan, o).settings.time_strided_preview);
}

// The stand-ins and warnings after the last stage are on the clock: the stages stop early by
// what the profile predicts for them, so the run as a whole ends on its budget (a fixed 3-6 ms
// there was most of the overshoot of budgets near 0.05 s).
TEST(FixedCosts, TheStagesStopEarlyByTheRendersPredictedEnd) {
    Scene scene = *builtin_scene("cornell");
    PipelinePlan plan = plan_for(kProgressive, scene);
    StageCosts stages{0.01, 48 * 32, 0.001, 48 * 32};
    stages.end_seconds = 0.02;
    RunOptions o = budgeted_options(48, 32, stages, 1.0);
    EXPECT_NEAR(resolve_run(plan, o).settings.end_seconds, 0.02, 1e-12);
    o.budget->amount = 0.03;  // at most half the budget is kept back
    o.budget_floor_ok = true;
    EXPECT_NEAR(resolve_run(plan, o).settings.end_seconds, 0.015, 1e-12);

    // Under an injected clock (rays x 1 us) the end costs nothing: the run ends where its
    // stages stopped, the budget less the end kept back.
    FakeClock c1;
    Profile costs;
    const RunResult full = run_plan(scene, plan, with_clock(c1, &costs, 48, 32));
    const double b = 0.5 * full.render_seconds;
    for (const double end : {0.0, 0.3 * b}) {
        FakeClock c2;
        RunSettings cut = with_clock(c2, &costs, 48, 32);
        cut.executor.budget_seconds = b;
        cut.preview_stride = 0;
        cut.end_seconds = end;
        const RunResult r = run_plan(scene, plan, cut);
        EXPECT_LE(r.render_seconds, 1.02 * (b - end)) << end;
        EXPECT_GE(r.render_seconds, 0.9 * (b - end)) << end;
        EXPECT_GE(r.end_seconds, 0.0);
    }
}

TEST(FixedCosts, ABudgetBelowThePipelinesFloorIsRefusedNamingTheFloor) {
    Scene scene = *builtin_scene("cornell");
    PipelinePlan plan = plan_for(kProgressive, scene);
    // 0.04 s is below the floor: the coarsest preview (~0.02 s) and guidance (0.05 s).
    RunOptions o = budgeted_options(128, 96, {1.0, 128 * 96, 0.05, 128 * 96}, 0.04);
    const double floor = predict_fixed_costs(o.profile->stages, 128, 96, 1)->floor_seconds;
    try {
        resolve_run(plan, o);
        FAIL() << "a budget below the floor was not refused";
    } catch (const BudgetBelowFloor& e) {
        EXPECT_NEAR(e.floor_seconds, floor, 1e-12);
        EXPECT_NE(std::string(e.what()).find(fmt::format("{:.3g} s", floor)), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("--budget-floor ok"), std::string::npos) << e.what();
    }
    // Above the prediction but within the fixed costs' spread: refused too (nothing is left to
    // cut when they run long).
    const double predicted = predict_fixed_costs(o.profile->stages, 128, 96, 1)->predicted_seconds;
    o.budget->amount = 1.2 * predicted;
    EXPECT_THROW(resolve_run(plan, o), BudgetBelowFloor);
    o.budget->amount = 0.04;
    // Asked to render anyway: the run knows its budget is broken; its preview goes coarse to fine.
    o.budget_floor_ok = true;
    ResolvedRun run = resolve_run(plan, o);
    EXPECT_TRUE(run.below_floor);
    EXPECT_EQ(run.settings.preview_stride, 0u);
    // A budget at the floor is met: no refusal, nothing broken.
    o.budget_floor_ok = false;
    o.budget->amount = floor * 1.01;
    EXPECT_FALSE(resolve_run(plan, o).below_floor);
    // Without a budget the preview renders every pixel, whatever the profile says.
    o.budget.reset();
    EXPECT_EQ(resolve_run(plan, o).settings.preview_stride, 1u);
}

// The cache's caustic map is scene set-up, as the BVH and path tracing's map are: built before
// the clock (the photons do not depend on the camera), so a budget does not pay it and the
// floor holds no fixed part for it. The image is the one a map carried in gives.
TEST(FixedCosts, TheCachesCausticMapIsBuiltBeforeTheClock) {
    Scene scene = *builtin_scene("cornell");  // a glass sphere: the map has photons
    PipelinePlan plan = plan_for(kProgressive, scene);
    RunSettings s;
    s.width = 24, s.height = 16;
    IcSettings ic;
    ic.divisions = 16, ic.bounces = 1, ic.caustic_photons = 4000;
    s.irradiance_cache = ic;
    const RunResult built = run_plan(scene, plan, s);
    ASSERT_TRUE(built.caustic_map);
    EXPECT_GT(built.caustic_map->size(), 0u);
    EXPECT_GT(built.caustic_map_seconds, 0.0);
    EXPECT_GE(built.setup_seconds, built.caustic_map_seconds);
    EXPECT_EQ(built.ic_stats.caustic_seconds, 0.0) << "nothing of the map on the render's clock";
    EXPECT_EQ(measured_stage_costs(built, 24, 16).preview_fixed_seconds, 0.0);
    RunSettings carried = s;
    carried.caustic_map = built.caustic_map;
    const RunResult again = run_plan(scene, plan, carried);
    EXPECT_EQ(again.caustic_map_seconds, 0.0) << "a map carried in is not built";
    EXPECT_EQ(again.image(), built.image());
}

// A scene whose caustic paths all miss (a glass ball under a lamp, nothing for its light to
// land on) builds an empty map; carried to the next frame it is not built again, and the image
// is the one without a map. The living room's windows traced 200,000 photons for none at every
// frame of a walk, 2-3 % of a later frame.
TEST(FixedCosts, AnEmptyCausticMapIsCarriedAndNotBuiltAgain) {
    Scene scene = *builtin_scene("cornell");
    std::erase_if(scene.shapes, [](const Shape& s) { return s.name != "light" && s.name != "glass_ball"; });
    // A speck of diffuse surface far above, so that path tracing has D rays (and a map to build).
    scene.shapes.push_back(build::quad("white", {0, 50, 0}, {0.01, 50, 0}, {0.01, 50, 0.01}, {0, 50, 0.01}, "speck"));
    PipelinePlan plan = plan_for(kProgressive, scene);
    RunSettings s;
    s.width = 24, s.height = 16;
    IcSettings ic;
    ic.divisions = 16, ic.bounces = 1, ic.caustic_photons = 4000;
    for (const bool cached : {true, false}) {
        SCOPED_TRACE(cached ? "the cache's map" : "path tracing's map");
        RunSettings with = s;
        if (cached) with.irradiance_cache = ic;
        else with.caustic_photons = 4000;
        RunSettings without = with;
        if (cached) without.irradiance_cache->caustic_photons = 0;
        else without.caustic_photons = 0;
        const RunResult built = run_plan(scene, plan, with);
        ASSERT_TRUE(built.caustic_map) << "built, though empty";
        EXPECT_TRUE(built.caustic_map->empty());
        EXPECT_GT(built.caustic_map->rays(), 0u) << "its photons were traced";
        EXPECT_GT(built.caustic_map_seconds, 0.0);
        EXPECT_EQ(built.image(), run_plan(scene, plan, without).image()) << "an empty map is no map";
        RunSettings carried = with;
        carried.caustic_map = built.caustic_map;
        const RunResult again = run_plan(scene, plan, carried);
        EXPECT_EQ(again.caustic_map_seconds, 0.0) << "an empty map carried in is not built again";
        EXPECT_EQ(again.caustic_map, built.caustic_map);
        EXPECT_EQ(again.image(), built.image());
    }
}

TEST(StridedPreview, RendersTheCornersOnlyAndGuidanceSeesTheRestInterpolated) {
    Scene scene = *builtin_scene("cornell");
    PipelinePlan plan = plan_for(kProgressive, scene);
    FakeClock clock;
    Profile profile;
    RunSettings s = with_clock(clock, &profile, 33, 17);
    s.preview_stride = 4;
    const RunResult r = run_plan(scene, plan, s);
    const SubsampleGrid grid(33, 17, std::vector<double>(33 * 17, 4.0));
    EXPECT_EQ(r.preview_samples, grid.rendered_count());
    EXPECT_EQ(r.preview_stride, 4u);
    EXPECT_FALSE(r.preview_grid) << "every pixel was rendered: nothing is left to interpolate";
    // The preview guidance saw: every pixel between corners is the bilinear mix of its square's.
    std::vector<float> corners_only = r.preview;
    grid.fill(corners_only);
    for (size_t i = 0; i < r.preview.size(); ++i) ASSERT_NEAR(r.preview[i], corners_only[i], 1e-5f * std::max(1.0f, corners_only[i])) << i;
    // No budget: the selective stage rendered every pixel the preview left out, at least once.
    for (uint32_t p = 0; p < r.film.pixel_count(); ++p) ASSERT_GE(r.film.samples(p), 1u) << p;
}

TEST(StridedPreview, UnderABudgetThePreviewGoesCoarseToFineWithinItsShare) {
    Scene scene = *builtin_scene("cornell");
    PipelinePlan plan = plan_for(kProgressive, scene);
    const int w = 48, h = 32;
    FakeClock c1;
    Profile profile;
    const RunResult full = run_plan(scene, plan, with_clock(c1, &profile, w, h));
    ASSERT_GT(full.preview_seconds, 0.0);
    // The same cost per sample at every level (the clock counts rays, no cache): a budget whose
    // share is a third of the full preview stops after every 2nd pixel (a quarter of them and
    // the edges), and one whose share is 1.5 of it renders every pixel.
    for (const auto& [share_of_preview, stride] : {std::pair{0.35, 2u}, {1.5, 1u}, {0.02, 8u}}) {
        const double budget = full.preview_seconds * share_of_preview / kPreviewShare;
        FakeClock c2;
        RunSettings cut = with_clock(c2, &profile, w, h);
        cut.executor.budget_seconds = budget;
        cut.preview_stride = 0;
        const RunResult r = run_plan(scene, plan, cut);
        EXPECT_EQ(r.preview_stride, stride) << share_of_preview;
        EXPECT_EQ(r.preview_samples, preview_samples_at(w, h, 1, stride));
        // Within its share, except the coarsest level, which always runs.
        if (stride < kCoarsestPreviewStride) {
            EXPECT_LE(r.preview_seconds, kPreviewShare * budget * 1.0001) << share_of_preview;
        }
        EXPECT_LE(r.render_seconds, 1.02 * budget) << share_of_preview;
        if (share_of_preview == 0.02) {
            // The selective stage went on coarse to fine over the whole image: every 4th pixel
            // everywhere, and the budget ended among every 2nd, not at a row of the 8-grid.
            ASSERT_TRUE(r.preview_grid);
            const SubsampleGrid fourth(w, h, std::vector<double>(size_t{w} * h, 4.0));
            for (uint32_t p = 0; p < r.film.pixel_count(); ++p) {
                if (!fourth.rendered(p)) continue;
                ASSERT_GE(r.film.samples(p), 1u) << p;
            }
            EXPECT_GT(r.budget_stopped_samples, 0u);
        }
        // An image in every pixel: the ones the budget left without samples are interpolated,
        // so one is black only beside a sampled pixel that is (one sample of the box can be
        // black: a path that found no light), never for lack of work.
        const std::vector<float> img = r.image();
        auto dark = [&](uint32_t p) { return img[3 * p] + img[3 * p + 1] + img[3 * p + 2] <= 0; };
        for (uint32_t p = 0; p < r.film.pixel_count(); ++p) {
            ASSERT_TRUE(std::isfinite(img[3 * p] + img[3 * p + 1] + img[3 * p + 2])) << p;
            if (r.film.samples(p) > 0 || !dark(p)) continue;
            const int x = static_cast<int>(p % w), y = static_cast<int>(p / w);
            bool beside_dark_sample = false;
            for (int qy = std::max(0, y - 8); qy < std::min(h, y + 9); ++qy)
                for (int qx = std::max(0, x - 8); qx < std::min(w, x + 9); ++qx) {
                    const auto q = static_cast<uint32_t>(qy * w + qx);
                    beside_dark_sample = beside_dark_sample || (r.film.samples(q) > 0 && dark(q));
                }
            EXPECT_TRUE(beside_dark_sample) << "pixel (" << x << ", " << y << ") black without samples, share " << share_of_preview;
        }
    }
}

TEST(ModulatedSteps, AComponentTheMapNeverReachesIsW405NamingTheMap) {
    // {TTMRSGD}2 by a map of 0.5: occurrences 5-7 (S, G, D) need more than 4/7 and never run.
    Scene scene = *builtin_scene("cornell");
    PipelinePlan plan = plan_for("pipeline p {\n preselective { crex \"TT\" spp 1 }\n guidance { half = constant(0.5) }\n"
                                 " selective { crex \"{TTMRSGD}2\" by half }\n}\n",
                                 scene);
    RunSettings s;
    s.width = s.height = 16;
    const RunResult r = run_plan(scene, plan, s);
    std::vector<std::string> w405;
    for (const auto& w : r.warnings)
        if (w.code == "W405") w405.push_back(w.message);
    ASSERT_FALSE(w405.empty());
    bool d_named = false;
    for (const auto& w : w405) {
        EXPECT_NE(w.find("'half'"), std::string::npos) << w;
        EXPECT_NE(w.find("at most 0.500"), std::string::npos) << w;
        d_named |= w.find("D inside") != std::string::npos && w.find("occurrence 7 of 7") != std::string::npos;
        EXPECT_EQ(w.find("T inside"), std::string::npos) << "T ran: " << w;
    }
    EXPECT_TRUE(d_named);
}

}  // namespace
}  // namespace crex
