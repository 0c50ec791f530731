// Running pipelines: the svt per pixel, progressive continuation of the preview, `{ }` by a
// map, and every runnable stdlib pipeline on both example scenes (issue 6).
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/driver/run_plan.h"
#include "runtime/scene/census.h"
#include "tests/support/plan_helpers.h"
#include "tests/support/scene_helpers.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

Scene load(const std::string& spec) {
    if (spec.rfind("builtin:", 0) == 0) return *builtin_scene(spec.substr(8));
    auto r = testing::load_path(spec);
    if (!r.scene) throw std::runtime_error("cannot load " + spec);
    return *r.scene;
}

using testing::plan_for;

RunResult run(const Scene& scene, const PipelinePlan& plan, int w, int h, uint32_t preview_spp = 1) {
    RunSettings o;
    o.width = w, o.height = h;
    o.spp = preview_spp;
    return run_plan(scene, plan, o);
}

const guidance::Raster& map_named(const RunResult& r, const std::string& name) {
    for (const auto& [n, m] : r.maps)
        if (n == name) return m;
    throw std::runtime_error("no map " + name);
}

TEST(PipelineRun, RaisingSppContinuesThePreviewsSequenceExactly) {
    // A preview of 1 spp raised to 5 everywhere uses exactly the samples of a direct 5-spp render.
    Scene scene = load("builtin:cornell");
    auto plan = plan_for("pipeline p {\n preselective { crex \"(TTMRSGD)*\" spp 1 }\n guidance { c = constant(0.5) }\n"
                         " selective { vary spp 1 .. 9 by c }\n}\n",
                         scene);
    auto piped = run(scene, plan, 20, 16);
    RunSettings ro;
    ro.width = 20, ro.height = 16, ro.spp = 5;
    auto direct = render(scene, plan.program, ro);
    auto a = piped.image(), b = direct.image();
    for (uint32_t p = 0; p < piped.film.pixel_count(); ++p) ASSERT_EQ(piped.film.samples(p), 5u);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) ASSERT_NEAR(a[i], b[i], 1e-5 * std::max(1.0f, std::fabs(b[i]))) << i;
    // The preview's camera rays were traced once: 1 + 4 per pixel in all.
    EXPECT_EQ(piped.stats.camera.rays, 5u * 20 * 16);
}

TEST(PipelineRun, EachPixelGetsTheSppItsMapAsksFor) {
    Scene scene = load("builtin:cornell");
    auto plan = plan_for(testing::read_text(CREX_SOURCE_DIR "/stdlib/pipelines/sel_rp.pipe"), scene);
    auto r = run(scene, plan, 32, 32);
    const auto& sal = map_named(r, "sal");
    size_t differing = 0;
    for (uint32_t p = 0; p < r.film.pixel_count(); ++p) {
        uint32_t want = static_cast<uint32_t>(std::round(1 + 15 * static_cast<double>(sal.v[p])));
        ASSERT_EQ(r.film.samples(p), want) << "pixel " << p;
        differing += want != 16;
    }
    EXPECT_GT(differing, 100u);  // selective: most pixels get fewer than the maximum
}

TEST(PipelineRun, SelectiveHitsCastTheirPixelsShadowRays) {
    Scene scene = load("builtin:cornell_diffuse");
    auto text = [](const std::string& vary) {
        return "pipeline p {\n preselective { spp 1 }\n guidance { c = constant(1) }\n selective { " + vary + " }\n}\n";
    };
    auto preview = run(scene, plan_for(text("vary spp 1 .. 1 by c"), scene), 16, 16);
    auto more = run(scene, plan_for(text("vary spp 1 .. 2 by c"), scene), 16, 16);
    auto four = run(scene, plan_for(text("vary spp 1 .. 2 by c  vary shadow_rays 4 .. 4 by c"), scene), 16, 16);
    uint64_t c = preview.stats.camera.shadow_rays, a = more.stats.camera.shadow_rays;
    ASSERT_GT(a, c);
    // Every selective hit casts 4 instead of 1; a light sample that lands behind the emitter
    // or behind the surface (a box's side, with the lamp partly behind its plane) casts none.
    // The 4 are other points of the pixel's light sequence than the 1 (LightSampling), so how
    // many of them land there differs by a few hits: 1.7 % here.
    double expect = static_cast<double>(c + 4 * (a - c)), got = static_cast<double>(four.stats.camera.shadow_rays);
    EXPECT_NEAR(got, expect, 0.03 * 4 * static_cast<double>(a - c));
}

