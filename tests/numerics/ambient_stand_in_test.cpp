// The automatic ambient stand-in (issue 14, spec/pipeline.md §6): a component skipped in a
// pixel is replaced by an estimate, never by black.
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/driver/ambient_stand_ins.h"
#include "runtime/driver/run_plan.h"
#include "runtime/scene/census.h"
#include "tests/support/plan_helpers.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

constexpr int kStandInSize = 24;

double luminance(const std::vector<float>& rgb, size_t p) {
    return 0.2126 * rgb[3 * p] + 0.7152 * rgb[3 * p + 1] + 0.0722 * rgb[3 * p + 2];
}

PipelinePlan skip_everything_after_tt(const Scene& s) {
    // Direct light and the glass only in the preview; `{ }` by a zero map runs nothing else.
    auto planned = testing::plan_text("t.pipe", R"(pipeline t {
  preselective { crex "TT" spp 2 }
  guidance { none = constant(0) }
  selective { crex "{MRSGD}" by none }
})",
                                      take_census(s).spawnable);
    if (!planned.plan) throw std::runtime_error(planned.diagnostics.empty() ? "no plan" : planned.diagnostics[0].message);
    return *planned.plan;
}

TEST(AmbientStandIn, SkippedComponentsNeverLeaveAPixelBlackThatTheFullRenderLights) {
    Scene s = *builtin_scene("cornell");
    PipelinePlan plan = skip_everything_after_tt(s);
    RunSettings o;
    o.width = o.height = kStandInSize;
    o.spp = 2;
    RunResult dark = run_plan(s, plan, o);  // av = 0: skipped work is black
    o.ambient_auto = true;
    RunResult stood_in = run_plan(s, plan, o);
    RunResult full = testing::render_crex(s, "(TTMRSGD)*", kStandInSize, 16);
    std::vector<float> a = stood_in.image(), d = dark.image(), f = full.image();
    size_t lit = 0, black_dark = 0;
    double sum_a = 0, sum_f = 0;
    for (size_t p = 0; p < f.size() / 3; ++p) {
        ASSERT_TRUE(std::isfinite(luminance(a, p)));
        sum_a += luminance(a, p), sum_f += luminance(f, p);
        if (luminance(f, p) < 1e-3) continue;
        ++lit;
        black_dark += luminance(d, p) <= 0;
        ASSERT_GT(luminance(a, p), 0) << "pixel " << p << " is black although the full render lights it";
    }
    EXPECT_GT(black_dark, lit / 10);  // without the stand-in, the ceiling and more are black
    // A stand-in, not a solution: of the right order of magnitude.
    EXPECT_GT(sum_a, 0.3 * sum_f);
    EXPECT_LT(sum_a, 3.0 * sum_f);
    // No D ray ran anywhere: D stood in with the preview's mean radiance.
    EXPECT_GT(stood_in.auto_ambient[static_cast<size_t>(Component::kD)].x, 0);
    // Every component none of whose rays ran stands in with that one mean: one note names them
    // all ("unexecuted D, S, R and M rays ..."), not a line each.
    size_t notes = 0;
    std::string note;
    for (const std::string& n : stood_in.notes)
        if (n.find("stood in") != std::string::npos) ++notes, note = n;
    EXPECT_EQ(notes, 1u);
    EXPECT_EQ(note.rfind("unexecuted D, ", 0), 0u) << note;
    EXPECT_NE(note.find(" and M rays stood in with av = "), std::string::npos) << note;
    EXPECT_NE(note.find("(none of their rays ran)"), std::string::npos) << note;
}

