// Each crex construct on a tiny scene where what the bins hold can be predicted
// (spec/crex.md §3).
#include <gtest/gtest.h>

#include <algorithm>

#include "base/render_text.h"
#include "runtime/scene/census.h"
#include "runtime/scene/load_scene.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

using testing::make_material;
using testing::quad;

// A lit diffuse wall at z = -2 behind a glass slab (a box 0.2 thick) that fills the view.
Scene glass_slab() {
    Scene s;
    s.materials.push_back(make_material("wall", MaterialType::kPlastic, {0.8, 0.8, 0.8}));
    s.materials.push_back(make_material("lamp", MaterialType::kLight, {5, 5, 5}));
    Material glass = make_material("glass", MaterialType::kGlass, {1, 1, 1});
    glass.ior = 1.5;
    s.materials.push_back(glass);
    s.shapes.push_back(quad("wall", {-5, -5, -2}, {5, -5, -2}, {5, 5, -2}, {-5, 5, -2}));
    s.shapes.push_back(quad("lamp", {-1, 3, -1.5}, {1, 3, -1.5}, {1, 3, -0.5}, {-1, 3, -0.5}));  // faces -y after winding
    Shape slab;
    slab.type = ShapeType::kBox;
    slab.material = "glass";
    slab.min = {-3, -3, -0.1};
    slab.max = {3, 3, 0.1};
    s.shapes.push_back(slab);
    s.camera.position = {0, 0, 2};
    s.camera.direction = {0, 0, -1};
    s.camera.vfov_deg = 30;
    return s;
}

TEST(ExecutorSemantics, TTFollowsLightThroughBothGlassInterfaces) {
    Scene s = glass_slab();
    RunResult t = testing::render_crex(s, "T", 8, 1);
    RunResult tt = testing::render_crex(s, "TT", 8, 1);
    // Every camera ray enters the slab: T takes 64 rays; their children wait in T inside the
    // glass. TT executes those too, reaching the wall, which is then lit in the image.
    ASSERT_EQ(t.stats.steps.size(), 1u);
    EXPECT_EQ(t.stats.steps[0].rays, 64u);
    EXPECT_EQ(t.rays_left[static_cast<size_t>(Component::kT)], 64u);
    ASSERT_EQ(tt.stats.steps.size(), 2u);
    EXPECT_EQ(tt.stats.steps[1].component, Component::kT);
    EXPECT_EQ(tt.stats.steps[1].rays, 64u);
    EXPECT_GT(testing::mean_luminance(tt.film.aov_image(aov_of(Component::kT))), 0.0);
    EXPECT_EQ(testing::mean_luminance(t.film.aov_image(aov_of(Component::kT))), 0.0);
}

// A glossy-and-diffuse floor (spawns D and G) under a light.
Scene glossy_room() {
    Scene s;
    Material floor = make_material("floor", MaterialType::kPlastic, {0.6, 0.6, 0.6});
    floor.specularity = 0.2;
    floor.roughness = 0.3;
    s.materials.push_back(floor);
    s.materials.push_back(make_material("lamp", MaterialType::kLight, {5, 5, 5}));
    s.shapes = testing::furnace_box(0.5, 0).shapes;
    for (auto& sh : s.shapes) sh.material = "floor";
    s.shapes.push_back(quad("lamp", {-0.3, 0.99, -0.3}, {0.3, 0.99, -0.3}, {0.3, 0.99, 0.3}, {-0.3, 0.99, 0.3}));
    s.camera.position = {0, 0, 0.5};
    s.camera.direction = {0, 0, -1};
    s.camera.vfov_deg = 60;
    return s;
}