TEST(PipelineRun, OnlySurfacesTheCameraSeesCastThePixelsShadowRays) {
    // The camera's hits and what it sees in the mirror ball take the pixel's 4 shadow rays;
    // the hits of diffuse bounces take one, so they cast as many as at 1 (the paths are the
    // same: scattering does not draw on the light samples' random numbers).
    Scene scene = load("builtin:cornell");
    const sched::Program program = plan_for("pipeline p {\n preselective { crex \"(TTMRSGD)*\" spp 1 }\n}\n", scene).program;
    RunSettings ro;
    ro.width = 24, ro.height = 24, ro.spp = 2;
    auto one = render(scene, program, ro);
    ro.executor.shade.shadow_rays = 4;
    auto four = render(scene, program, ro);
    auto of = [](const RunResult& r, Component c) { return r.stats.components[static_cast<size_t>(c)].shadow_rays; };
    const double camera1 = static_cast<double>(one.stats.camera.shadow_rays);
    ASSERT_GT(camera1, 500);
    EXPECT_NEAR(static_cast<double>(four.stats.camera.shadow_rays), 4 * camera1, 0.01 * 4 * camera1);
    ASSERT_GT(of(one, Component::kD), 100u);
    EXPECT_EQ(of(four, Component::kD), of(one, Component::kD));
    // Mirror hits: those from a camera hit are seen (4), most come after a diffuse bounce (1).
    EXPECT_GT(of(four, Component::kM), of(one, Component::kM) + 30);
    EXPECT_LT(of(four, Component::kM), 4 * of(one, Component::kM));
}

TEST(PipelineRun, ThePreviewsSamplesGetTheirPixelsShadowRaysToo) {
    // Progressive direct light (thesis 8.2): the preview's kept samples have their camera-hit
    // direct light estimated again with the pixel's shadow_rays. With no new sample, the camera
    // AOV (emission and direct light at camera hits) is then that of a render with 8 shadow rays.
    Scene scene = load("builtin:cornell");
    auto text = [](const std::string& value) {
        return "pipeline p {\n preselective { crex \"(TTMRSGD)*\" spp 2 }\n guidance { c = constant(" + value +
               ") }\n selective { vary shadow_rays 1 .. 8 by c }\n}\n";
    };
    auto eight = run(scene, plan_for(text("1"), scene), 20, 16, 2);
    auto one = run(scene, plan_for(text("0"), scene), 20, 16, 2);
    RunSettings ro;
    ro.width = 20, ro.height = 16, ro.spp = 2;
    const sched::Program program = plan_for(text("1"), scene).program;
    auto plain = render(scene, program, ro);
    ro.executor.shade.shadow_rays = 8;
    auto plain8 = render(scene, program, ro);
    EXPECT_EQ(one.direct_light_redone, 0u);  // nobody asked for more than the preview's one
    EXPECT_EQ(eight.direct_light_redone, 2u * 20 * 16);
    EXPECT_GT(eight.direct_light_redone_shadow_rays, 2u * 20 * 16);
    auto near_all = [](const std::vector<float>& a, const std::vector<float>& b) {
        ASSERT_EQ(a.size(), b.size());
        for (size_t i = 0; i < a.size(); ++i) ASSERT_NEAR(a[i], b[i], 1e-4 * std::max(1.0f, std::fabs(b[i]))) << i;
    };
    near_all(one.film.aov_image(kCameraAov), plain.film.aov_image(kCameraAov));
    near_all(eight.film.aov_image(kCameraAov), plain8.film.aov_image(kCameraAov));
    // And it changed something: the one-ray and eight-ray direct light differ.
    EXPECT_NE(one.film.aov_image(kCameraAov), eight.film.aov_image(kCameraAov));
    // Every other AOV (the paths beyond the camera hit) is the preview's, untouched.
    for (size_t c = 0; c < kComponentCount; ++c)
        EXPECT_EQ(one.film.aov_image(aov_of(static_cast<Component>(c))), eight.film.aov_image(aov_of(static_cast<Component>(c))));
}