TEST(AmbientStandIn, MeasuredFromTheComponentsOwnRaysWhereSomeRan) {
    // D runs in the left half only ({ } by a map of 1 there): the right half's D rays stand in
    // with what the left half's brought back per unit throughput.
    Scene s = *builtin_scene("cornell_diffuse");
    auto planned = testing::plan_text("t.pipe", R"(pipeline t {
  preselective { crex "" spp 4 }
  guidance { half = threshold(edges(preview), at 2) }
  selective { crex "{D}" by half }
})",
                                      take_census(s).spawnable);
    ASSERT_TRUE(planned.plan);
    RunSettings o;
    o.width = o.height = kStandInSize;
    o.spp = 4;
    o.ambient_auto = true;
    RunResult r = run_plan(s, *planned.plan, o);
    // threshold at 2 is 0 everywhere: nothing ran, so the mean radiance stands in ...
    Vec3 mean_based = r.auto_ambient[static_cast<size_t>(Component::kD)];
    EXPECT_GT(mean_based.x, 0);
    // ... and with D run everywhere, nothing is left to stand in for at depth 1.
    auto all = testing::plan_text("t.pipe", R"(pipeline t {
  preselective { crex "" spp 4 }
  guidance { one = constant(1) }
  selective { crex "{D}" by one }
})",
                                  take_census(s).spawnable);
    ASSERT_TRUE(all.plan);
    RunResult ran = run_plan(s, *all.plan, o);
    Vec3 measured = ran.auto_ambient[static_cast<size_t>(Component::kD)];  // the second bounce's D rays are left
    EXPECT_GT(measured.x, 0);
    EXPECT_GT(ran.stats.components[static_cast<size_t>(Component::kD)].beta[0], 0);
}

// The end of a render reads the film once for every component (in parallel, over fixed chunks)
// and adds every component's stand-in in one pass: each component's av is what its executed
// rays found over their throughput, and each pixel's stand-in is the sum over components of
// av x its throughput left, in component order, as one addition per component would give it;
// a component none of whose rays were left gets no stand-in and no note.
TEST(AmbientStandIn, EveryComponentLeftStandsInWithItsOwnMeasureInOnePass) {
    const int w = 300, h = 200;  // more pixels than one chunk of the sums
    Film film(w, h);
    const size_t pixels = film.pixel_count();
    ExecutorStats stats;
    AmbientStandIns stand_ins(pixels, Vec3{0, 0, 0}, true);
    std::vector<float> image(3 * pixels);
    for (size_t p = 0; p < pixels; ++p) {
        for (size_t k = 0; k < 3; ++k) image[3 * p + k] = float(0.001 * double((p * 7 + k) % 97));
        for (size_t c = 0; c < kComponentCount; ++c)
            film.add(aov_of(static_cast<Component>(c)), static_cast<uint32_t>(p),
                     Vec3{0.01 * double(c + 1), 0.02 * double((p + c) % 5), 0.005 * double(p % 3)});
    }
    // Components 1 and 3 measured (their rays ran), 4 left but never run (the mean stands in),
    // the others with nothing left.
    for (size_t c : {size_t{1}, size_t{3}}) stats.components[c].beta[0] = stats.components[c].beta[1] = stats.components[c].beta[2] = 2.0 * double(pixels);
    // Every component's buffer made before (as a budgeted render does): those no ray was left
    // in are known by the rays flush() counted, not by their zeros.
    std::array<bool, kComponentCount> every{};
    every.fill(true);
    stand_ins.keep(every);
    std::array<RayBatch, kComponentCount> bins;
    for (size_t c : {size_t{1}, size_t{3}, size_t{4}})
        for (size_t p = 0; p < pixels; ++p) {
            RayRecord r;
            r.pixel = static_cast<uint32_t>(p);
            r.beta = Vec3{0.25 * double((3 * p + c) % 4), 0.25 * double((3 * p + 1 + c) % 4), 0.25 * double((3 * p + 2 + c) % 4)};
            if (p % 7 != 0) bins[c].push(r);  // some pixels with nothing left
        }
    std::array<size_t, kComponentCount> left_count{};
    stand_ins.flush(bins, left_count);
    const std::array<std::vector<float>, kComponentCount> left = stand_ins.throughput_left();
    std::array<Vec3, kComponentCount> av{};
    std::vector<std::string> notes;
    stand_ins.finish_automatic(film, stats, image, 0, pixels, nullptr, av, notes);
    EXPECT_EQ(notes.size(), 3u);
    // Each av from its own sums, within float rounding of the sums' order.
    Vec3 mean{0, 0, 0};
    for (size_t p = 0; p < pixels; ++p) mean = mean + Vec3{image[3 * p], image[3 * p + 1], image[3 * p + 2]};
    mean = mean / double(pixels);
    for (size_t c : {size_t{1}, size_t{3}}) {
        const Vec3 found = film.aov_total(aov_of(static_cast<Component>(c)), 0, static_cast<uint32_t>(pixels));
        EXPECT_NEAR(av[c].x, found.x / (2.0 * double(pixels)), 1e-12);
        EXPECT_NEAR(av[c].y, found.y / (2.0 * double(pixels)), 1e-12);
    }
    EXPECT_NEAR(av[4].x, mean.x, 1e-9);
    EXPECT_NEAR(av[4].z, mean.z, 1e-9);
    // Each pixel's stand-in, bit for bit.
    const std::vector<double>& ambient = stand_ins.ambient();
    ASSERT_EQ(ambient.size(), 3 * pixels);
    for (size_t i = 0; i < ambient.size(); ++i) {
        double expected = 0;
        const size_t k = i % 3;
        for (size_t c : {size_t{1}, size_t{3}, size_t{4}}) expected += (k == 0 ? av[c].x : k == 1 ? av[c].y : av[c].z) * left[c][i];
        ASSERT_EQ(ambient[i], expected) << "value " << i;
    }
    // Kept until the render's clock stopped, then freed.
    EXPECT_EQ(stand_ins.kept_bytes(), kComponentCount * 3 * pixels * sizeof(float));
    stand_ins.release();
    EXPECT_EQ(stand_ins.kept_bytes(), 0u);
}