TEST(ExecutorSemantics, DeferredGroupHoldsSpawnedRaysBack) {
    Scene s = glossy_room();
    // One sample a pixel: one pass, so the steps' counts are the whole render's.
    // G rays waiting after the camera rays alone, and after camera rays then D:
    size_t g_from_camera = testing::render_crex(s, "", 8, 1).rays_left[static_cast<size_t>(Component::kG)];
    size_t g_after_d = testing::render_crex(s, "D", 8, 1).rays_left[static_cast<size_t>(Component::kG)];
    ASSERT_GT(g_after_d, g_from_camera);

    RunResult inherit = testing::render_crex(s, "(DGS)G", 8, 1);
    RunResult deferred = testing::render_crex(s, "<DGS>G", 8, 1);
    auto first_g = [](const RunResult& r) {
        for (const auto& st : r.stats.steps)
            if (st.component == Component::kG) return st.rays;
        return uint64_t{0};
    };
    // In (DGS)G the first G executes the glossy rays D just spawned; in <DGS>G they wait.
    EXPECT_EQ(first_g(inherit), g_after_d);
    EXPECT_EQ(first_g(deferred), g_from_camera);
    // ...and reach the final G once the group has ended.
    EXPECT_EQ(deferred.stats.steps.back().component, Component::kG);
    EXPECT_EQ(deferred.stats.steps.back().rays, g_after_d - g_from_camera + /* children of the first G */
                                                    (testing::render_crex(s, "G", 8, 1).rays_left[static_cast<size_t>(Component::kG)]));
}

TEST(ExecutorSemantics, ModulationFollowsTheCeilRuleOnAStepMap) {
    // Importance 0.3 on the left half, 0.9 on the right; {DDD} has n = 3: the first D runs
    // where I > 0 (everywhere), the second where I > 1/3 and the third where I > 2/3 (right
    // half only). So rays left in D are one bounce deep on the left, three on the right.
    Scene s = testing::furnace_box(0.5, 0.1);
    const int n = 8;
    std::vector<float> importance(n * n);
    for (int p = 0; p < n * n; ++p) importance[static_cast<size_t>(p)] = (p % n) < n / 2 ? 0.3f : 0.9f;
    RunSettings o;
    o.width = o.height = n;
    o.spp = 2;
    o.executor.importance = &importance;
    // Render, then look at the depth of what is left in D per pixel half.
    sched::Program program = testing::lower_or_die("{DDD}");
    RenderScene scene(s);
    Film film(n, n);
    Executor ex(scene, film, o.executor);
    RayBatch camera_rays;
    CameraRays cam(s.camera, n, n, scene.embree->origin_offset());
    for (uint32_t p = 0; p < static_cast<uint32_t>(n * n); ++p)
        for (uint32_t k = 0; k < 2; ++k) {
            RayRecord r;
            cam.generate(p % n + 0.5, p / n + 0.5, r.origin, r.direction);
            r.beta = {1, 1, 1};
            r.pixel = p;
            r.path = camera_path_id(0, p, k);
            camera_rays.push(r);
        }
    ex.run_camera_rays(camera_rays);
    ex.run(program.selective);
    const RayBatch& d = ex.bins()[static_cast<size_t>(Component::kD)];
    ASSERT_EQ(d.size(), static_cast<size_t>(n * n * 2));  // diffuse walls: one D child per ray
    for (size_t i = 0; i < d.size(); ++i) {
        bool left = (d.pixel[i] % n) < static_cast<uint32_t>(n / 2);
        EXPECT_EQ(d.depth[i], left ? 2 : 4) << "pixel " << d.pixel[i];
    }
    ASSERT_EQ(ex.stats().steps.size(), 3u);
    EXPECT_EQ(ex.stats().steps[0].rays, static_cast<uint64_t>(n * n * 2));
    EXPECT_EQ(ex.stats().steps[1].rays, static_cast<uint64_t>(n * n));  // right half only
    EXPECT_EQ(ex.stats().steps[2].rays, static_cast<uint64_t>(n * n));
}

TEST(ExecutorSemantics, ImportanceZeroRunsNoneAndOneRunsAll) {
    Scene s = testing::furnace_box(0.5, 0.1);
    for (double I : {0.0, 1.0}) {
        RunSettings o;
        o.width = o.height = 4;
        o.executor.constant_importance = I;
        RunResult r = render(s, testing::lower_or_die("{DD}"), o);
        EXPECT_EQ(r.stats.steps.size(), I == 0 ? 0u : 2u) << "I = " << I;
    }
}

