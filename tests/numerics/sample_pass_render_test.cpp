// Renders in sample passes (issue 13): the image does not depend on how the samples are split
// into passes or bands (within 1e-6 relative: only the order of the film's sums changes), it
// is bit-identical at 1 and 2 threads for a given split, and a pipeline's selective samples
// continue the preview's sequence across passes.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>

#include "runtime/driver/run_plan.h"
#include "runtime/scene/census.h"
#include "tests/support/plan_helpers.h"
#include "tests/support/scene_helpers.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

constexpr int kPassSize = 16;

RunSettings settings(uint32_t spp, uint32_t pass_samples) {
    RunSettings o;
    o.width = o.height = kPassSize;
    o.spp = spp;
    o.seed = 3;
    o.pass_samples = pass_samples;
    return o;
}

void expect_same_image(const std::vector<float>& a, const std::vector<float>& b, double rel) {
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) ASSERT_NEAR(a[i], b[i], rel * std::fabs(a[i]) + 1e-12) << "value " << i;
}

TEST(SamplePassRender, PassesOfOneThreeAndAllSamplesGiveTheSameImage) {
    Scene s = *builtin_scene("cornell");
    sched::Program p = testing::lower_or_die("(TTMRSGD)*");
    RunResult all = render(s, p, settings(7, 7));
    RunResult ones = render(s, p, settings(7, 1));
    RunResult threes = render(s, p, settings(7, 3));
    EXPECT_EQ(all.passes, 1u);
    EXPECT_EQ(ones.passes, 7u);
    EXPECT_EQ(threes.passes, 3u);
    expect_same_image(all.image(), ones.image(), 1e-6);
    expect_same_image(all.image(), threes.image(), 1e-6);
    EXPECT_EQ(all.stats.camera.rays, ones.stats.camera.rays);
    for (size_t c = 0; c < kComponentCount; ++c) EXPECT_EQ(all.stats.components[c].rays, ones.stats.components[c].rays) << c;
}

TEST(SamplePassRender, BandsOfRowsUnderATinyMemoryLimitGiveTheSameImage) {
    Scene s = *builtin_scene("cornell");
    sched::Program p = testing::lower_or_die("(TTMRSGD)*");
    RunSettings tiny = settings(3, 0);
    tiny.max_memory = 1;  // below anything: one row per pass
    RunResult banded = render(s, p, tiny);
    EXPECT_EQ(banded.passes, 3u * kPassSize);
    // The limit cannot be kept, and the run says so.
    EXPECT_TRUE(std::any_of(banded.notes.begin(), banded.notes.end(),
                            [](const std::string& n) { return n.find("more than --max-memory") != std::string::npos; }));
    expect_same_image(render(s, p, settings(3, 0)).image(), banded.image(), 1e-6);
}

TEST(SamplePassRender, BitIdenticalAtOneAndTwoThreadsForAGivenPassSize) {
    Scene s = *builtin_scene("cornell");
    sched::Program p = testing::lower_or_die("(TTMRSGD)*");
    std::vector<float> one, two;
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
        one = render(s, p, settings(5, 2)).image();
    }
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
        two = render(s, p, settings(5, 2)).image();
    }
    EXPECT_EQ(one, two);
}

TEST(SamplePassRender, SelectiveSamplesContinueThePreviewAcrossPasses) {
    // spp varies 2..9 by saliency: the selective stage's new samples [2, spp(p)) go in passes
    // of one sample; the image and every pixel's sample count match the one-pass run.
    Scene s = *builtin_scene("cornell");
    auto planned = testing::plan_text("t.pipe", R"(pipeline t {
  preselective { crex "TT" spp 2 }
  guidance { sal = saliency(preview) }
  selective { crex "(MRSGD)*" vary spp 2 .. 9 by sal }
})",
                                      take_census(s).spawnable);
    ASSERT_TRUE(planned.plan) << (planned.diagnostics.empty() ? "" : planned.diagnostics[0].message);
    RunSettings one = settings(2, 9), many = settings(2, 1);
    RunResult a = run_plan(s, *planned.plan, one), b = run_plan(s, *planned.plan, many);
    EXPECT_GT(b.passes, a.passes);
    uint32_t most = 0;
    for (uint32_t p = 0; p < a.film.pixel_count(); ++p) {
        ASSERT_EQ(a.film.samples(p), b.film.samples(p)) << p;
        ASSERT_GE(a.film.samples(p), 2u);
        most = std::max(most, a.film.samples(p));
    }
    EXPECT_GT(most, 2u);  // some pixels did get selective samples
    EXPECT_EQ(a.stats.camera.rays, b.stats.camera.rays);  // no sample traced twice
    expect_same_image(a.image(), b.image(), 1e-6);
    expect_same_image(a.preview, b.preview, 1e-6);
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(CyclicProcess, RoundsWithAConstantMapTakeTheSameSamplesAsOneRound) {
    Scene s = *builtin_scene("cornell");
    auto planned = testing::plan_text("t.pipe", R"(pipeline t {
  preselective { crex "TT" spp 1 }
  guidance { some = constant(0.5) }
  selective { crex "(MRSGD)*" vary spp 1 .. 9 by some }
})",
                                      take_census(s).spawnable);
    ASSERT_TRUE(planned.plan);
    RunSettings one = settings(1, 9), three = settings(1, 9);  // each stage in one pass
    three.rounds = 3;
    RunResult a = run_plan(s, *planned.plan, one), b = run_plan(s, *planned.plan, three);
    for (uint32_t p = 0; p < a.film.pixel_count(); ++p) ASSERT_EQ(a.film.samples(p), 5u);
    for (uint32_t p = 0; p < b.film.pixel_count(); ++p) ASSERT_EQ(b.film.samples(p), 5u);
    EXPECT_GE(b.passes, a.passes + 2);
    expect_same_image(a.image(), b.image(), 1e-6);
}