TEST(PipelineRun, SpecularThresholdOneStopsSelectiveSpecularRays) {
    Scene scene = load(CREX_SOURCE_DIR "/examples/scenes/corridor/scene.json");
    auto text = [](const std::string& vary) {
        return "pipeline p {\n preselective { crex \"(TTRSGD)*\" spp 1 }\n guidance { c = constant(1) }\n selective { vary spp 1 .. 2 by c "
               + vary + " }\n}\n";
    };
    auto sg = [](const RunResult& r) {
        return r.stats.components[static_cast<size_t>(Component::kS)].rays +
               r.stats.components[static_cast<size_t>(Component::kG)].rays;
    };
    auto base = run(scene, plan_for(text(""), scene), 24, 16);
    auto cut = run(scene, plan_for(text("vary specular_threshold 1 .. 1 by c"), scene), 24, 16);
    auto preview = run(scene, plan_for("pipeline p {\n preselective { crex \"(TTRSGD)*\" spp 1 }\n}\n", scene), 24, 16);
    ASSERT_GT(sg(base), sg(preview));
    EXPECT_LT(sg(cut), sg(base));
    // Only the rays the preview spawned remain; the selective samples spawn none into S or G.
    EXPECT_EQ(sg(cut), sg(preview) + 0) << "cut " << sg(cut) << " preview " << sg(preview);
}

TEST(PipelineRun, ModulationByAMapDecidesWhatTheSelectiveCrexRuns) {
    Scene scene = load("builtin:cornell");
    auto text = [](const std::string& value) {
        return "pipeline p {\n preselective { crex \"TT\" spp 1 }\n guidance { c = constant(" + value +
               ") }\n selective { crex \"{TTMRSGD}2\" by c }\n}\n";
    };
    auto none = run(scene, plan_for(text("0"), scene), 16, 16);
    auto all = run(scene, plan_for(text("1"), scene), 16, 16);
    size_t d = static_cast<size_t>(Component::kD);
    EXPECT_EQ(none.stats.components[d].rays, 0u);
    EXPECT_GT(all.stats.components[d].rays, 0u);
    EXPECT_GT(none.rays_left[d], 0u);  // skipped rays stay in their bin
}

TEST(PipelineRun, SubsamplingRendersCornersAndInterpolatesTheRest) {
    Scene scene = load("builtin:cornell");
    auto plan = plan_for("pipeline p {\n preselective { spp 1 }\n guidance { c = constant(0) }\n"
                         " selective { spp 4  vary subsample 4 .. 1 by c }\n}\n",
                         scene);
    auto r = run(scene, plan, 17, 9);
    ASSERT_TRUE(r.subsample);
    for (uint32_t p = 0; p < 17 * 9; ++p) {
        bool corner = (p % 17 % 4 == 0 || p % 17 == 16) && (p / 17 % 4 == 0 || p / 17 == 8);
        EXPECT_EQ(r.subsample->rendered(p), corner) << p;
        EXPECT_EQ(r.film.samples(p), corner ? 4u : 1u) << p;
    }
    EXPECT_TRUE(testing::all_finite(r.image()));
}

struct StdlibCase {
    std::string pipeline, scene;
};

void PrintTo(const StdlibCase& c, std::ostream* os) { *os << c.pipeline << " on " << c.scene; }

class StdlibPipelines : public ::testing::TestWithParam<StdlibCase> {};

TEST_P(StdlibPipelines, RenderFiniteImagesWithMapsInTheUnitInterval) {
    Scene scene = load(GetParam().scene);
    auto plan = plan_for(testing::read_text(CREX_SOURCE_DIR "/stdlib/pipelines/" + GetParam().pipeline + ".pipe"), scene);
    auto r = run(scene, plan, 32, 24);
    EXPECT_TRUE(testing::all_finite(r.image()));
    EXPECT_TRUE(testing::all_finite(r.preview));
    uint64_t samples = 0;
    for (uint32_t p = 0; p < r.film.pixel_count(); ++p) {
        ASSERT_GE(r.film.samples(p), 1u);  // the preview's samples are kept
        samples += r.film.samples(p);
    }
    EXPECT_EQ(r.stats.camera.rays, samples);  // no sample traced twice
    for (const auto& [name, m] : r.maps) {
        ASSERT_EQ(m.pixels(), 32u * 24u) << name;
        for (float x : m.v) ASSERT_TRUE(x >= 0 && x <= 1) << name;
    }
    EXPECT_GT(r.preview_seconds, 0);
}