// A budgeted render makes the throughput buffers of the components its crex reads before its
// clock starts (made at its last pass's end, after the budget's last decision, their page
// faults overran 0.11 s budgets by 3 to 4 %). Rays left later add into them as into buffers
// made on demand, and the components not asked for are still made only when rays are left.
TEST(AmbientStandIn, BuffersKeptBeforeTheRenderHoldWhatLaterPassesLeave) {
    const size_t pixels = 50;
    std::array<bool, kComponentCount> read{};
    read[static_cast<size_t>(Component::kD)] = read[static_cast<size_t>(Component::kG)] = true;
    AmbientStandIns kept(pixels, Vec3{0, 0, 0}, true), on_demand(pixels, Vec3{0, 0, 0}, true);
    kept.keep(read);
    EXPECT_EQ(kept.kept_bytes(), 2 * 3 * pixels * sizeof(float));
    EXPECT_EQ(on_demand.kept_bytes(), 0u);
    for (int pass = 0; pass < 2; ++pass) {
        std::array<RayBatch, kComponentCount> bins_a, bins_b;
        for (Component c : {Component::kD, Component::kS}) {
            for (uint32_t i = 0; i < 20; ++i) {
                RayRecord r;
                r.pixel = (7 * i + static_cast<uint32_t>(pass)) % pixels;
                r.beta = Vec3{0.1 * (i + 1), 0.2, 0.05 * pass};
                bins_a[static_cast<size_t>(c)].push(r);
                bins_b[static_cast<size_t>(c)].push(r);
            }
        }
        std::array<size_t, kComponentCount> left_a{}, left_b{};
        kept.flush(bins_a, left_a);
        on_demand.flush(bins_b, left_b);
        EXPECT_EQ(left_a, left_b);
    }
    for (size_t c = 0; c < kComponentCount; ++c) EXPECT_EQ(kept.throughput_left()[c].empty(), c != static_cast<size_t>(Component::kD) &&
                                                                                              c != static_cast<size_t>(Component::kG) &&
                                                                                              c != static_cast<size_t>(Component::kS))
                                                              << c;
    EXPECT_EQ(kept.throughput_left()[static_cast<size_t>(Component::kD)], on_demand.throughput_left()[static_cast<size_t>(Component::kD)]);
    EXPECT_EQ(kept.throughput_left()[static_cast<size_t>(Component::kS)], on_demand.throughput_left()[static_cast<size_t>(Component::kS)]);
    EXPECT_TRUE(on_demand.throughput_left()[static_cast<size_t>(Component::kG)].empty());  // nothing of G was left
    EXPECT_EQ(kept.kept_bytes(), 3 * 3 * pixels * sizeof(float));
}

}  // namespace
}  // namespace crex