TEST(CyclicProcess, LaterRoundsFollowTheNoiseOfTheImageSoFar) {
    // Each round recomputes the map on the image so far and tops pixels up towards its target.
    Scene s = *builtin_scene("cornell");
    auto planned = testing::plan_text("t.pipe", R"(pipeline t {
  preselective { crex "(TTMRSGD)*" spp 2 }
  guidance { rough = normalise(blur(edges(component(D)))) }
  selective { crex "(TTMRSGD)*" vary spp 2 .. 24 by rough }
})",
                                      take_census(s).spawnable);
    ASSERT_TRUE(planned.plan) << (planned.diagnostics.empty() ? "" : planned.diagnostics[0].message);
    RunSettings o = settings(2, 0);
    o.rounds = 4;
    RunResult r = run_plan(s, *planned.plan, o);
    uint64_t samples = 0;
    uint32_t most = 0;
    for (uint32_t p = 0; p < r.film.pixel_count(); ++p) samples += r.film.samples(p), most = std::max(most, r.film.samples(p));
    EXPECT_EQ(r.stats.camera.rays, samples);  // no sample twice, across rounds
    EXPECT_GT(most, 2u);
    EXPECT_LE(most, 24u);
    std::vector<float> image = r.image();
    EXPECT_TRUE(std::all_of(image.begin(), image.end(), [](float v) { return std::isfinite(v); }));
}

TEST(NoiseEstimate, HalfBuffersShrinkLikeOneOverTheSquareRootOfTheSamples) {
    Scene s = *builtin_scene("cornell");
    auto mean_noise = [&](uint32_t spp) {
        RunResult r = testing::render_crex(s, "(TTMRSGD)*", kPassSize, spp, 5);
        std::vector<float> n = r.film.noise_image();
        double sum = 0;
        for (float v : n) {
            EXPECT_TRUE(std::isfinite(v) && v >= 0);
            sum += v;
        }
        return sum / double(n.size());
    };
    double few = mean_noise(4), many = mean_noise(64);
    EXPECT_GT(few, 0);
    // sqrt(64 / 4) = 4 in expectation; the estimate is noisy itself.
    EXPECT_GT(few / many, 2.0);
    EXPECT_LT(few / many, 8.0);
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

// Passes are sized by a model (512 bytes a sample); the first pass is an eighth of the memory
// and the rest is planned on the rays it held. The room (trans, glass, a mirror: lobe
// splitting) holds more rays a sample than the model and gets more, smaller passes; the
// Cornell box holds fewer and keeps the model; both images are what one pass gives.
TEST(SamplePassRender, LaterPassesAreSizedByTheRaysTheFirstHeld) {
    sched::Program p = testing::lower_or_die("(TTMRSGD)*");
    auto run = [&](const Scene& s, size_t max_memory) {
        RunSettings o;
        o.width = 24, o.height = 16;
        o.spp = 24;
        o.max_memory = max_memory;
        return render(s, p, o);
    };
    Scene room = *testing::load_path(CREX_SOURCE_DIR "/examples/scenes/room/scene.json").scene;
    const size_t tight = (size_t{96} << 20) + (size_t{4} << 20);  // the baseline plus 4 MiB for rays
    RunResult split = run(room, tight), whole = run(room, size_t{1} << 32);
    EXPECT_GT(split.bytes_per_sample, 512u);
    EXPECT_GT(split.passes, 2u);
    expect_same_image(split.image(), whole.image(), 1e-5);
    RunResult box = run(*builtin_scene("cornell"), tight);
    EXPECT_EQ(box.bytes_per_sample, 512u);
}

// With an irradiance cache the split into passes changes the image (records made in one pass
// answer the next), so it must not depend on which buffers the film keeps: a run that writes
// the component images and one that does not make the same records and the same image.
TEST(SamplePassRender, ACachedRendersImageDoesNotDependOnTheImagesItWrites) {
    Scene room = *testing::load_path(CREX_SOURCE_DIR "/examples/scenes/room/scene.json").scene;
    sched::Program p = testing::lower_or_die("(TTMRSGD)*");
    auto run = [&](bool component_images) {
        RunSettings o;
        o.width = 48, o.height = 32;
        o.spp = 4;
        o.seed = 5;
        IcSettings ic;
        ic.divisions = 32, ic.bounces = 1;
        o.irradiance_cache = ic;
        o.component_images = component_images;
        o.max_memory = (size_t{96} << 20) + (size_t{1} << 20);  // the baseline and 1 MiB: several passes
        return render(room, p, o);
    };
    const RunResult every = run(true), lean = run(false);
    EXPECT_GT(every.passes, 1u);
    EXPECT_EQ(every.passes, lean.passes);
    EXPECT_EQ(every.ic_stats.records, lean.ic_stats.records);
    expect_same_image(every.image(), lean.image(), 1e-5);
}

}  // namespace
}  // namespace crex