std::vector<StdlibCase> stdlib_cases() {
    std::vector<StdlibCase> out;
    for (const char* p : {"gold", "sel_rp", "osd", "sel_edge", "cbr", "sel_st", "sel_task", "prog_rp", "prog_all", "sel_quiet", "tc_rp", "apict", "adaptive"})
        for (const char* s : {"builtin:cornell", CREX_SOURCE_DIR "/examples/scenes/corridor/scene.json"}) out.push_back({p, s});
    return out;
}

INSTANTIATE_TEST_SUITE_P(OnCornellAndCorridor, StdlibPipelines, ::testing::ValuesIn(stdlib_cases()),
                         [](const auto& test) {
                             return test.param.pipeline + (test.param.scene.find("corridor") != std::string::npos ? "_corridor" : "_cornell");
                         });

}  // namespace
}  // namespace crex

namespace crex {
namespace {

// A map written inline (`vary shadow_rays 1 .. 3 by edges(direct)`) is listed as the user
// wrote it, not under the plan's node id (`op.vary.shadow_rays.0`).
TEST(PipelineRun, InlineMapsAreNamedAsWritten) {
    Scene scene = load("builtin:cornell");
    const std::string text = "pipeline p {\n preselective { crex \"(TTMRSGD)*\" spp 1 }\n"
                             " selective { vary shadow_rays 1 .. 3 by edges(direct) }\n}\n";
    RunSettings o;
    o.width = o.height = 16;
    auto r = run_plan(scene, plan_for(text, scene), o);
    ASSERT_EQ(r.maps.size(), 1u);
    EXPECT_EQ(r.maps[0].first, "edges(direct)");
}

// A small square render with a cheap irradiance cache (64 hemisphere rays, 2 bounces).
RunSettings cached_settings(int size) {
    RunSettings o;
    o.width = o.height = size;
    IcSettings ic;
    ic.divisions = 64, ic.bounces = 2;
    o.irradiance_cache = ic;
    return o;
}

TEST(PipelineRun, TheProgressiveCacheAnswersThePreviewAgainOnlyWhereAskedTo) {
    Scene scene = load("builtin:cornell_diffuse");
    auto text = [](const std::string& value) {
        return "pipeline p {\n preselective { crex \"(TTMRSGD)*\" spp 1 }\n guidance { c = constant(" + value +
               ") }\n selective { vary ic_radius 0.5 .. 0.1 by c }\n}\n";
    };
    RunSettings o = cached_settings(24);
    auto coarse = run_plan(scene, plan_for(text("0"), scene), o);
    auto fine = run_plan(scene, plan_for(text("1"), scene), o);
    // Map 0: nothing asks for more than the base radius: no sample answered again, no record made.
    EXPECT_EQ(coarse.ic_reprocessed, 0u);
    EXPECT_EQ(coarse.ic_selective_records, 0u);
    // Map 1: every preview D sample is answered again at 0.1, with new records where needed.
    EXPECT_GT(fine.ic_reprocessed, 24u * 24u / 2);
    EXPECT_GT(fine.ic_selective_records, 0u);
    EXPECT_EQ(fine.ic_preview_records, coarse.ic_preview_records);  // the same preview
    // The finer answers replace the coarse ones: the D AOV changes, the camera AOV does not.
    EXPECT_EQ(fine.film.aov_image(kCameraAov), coarse.film.aov_image(kCameraAov));
    EXPECT_NE(fine.film.aov_image(aov_of(Component::kD)), coarse.film.aov_image(aov_of(Component::kD)));
    double a = testing::mean_luminance(fine.image()), b = testing::mean_luminance(coarse.image());
    EXPECT_NEAR(a, b, 0.05 * b);  // same light, answered more finely
}

// The preview's cache answers are kept (a million of them at 960x540: 150 MB of edge_aa's 530)
// only for a plan whose ic_radius can end finer than it starts; one that cannot renders the same.
TEST(PipelineRun, OnlyAPlanThatCanRefineTheCacheKeepsThePreviewsAnswers) {
    Scene scene = load("builtin:cornell_diffuse");
    auto text = [](const std::string& range) {
        return "pipeline p {\n preselective { crex \"(TTMRSGD)*\" spp 1 }\n guidance { c = constant(1) }\n selective { " + range +
               " }\n}\n";
    };
    EXPECT_TRUE(may_refine_accuracy(plan_for(text("vary ic_radius 0.5 .. 0.1 by c"), scene)));
    EXPECT_FALSE(may_refine_accuracy(plan_for(text("vary ic_radius 0.15 .. 0.15 by c"), scene)));
    EXPECT_FALSE(may_refine_accuracy(plan_for(text("vary ic_radius 0.1 .. 0.5 by c"), scene)));
    EXPECT_FALSE(may_refine_accuracy(plan_for(text("vary spp 1 .. 4 by c"), scene)));
    RunSettings o = cached_settings(24);
    auto same = run_plan(scene, plan_for(text("vary ic_radius 0.3 .. 0.3 by c\n vary spp 1 .. 2 by c"), scene), o);
    EXPECT_EQ(same.ic_reprocessed, 0u);
    EXPECT_GT(same.ic_preview_records, 0u);
}

// `vary ic_rays`: a pixel whose map asks for more hemisphere rays than the preview's records
// have answers its D samples again from records made with them; at one value everywhere it is
// the cache at that `ad`, bit for bit.
TEST(PipelineRun, QuieterRecordsAreMadeWhereTheMapAsksForThem) {
    Scene scene = load("builtin:cornell_diffuse");
    auto text = [](const std::string& value, const std::string& vary) {
        return "pipeline p {\n preselective { crex \"(TTMRSGD)*\" spp 1 }\n guidance { c = constant(" + value + ") }\n selective { " +
               vary + " }\n}\n";
    };
    RunSettings o = cached_settings(24);
    const auto loud = run_plan(scene, plan_for(text("0", "vary ic_rays 32 .. 256 by c"), scene), o);
    const auto quiet = run_plan(scene, plan_for(text("1", "vary ic_rays 32 .. 256 by c"), scene), o);
    EXPECT_TRUE(may_refine_accuracy(plan_for(text("1", "vary ic_rays 32 .. 256 by c"), scene)));
    EXPECT_TRUE(may_refine_accuracy(plan_for(text("1", "vary ic_rays 256 .. 32 by c"), scene)));  // the preview has 32
    EXPECT_FALSE(may_refine_accuracy(plan_for(text("1", "vary ic_rays 64 .. 70 by c"), scene)));  // both are 64
    // Map 0: the preview's records (the cache's own rays, set to the map-0 value 32; a record
    // says 0 for them) serve every pixel; nothing is answered again.
    EXPECT_EQ(loud.ic_reprocessed, 0u);
    EXPECT_EQ(loud.ic_selective_records, 0u);
    for (const IrradianceRecord& r : loud.ic_records) EXPECT_EQ(r.divisions, 0u);
    // Map 1: every preview D sample is answered again from records of 256 rays (and their
    // deeper bounces' 128), made for it.
    EXPECT_GT(quiet.ic_reprocessed, 24u * 24u / 2);
    EXPECT_GT(quiet.ic_selective_records, 0u);
    size_t made_quiet = 0;
    for (const IrradianceRecord& r : quiet.ic_records) made_quiet += r.divisions == 256;
    EXPECT_EQ(made_quiet, quiet.ic_selective_records);
    EXPECT_GT(quiet.ic_stats.hemisphere_rays, 2 * loud.ic_stats.hemisphere_rays);
    EXPECT_EQ(quiet.film.aov_image(kCameraAov), loud.film.aov_image(kCameraAov));
    EXPECT_NEAR(testing::mean_luminance(quiet.image()), testing::mean_luminance(loud.image()), 0.05 * testing::mean_luminance(loud.image()));
    // One value everywhere is the cache at that ad: the same image as --ad 32 (the records say
    // how many rays they have, which changes nothing else).
    RunSettings ad32 = o;
    ad32.irradiance_cache->divisions = 32;
    const auto plain = run_plan(scene, plan_for(text("1", "vary ic_radius 0.15 .. 0.15 by c"), scene), ad32);
    const auto varied = run_plan(scene, plan_for(text("1", "vary ic_rays 32 .. 32 by c\n vary ic_radius 0.15 .. 0.15 by c"), scene), o);
    EXPECT_EQ(varied.image(), plain.image());
    EXPECT_EQ(varied.ic_records.size(), plain.ic_records.size());
}

// --uniform max is the pipeline's own gold: the same image as the pipeline whose every map is
// constant(1) (the thesis protocol's denominator is exactly that pipeline, not another renderer).
TEST(PipelineRun, UniformMaxIsThePipelineWithEveryMapAtOne) {
    Scene scene = load("builtin:cornell");
    auto text = [](const std::string& sal, const std::string& dl) {
        return "pipeline p {\n preselective { crex \"(TTMRSGD)*\" spp 1 }\n guidance {\n sal = " + sal + "\n dl = " + dl +
               "\n }\n selective {\n vary spp 1 .. 4 by sal\n vary shadow_rays 1 .. 3 by dl\n }\n}\n";
    };
    RunSettings o;
    o.width = o.height = 16;
    RunSettings gold = o;
    gold.uniform = UniformQuality::kMax;
    auto a = run_plan(scene, plan_for(text("saliency(preview)", "edges(direct)"), scene), gold);
    auto b = run_plan(scene, plan_for(text("constant(1)", "constant(1)"), scene), o);
    auto c = run_plan(scene, plan_for(text("saliency(preview)", "edges(direct)"), scene), o);
    EXPECT_EQ(a.image(), b.image());
    EXPECT_EQ(a.stats.camera.rays, 4u * 16u * 16u);
    EXPECT_NE(a.image(), c.image());  // the maps do matter without --uniform
}

// capict (issue 18): with every grid at spacing 1 (`--uniform max`) nothing is interpolated and
// the pipeline is stratified sampling itself; at spacing 8 D's first bounces run at a few
// corners only, and no pixel the preview lit goes black, nor does the image's light move.
TEST(PipelineRun, CapictAtItsMaximumIsTheUniformRender) {
    Scene scene = load("builtin:cornell");
    auto capict = plan_for(testing::read_text(CREX_SOURCE_DIR "/stdlib/pipelines/capict.pipe"), scene);
    auto uniform = plan_for("pipeline p {\n preselective { crex \"(TTMRSGD)*\" spp 1 }\n guidance { c = constant(1) }\n"
                            " selective { vary spp 16 .. 16 by c }\n}\n",
                            scene);
    RunSettings o;
    o.width = o.height = 16;
    RunSettings gold = o;
    gold.uniform = UniformQuality::kMax;
    auto a = run_plan(scene, capict, gold);
    auto b = run_plan(scene, uniform, o);
    ASSERT_TRUE(a.component_subsample.any());
    EXPECT_EQ(a.component_subsample.grid(Component::kD)->rendered_count(), 16u * 16u);
    EXPECT_EQ(a.image(), b.image());
    EXPECT_EQ(a.stats.components[0].rays, b.stats.components[0].rays);
}

TEST(PipelineRun, CapictInterpolatesWithoutBlackPixelsOrLostLight) {
    Scene scene = load("builtin:cornell");
    const std::string text =
        "pipeline p extends capict {\n guidance { z = constant(0) }\n selective {\n vary subsample(D) 8 .. 1 by z\n"
        " vary subsample(R) 4 .. 1 by z\n }\n}\n";
    RunSettings o;
    o.width = o.height = 32;
    auto sub = run_plan(scene, plan_for(text, scene), o);
    auto full = run_plan(scene, plan_for(text, scene), [&] { RunSettings g = o; g.uniform = UniformQuality::kMax; return g; }());
    const size_t d = static_cast<size_t>(Component::kD);
    // D's first bounces ran at the corners (and wherever a square had none on the pixel's surface).
    const size_t corners = sub.component_subsample.grid(Component::kD)->rendered_count();
    EXPECT_LT(corners, 32u * 32u / 4);
    EXPECT_LT(sub.stats.components[d].rays, full.stats.components[d].rays / 2);
    auto image = sub.image(), preview = sub.preview;
    for (size_t p = 0; p < sub.film.pixel_count(); ++p) {
        const double y = 0.2126 * image[3 * p] + 0.7152 * image[3 * p + 1] + 0.0722 * image[3 * p + 2];
        ASSERT_TRUE(std::isfinite(y)) << p;
        const double before = 0.2126 * preview[3 * p] + 0.7152 * preview[3 * p + 1] + 0.0722 * preview[3 * p + 2];
        if (before > 0) {
            EXPECT_GT(y, 0.0) << "pixel " << p << " went black";
        }
    }
    // The interpolation moves light between pixels, it neither makes nor loses it: the image's
    // mean is the full render's within 3 % (16 spp of 32x32: the means' own noise is ~1 %).
    const double a = testing::mean_luminance(image), b = testing::mean_luminance(full.image());
    EXPECT_NEAR(a, b, 0.03 * b);
    // The D image carries the interpolation: the component images still add up to the image.
    std::vector<float> sum(image.size(), 0.0f);
    for (size_t aov = 0; aov < kAovCount; ++aov) {
        auto part = sub.aov_image(aov);
        for (size_t i = 0; i < sum.size(); ++i) sum[i] += part[i];
    }
    for (size_t i = 0; i < sum.size(); ++i) ASSERT_NEAR(sum[i], image[i], 1e-4 * std::max(1.0f, image[i])) << i;
}

// capict's refinement renders the branch a new corner skipped by tracing its samples again:
// more corners and D rays than without it, and no sample or camera light counted twice.
TEST(PipelineRun, CapictRefinementAddsCornersWithoutCountingSamplesTwice) {
    Scene scene = load("builtin:cornell");
    auto text = [](const std::string& refine) {
        return "pipeline p extends capict {\n guidance { z = constant(0) }\n selective {\n vary subsample(D) 8 .. 1 by z" + refine +
               "\n vary subsample(R) 4 .. 1 by z\n }\n}\n";
    };
    RunSettings o;
    o.width = o.height = 32;
    auto plain = run_plan(scene, plan_for(text(""), scene), o);
    auto refined = run_plan(scene, plan_for(text(" refine 0.25"), scene), o);
    EXPECT_EQ(plain.refinements, 0u);
    EXPECT_GT(refined.refinements, 0u);
    EXPECT_GT(refined.component_subsample.grid(Component::kD)->rendered_count(),
              plain.component_subsample.grid(Component::kD)->rendered_count());
    const size_t d = static_cast<size_t>(Component::kD);
    EXPECT_GT(refined.stats.components[d].rays, plain.stats.components[d].rays);
    EXPECT_GT(refined.stats.camera.rays, plain.stats.camera.rays);  // samples traced again
    for (uint32_t p = 0; p < refined.film.pixel_count(); ++p) ASSERT_EQ(refined.film.samples(p), 16u) << p;
    // What every pixel's camera rays found (direct light, emission) is counted once.
    EXPECT_EQ(refined.film.aov_image(kCameraAov), plain.film.aov_image(kCameraAov));
}

// A cached pipeline's selective samples ask the cache for D like its preview does: no D ray is
// path traced (path-traced D rays shade their hits with shadow rays; cache queries do not).
TEST(PipelineRun, SelectiveSamplesQueryTheCacheForIndirectDiffuse) {
    Scene scene = load("builtin:cornell_diffuse");
    const std::string text =
        "pipeline p {\n preselective { crex \"(TTMRSGD)*\" spp 1 }\n guidance { c = constant(1) }\n"
        " selective { vary ic_radius 0.3 .. 0.3 by c\n vary spp 4 .. 4 by c }\n}\n";
    RunSettings o = cached_settings(16);
    auto r = run_plan(scene, plan_for(text, scene), o);
    EXPECT_EQ(r.stats.camera.rays, 4u * 16u * 16u);  // 3 of the 4 samples in the selective stage
    EXPECT_GT(r.stats.components[static_cast<size_t>(Component::kD)].rays, 0u);
    EXPECT_EQ(r.stats.components[static_cast<size_t>(Component::kD)].shadow_rays, 0u);
}

}  // namespace
}  // namespace crex