// Two facing mirrors with the camera between them, looking straight at one.
Scene facing_mirrors(double reflectance) {
    Scene s;
    s.materials.push_back(make_material("mirror", MaterialType::kMirror, {reflectance, reflectance, reflectance}));
    s.materials.push_back(make_material("lamp", MaterialType::kLight, {1, 1, 1}));
    s.shapes.push_back(quad("mirror", {-50, -50, -1}, {50, -50, -1}, {50, 50, -1}, {-50, 50, -1}));
    s.shapes.push_back(quad("mirror", {-50, -50, 1}, {-50, 50, 1}, {50, 50, 1}, {50, -50, 1}));
    s.shapes.push_back(quad("lamp", {-0.1, 5, -0.1}, {0.1, 5, -0.1}, {0.1, 5, 0.1}, {-0.1, 5, 0.1}));
    s.camera.position = {0, 0, 0};
    s.camera.direction = {0, 0, -1};
    s.camera.vfov_deg = 1;
    return s;
}

TEST(ExecutorSemantics, StarTerminatesBetweenPerfectMirrorsAtTheDepthLimit) {
    // Perfect mirrors never lose weight: only max_depth (256) ends the bouncing, and '*'
    // stops at the first iteration without work, well before its cap.
    RunResult r = testing::render_crex(facing_mirrors(1.0), "M*", 4, 1);
    EXPECT_EQ(r.stats.components[static_cast<size_t>(Component::kM)].executions, 256u);
    EXPECT_TRUE(r.warnings.empty());
    EXPECT_TRUE(testing::all_finite(r.image()));
}

TEST(ExecutorSemantics, StarTerminatesBetweenLossyMirrorsByWeight) {
    RunSettings o;
    o.width = o.height = 4;
    o.executor.shade.roulette = false;
    RunResult r = render(facing_mirrors(0.9), testing::lower_or_die("(M)*"), o);
    // 0.9^k >= 1e-3 for k <= 65: 65 mirror bounces, then the weight limit drops the rays.
    EXPECT_EQ(r.stats.components[static_cast<size_t>(Component::kM)].executions, 65u);
}

TEST(ExecutorSemantics, StarCapStopsWithW401) {
    SourceFile f("<t>", "M*");
    DiagnosticSink sink;
    LowerOptions lo;
    lo.star_cap = 10;
    CompiledCrex c = compile_crex(f, sink, lo);
    RunSettings o;
    o.width = o.height = 2;
    RunResult r = render(facing_mirrors(1.0), *c.program, o);
    EXPECT_EQ(r.stats.components[static_cast<size_t>(Component::kM)].executions, 10u);
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_EQ(r.warnings[0].code, "W401");
    EXPECT_EQ(r.warnings[0].severity, Severity::kWarning);  // from the code table
    EXPECT_EQ(r.warnings[0].where, "<t>:1:1");
    EXPECT_EQ(render_text(r.warnings[0]), "<t>:1:1: warning[W401]: '*' stopped after 10 iterations (the cap) with work left\n");
}

TEST(ExecutorSemantics, AmbientStandsInForWaitingDiffuseRaysOnly) {
    Scene s = testing::furnace_box(0.5, 0);
    RunSettings o;
    o.width = o.height = 4;
    o.ambient = {0.2, 0.2, 0.2};
    // Camera rays only: every pixel has one D ray of weight 0.5 waiting: ambient = 0.5 * 0.2.
    RunResult r = render(s, testing::lower_or_die(""), o);
    EXPECT_NEAR(testing::mean_luminance(r.image()), 0.1, 1e-6);
    // After D* nothing waits in D, so the ambient term has faded to zero.
    RunResult all = render(s, testing::lower_or_die("D*"), o);
    EXPECT_NEAR(testing::mean_luminance(all.image()), 0.0, 1e-9);
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

// Under a budget with a fake clock (1 microsecond per ray executed, camera rays included)
// and a profile that knows that cost, admission is exact, so thesis fig. 5.13 can be checked
// without wall-clock timing: (TT[RS]G)*D executes as (TT[RS]G)* when the budget covers all
// but D, as TT[RS] with less, and as TT when [RS] would overrun.
struct BudgetRun {
    std::vector<StepRecord> steps;
    std::vector<SkippedTask> skipped;
};

constexpr int kBudgetSize = 32;

BudgetRun run_with_budget(const Scene& s, const std::string& crex, double budget_rays) {
    RunSettings o;
    o.width = o.height = kBudgetSize;
    o.spp = 1;
    Profile profile;
    for (const auto& row : kComponentTable) profile.record(row.component, 1000000, 1.0);
    double fake_now = 0;
    o.executor.profile = &profile;
    o.executor.budget_seconds = budget_rays * 1e-6;
    o.policy = pipeline::SchedulingPolicy::kTasks;  // whole tasks (a plain crex's default is progressive passes)
    o.executor.clock = [&] { return fake_now; };
    o.executor.progress = [&](const std::string&, uint64_t rays) { fake_now = static_cast<double>(rays) * 1e-6; };
    RunResult r = render(s, testing::lower_or_die(crex), o);
    return {r.stats.steps, r.stats.skipped};
}

std::string letters(const std::vector<StepRecord>& steps) {
    std::string out;
    for (const auto& st : steps) out += component_letter(st.component);
    return out;
}

// A glossy room (D, G) with a glass sphere (T, R) and an ideal metal sphere (S) in view.
Scene budget_scene() {
    Scene s = glossy_room();
    Material glass = make_material("glass", MaterialType::kGlass, {0.95, 0.95, 0.95});
    glass.ior = 1.5;
    Material steel = make_material("steel", MaterialType::kMetal, {0.9, 0.9, 0.9});
    steel.specularity = 0.9;
    s.materials.push_back(glass);
    s.materials.push_back(steel);
    Shape ball;
    ball.type = ShapeType::kSphere;
    ball.material = "glass";
    ball.center = {-0.4, -0.3, -0.5};
    ball.radius = 0.35;
    s.shapes.push_back(ball);
    ball.material = "steel";
    ball.center = {0.4, -0.3, -0.5};
    s.shapes.push_back(ball);
    return s;
}

TEST(BudgetScheduling, ThesisFigure513) {
    Scene scene = budget_scene();
    const std::string crex = "(TT[RS]G)*D";
    BudgetRun full = run_with_budget(scene, crex, 1e12);
    ASSERT_GE(full.steps.size(), 6u) << letters(full.steps);
    ASSERT_EQ(full.steps.back().component, Component::kD);
    ASSERT_TRUE(full.skipped.empty());
    uint64_t camera = kBudgetSize * kBudgetSize;
    uint64_t all = camera;
    for (const auto& st : full.steps) all += st.rays;
    const auto& f = full.steps;
    ASSERT_EQ(letters({f.begin(), f.begin() + 5}), "TTRSG");

    // All but D.
    BudgetRun a = run_with_budget(scene, crex, static_cast<double>(all - f.back().rays) + 0.5);
    EXPECT_EQ(letters(a.steps), letters({f.begin(), f.end() - 1}));
    ASSERT_FALSE(a.skipped.empty());
    EXPECT_EQ(a.skipped.back().what.substr(0, 1), "D");

    // Only the first TT[RS].
    BudgetRun b = run_with_budget(scene, crex, static_cast<double>(camera + f[0].rays + f[1].rays + f[2].rays + f[3].rays) + 0.5);
    EXPECT_EQ(letters(b.steps), "TTRS");

    // [RS] would overrun: TT only, and the group is reported as skipped.
    BudgetRun c = run_with_budget(scene, crex, static_cast<double>(camera + f[0].rays + f[1].rays) + 0.5);
    EXPECT_EQ(letters(c.steps), "TT");
    bool rs_skipped = false;
    for (const auto& sk : c.skipped) rs_skipped |= sk.what.rfind("[RS]", 0) == 0;
    EXPECT_TRUE(rs_skipped);
}

TEST(BudgetScheduling, WithoutAProfileAPilotRunsAndIsKept) {
    Scene s = testing::furnace_box(0.5, 0.1);
    RunSettings o;
    o.width = o.height = 20;  // 400 camera rays -> 400 D rays
    o.executor.chunk_rays = 10;
    Profile profile;
    o.executor.profile = &profile;
    o.executor.budget_seconds = 1e-9;  // nothing beyond the pilot fits
    o.policy = pipeline::SchedulingPolicy::kTasks;
    RunResult r = render(s, testing::lower_or_die("D"), o);
    ASSERT_EQ(r.stats.steps.size(), 1u);
    EXPECT_EQ(r.stats.steps[0].rays, 10u);  // max(1 % of 400, one chunk of 10)
    EXPECT_TRUE(profile.cost(Component::kD).has_value());
    EXPECT_EQ(r.rays_left[static_cast<size_t>(Component::kD)], 390u + 10u);  // the rest waits; the pilot spawned 10
}

// The profile weighs measurements by their rays: the last step of a loop (a few rays, mostly
// fixed overhead) no longer decides the cost (halving per measurement saved profiles 2-8x too
// dear, and tasks that fit were skipped on them), yet a change in cost is followed.
TEST(BudgetScheduling, ProfileWeighsMeasurementsByTheirRays) {
    Profile p;
    p.record(Component::kD, 100000, 0.1);  // 1 us per ray
    p.record(Component::kD, 10, 0.001);    // 100 us per ray, ten rays
    EXPECT_NEAR(*p.cost(Component::kD), 1e-6, 0.02e-6);
    for (int k = 0; k < 8; ++k) p.record(Component::kD, 65536, 65536 * 2e-6);  // the cost doubles
    EXPECT_NEAR(*p.cost(Component::kD), 2e-6, 0.02e-6);
}

// `n` cache queries in D's bin, spread over a 16x16 film's pixels.
void add_cache_queries(Executor& ex, uint32_t n) {
    RayBatch& d = ex.bins()[static_cast<size_t>(Component::kD)];
    for (uint32_t i = 0; i < n; ++i) {
        RayRecord r;
        r.direction = {0, 1, 0};
        r.beta = {1, 1, 1};
        r.pixel = i % 256;
        r.depth = 1;
        r.flags = kRayIcQuery;
        d.push(r);
    }
}

// Cache queries cost what the records they make cost, which no profile predicts: a profile
// that says 1 us a query, queries that take 100 us each (on the fake clock), and a queue of
// 4,096 of them under a 50 ms budget. The queue admits a batch of all 4,096 on the profile's
// figure (4 ms); run in one go it ended at 410 ms. Paced, its queries go in parts sized from
// the part before, each at most half the time left, and the rest waits in its bin: the stage
// ends within two queries' time of the budget, having run about 500.
TEST(BudgetScheduling, CacheQueriesDearerThanTheProfileSaysStopAtTheBudget) {
    Scene s = testing::furnace_box(0.5, 0.1);
    RenderScene scene(s);
    Film film(16, 16);
    Profile profile;
    profile.record(Component::kD, 1000000000, 1000.0);  // 1 us a ray, weighed as 10^9 rays
    double fake_now = 0;
    ExecutorOptions o;
    o.profile = &profile;
    o.budget_seconds = 0.05;
    o.clock = [&] { return fake_now; };
    o.task_admission = ExecutorOptions::TaskAdmission::kQueues;
    Executor ex(scene, film, o);
    ex.set_irradiance([&](const RayBatch&, size_t begin, size_t end, std::vector<Vec3>& e) {
        e.assign(end - begin, Vec3{1, 1, 1});
        fake_now += 100e-6 * static_cast<double>(end - begin);
    });
    add_cache_queries(ex, 4096);
    const sched::Program program = testing::lower_or_die("D");
    ex.run_stage(program.preselective);
    EXPECT_LE(fake_now, o.budget_seconds);
    EXPECT_GE(fake_now, o.budget_seconds - 2 * 100e-6);
    const uint64_t ran = ex.stats().components[static_cast<size_t>(Component::kD)].rays;
    EXPECT_EQ(ran + ex.bins()[static_cast<size_t>(Component::kD)].size(), 4096u) << "a query either ran or waits";
    EXPECT_NEAR(static_cast<double>(ran), 500.0, 3.0);
}

// Without a profile the first queries of a step are a pilot, whose cost is measured; cache
// queries cost what the records they make cost, so their pilot is paced too: 4,096 queries at
// 100 us each (the fake clock) and no profile made a pilot of one chunk of all 4,096, run whole
// in 410 ms of a 50 ms budget. And where queries turn dear inside a part (the 101st on cost
// 10 ms each), the cache stops (IrradianceCache::set_stop; its answers come back empty) and
// the stopped part waits in the bin with the rest.
TEST(BudgetScheduling, APilotOfCacheQueriesIsPacedAndAStoppedPartWaits) {
    Scene s = testing::furnace_box(0.5, 0.1);
    RenderScene scene(s);
    for (const bool turns_dear : {false, true}) {
        Film film(16, 16);
        double fake_now = 0;
        ExecutorOptions o;
        o.budget_seconds = 0.05;
        o.clock = [&] { return fake_now; };
        o.task_admission = ExecutorOptions::TaskAdmission::kWhole;
        Executor ex(scene, film, o);
        size_t answered = 0;
        bool stopped = false;
        ex.set_irradiance([&](const RayBatch&, size_t begin, size_t end, std::vector<Vec3>& e) {
            for (size_t i = begin; i < end; ++i) {
                fake_now += turns_dear && answered + i - begin >= 100 ? 10e-3 : 100e-6;
                if (ex.paced_queries_out_of_time()) {  // the cache's stop test, between its pieces
                    stopped = true;
                    e.clear();
                    return;
                }
            }
            answered += end - begin;
            e.assign(end - begin, Vec3{1, 1, 1});
        });
        add_cache_queries(ex, 4096);
        ex.run_stage(testing::lower_or_die("D").preselective);
        const uint64_t ran = ex.stats().components[static_cast<size_t>(Component::kD)].rays;
        EXPECT_EQ(ran, answered);
        EXPECT_EQ(ran + ex.bins()[static_cast<size_t>(Component::kD)].size(), 4096u) << "a query either ran or waits";
        EXPECT_GT(ran, 0u);
        EXPECT_LT(ran, 1000u);
        if (turns_dear) {
            EXPECT_TRUE(stopped);
            EXPECT_LE(fake_now, o.budget_seconds + 10e-3) << "one dear query past the budget at most";
        } else {
            EXPECT_FALSE(stopped) << "paced parts of half the time left end before the budget";
            EXPECT_LE(fake_now, o.budget_seconds);
        }
    }
}

// What a budget admits rays on follows this render's latest batches (RecentCosts) where the
// Profile, weighing 65,536 rays, lags: D queries that cost 5 us and then ten times that.
TEST(BudgetScheduling, RecentCostsFollowTheLatestBatches) {
    RecentCosts recent;
    recent.record(Component::kD, 32, 0.01);
    EXPECT_FALSE(recent.cost(Component::kD).has_value()) << "32 rays are their overhead, not a cost";
    recent.record(Component::kD, 2000, 2000 * 5e-6);
    EXPECT_NEAR(*recent.cost(Component::kD), 5e-6, 2e-6);
    recent.record(Component::kD, 2000, 2000 * 50e-6);
    EXPECT_GT(*recent.cost(Component::kD), 35e-6);
    Profile p;
    p.record(Component::kD, 65536, 65536 * 5e-6);
    p.record(Component::kD, 4000, 2000 * 5e-6 + 2000 * 50e-6);
    EXPECT_LT(*p.cost(Component::kD), 10e-6);
}

TEST(BudgetScheduling, ProfileRoundTripsThroughJson) {
    Profile p;
    p.record(Component::kT, 1000, 0.002);
    p.record_camera(10, 0.001);
    Profile q;
    ASSERT_EQ(Profile::from_json_text(p.to_json_text(), q), "");
    EXPECT_DOUBLE_EQ(*q.cost(Component::kT), 2e-6);
    EXPECT_DOUBLE_EQ(*q.camera_cost(), 1e-4);
    EXPECT_FALSE(q.cost(Component::kD).has_value());
    Profile bad;
    EXPECT_NE(Profile::from_json_text("{\"format\": \"crex-profile\", \"version\": 1, \"seconds_per_ray\": {\"X\": 1}}", bad), "");
    // Fields of another type are errors, not exceptions (profile_fuzzer's first finding: a
    // numeric "format" threw out of the reader).
    for (const char* text : {R"({"format": 1.33, "seconds_per_ray": {"D": 3.5e-06}})", R"({"format": "crex-profile", "version": "1"})",
                             R"({"format": "crex-profile", "version": 1, "seconds_per_ray": 7})",
                             R"({"format": "crex-profile", "version": 1, "seconds_per_ray": {"D": 1e999}})"}) {
        std::string error;
        EXPECT_NO_THROW(error = Profile::from_json_text(text, bad)) << text;
        EXPECT_NE(error, "") << text;
    }
}

// The full render's time of a saved profile: a string or null there was "internal error:
// [json.exception.type_error.302]" (issue 37); every number is located and ranged.
TEST(BudgetScheduling, ProfileNumbersAreCheckedWhereTheyAre) {
    Profile p;
    double full = -1;
    ASSERT_EQ(Profile::from_json_text(R"({"format": "crex-profile", "version": 1, "full_render_seconds": 1.5})", p, &full), "");
    EXPECT_EQ(full, 1.5);
    struct Case {
        const char* text;
        const char* said;
    };
    for (const Case& c : {Case{"", "p.json:1:1: the file is empty"},
                          Case{"  \n", "p.json:1:1: the file is empty"},
                          Case{"[1]", "p.json:1:1: expected a crex profile"},
                          Case{"{\"format\": \"crex-profile\", \"version\": 1,\n \"full_render_seconds\": \"x\"}",
                               "p.json:2:25: full_render_seconds: expected a number from 0 to 1000000, but this is string"},
                          Case{"{\"format\": \"crex-profile\", \"version\": 1, \"full_render_seconds\": null}",
                               "full_render_seconds: expected a number from 0 to 1000000, but this is null"},
                          Case{"{\"format\": \"crex-profile\", \"version\": 1, \"full_render_seconds\": -2}",
                               "full_render_seconds: -2 is out of range: expected a number from 0 to 1000000"},
                          Case{"{\"format\": \"crex-profile\", \"version\": 1, \"seconds_per_ray\": {\"D\": 1e9}}",
                               "seconds_per_ray.D: 1000000000 is out of range: expected a number from 0 to 1000"},
                          Case{"{\"format\": \"crex-profile\"", "p.json:1:"}}) {
        std::string error;
        EXPECT_NO_THROW(error = Profile::from_json_text(c.text, p, &full, "p.json")) << c.text;
        EXPECT_NE(error.find(c.said), std::string::npos) << c.text << "\n" << error;
    }
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(RepeatCounts, AHugeCountStopsAtTheFirstIterationWithoutWork) {
    // D2147483647 used to run two billion steps on empty bins. The image equals D1000's (paths
    // end by weight and depth long before), and the same holds for a repeated '*' and '[ ]'.
    Scene s = *builtin_scene("cornell_diffuse");
    auto image = [&](const std::string& crex) { return testing::render_crex(s, crex, 8, 1).image(); };
    std::vector<float> finite = image("D1000");
    EXPECT_EQ(image("D2147483647"), finite);
    EXPECT_EQ(image("(D*)2147483647"), image("(D*)1000"));
    EXPECT_EQ(image("[D]2147483647"), image("[D]1000"));
}

// --clamp L: with one camera sample and one D step, a pixel's D AOV holds one ray's
// contribution, so every pixel of it is at most L; camera rays (direct light) are untouched.
TEST(ExecutorSemantics, ClampBoundsIndirectContributionsOnly) {
    Scene s = glossy_room();
    RunSettings o;
    o.width = o.height = 8;
    o.spp = 1;
    RunResult free = render(s, testing::lower_or_die("D"), o);
    o.executor.clamp_indirect = 0.05;
    RunResult clamped = render(s, testing::lower_or_die("D"), o);
    std::vector<float> d_free = free.film.aov_image(aov_of(Component::kD));
    std::vector<float> d = clamped.film.aov_image(aov_of(Component::kD));
    ASSERT_GT(*std::max_element(d_free.begin(), d_free.end()), 0.05f) << "the test needs contributions above the clamp";
    for (float v : d) EXPECT_LE(v, 0.05f + 1e-6f);
    EXPECT_EQ(free.film.aov_image(kCameraAov), clamped.film.aov_image(kCameraAov));
}

}  // namespace
}  // namespace crex
