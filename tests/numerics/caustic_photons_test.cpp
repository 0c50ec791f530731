// The caustic photon map beside the irradiance cache: right where the answer is known (a
// mirror's image of a lamp), deterministic, absent where a scene has no caustics or light only
// goes straight through a screen (direct lighting's), and the reason it exists: the cache's
// caustics far quieter than from its hemisphere rays.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <unistd.h>

#include "runtime/cache/caustic_photons.h"
#include "runtime/cache/irradiance_cache.h"
#include "runtime/scene/load_scene.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

// A lamp (half side 0.1, radiance L, facing down) at y = 1 over a mirror floor (reflectance
// rho) at y = 0, under a diffuse ceiling at y = 3: the ceiling sees the lamp only in the
// mirror.
constexpr double kL = 20, kRho = 0.9, kHalf = 0.1, kLamp = 1, kCeiling = 3;

Scene mirror_under_lamp() {
    Scene s;
    s.materials.push_back(testing::make_material("mirror", MaterialType::kMirror, {kRho, kRho, kRho}));
    s.materials.push_back(testing::make_material("lamp", MaterialType::kLight, {kL, kL, kL}));
    s.materials.push_back(testing::make_material("ceiling", MaterialType::kPlastic, {0.5, 0.5, 0.5}));
    const double w = 3;
    s.shapes.push_back(build::quad("mirror", {-w, 0, w}, {w, 0, w}, {w, 0, -w}, {-w, 0, -w}));
    s.shapes.push_back(build::quad("lamp", {-kHalf, kLamp, -kHalf}, {kHalf, kLamp, -kHalf}, {kHalf, kLamp, kHalf}, {-kHalf, kLamp, kHalf}));
    s.shapes.push_back(build::quad("ceiling", {-w, kCeiling, -w}, {w, kCeiling, -w}, {w, kCeiling, w}, {-w, kCeiling, w}));
    s.camera.position = {0, 2, 5};
    s.camera.direction = {0, 0, -1};
    return s;
}

// Irradiance at ceiling point (x, kCeiling, z) from a lamp square of half side kHalf and
// radiance kL, parallel to the ceiling at distance h below it and facing it: midpoint
// quadrature over the square.
double lamp_irradiance(double x, double z, double h) {
    const int n = 200;
    const double cell = 2 * kHalf / n;
    double e = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            double dx = x - (-kHalf + (i + 0.5) * cell), dz = z - (-kHalf + (j + 0.5) * cell);
            double r2 = dx * dx + dz * dz + h * h;
            e += kL * (h * h / r2) / r2 * cell * cell;  // cos at the lamp x cos at the ceiling / r^2
        }
    return e;
}

// The map's irradiance on the ceiling (facing down) against `expect`, averaged over 7 x 7
// points 0.07 apart around each place: each place within `each`, all of them within `all`.
// Each estimate is k = 32 photons, blended with the others whose discs hold the point: about
// 10 % noise whatever the photon count; the 49 points average it to about 5 %, the places
// together to about 2 %.
void expect_ceiling_irradiance(const RenderScene& rs, const CausticPhotons& map, const std::vector<std::pair<double, double>>& places,
                               const std::function<double(double, double)>& expect_at, double each, double all) {
    const Vec3 down{0, -1, 0}, offset = rs.embree->origin_offset();
    double all_expect = 0, all_got = 0;
    for (auto [x, z] : places) {
        double expect = 0, got = 0;
        for (int i = -3; i <= 3; ++i)
            for (int j = -3; j <= 3; ++j) {
                double px = x + 0.07 * i, pz = z + 0.07 * j;
                expect += expect_at(px, pz) / 49;
                Vec3 e = map.irradiance(Vec3{px, kCeiling, pz} - offset, down);
                got += e.x / 49;
                EXPECT_EQ(e.x, e.y);  // a grey lamp through grey surfaces
                // The ceiling's far side holds no caustic.
                EXPECT_EQ(map.irradiance(Vec3{px, kCeiling, pz} - offset, Vec3{0, 1, 0}).x, 0.0);
            }
        EXPECT_NEAR(got, expect, each * expect) << x << ", " << z;
        all_expect += expect, all_got += got;
    }
    EXPECT_NEAR(all_got, all_expect, all * all_expect);
}

TEST(CausticPhotons, AMirrorsCausticIsTheIrradianceOfTheLampsImage) {
    Scene s = mirror_under_lamp();
    RenderScene rs(s);
    CausticPhotonSettings set;
    set.photons = 1000000;
    CausticPhotons map(rs, set);
    ASSERT_FALSE(map.empty());
    // Around points whose path from the image (at y = -kLamp) passes beside the lamp (not
    // through its back); three seeds: each place within 7.9 %, all within 2.5 %.
    expect_ceiling_irradiance(rs, map, {{1.0, 0.0}, {-1.0, 0.5}, {0.5, -1.0}, {1.5, 1.0}, {-2.0, -1.5}},
                              [](double x, double z) { return kRho * lamp_irradiance(x, z, kCeiling + kLamp); }, 0.1, 0.04);
}

// A lamp (half side `half`, radiance L, facing up) at y = 0 under a frosted screen (trans) at
// y = 1, under a diffuse ceiling at y = 3: the ceiling sees the lamp only through the screen.
constexpr double kScreen = 1, kTransmissivity = 0.5, kTransmittedSpecular = 0.6;

Scene lamp_under_screen(double half) {
    Scene s;
    Material screen = testing::make_material("screen", MaterialType::kTrans, {1, 1, 1});
    screen.transmissivity = kTransmissivity;
    screen.transmitted_specular = kTransmittedSpecular;
    s.materials.push_back(screen);
    s.materials.push_back(testing::make_material("lamp", MaterialType::kLight, {kL, kL, kL}));
    s.materials.push_back(testing::make_material("ceiling", MaterialType::kPlastic, {0.5, 0.5, 0.5}));
    const double w = 3;
    s.shapes.push_back(build::quad("screen", {-w, kScreen, -w}, {w, kScreen, -w}, {w, kScreen, w}, {-w, kScreen, w}));
    s.shapes.push_back(build::quad("lamp", {-half, 0, half}, {half, 0, half}, {half, 0, -half}, {-half, 0, -half}));
    s.shapes.push_back(build::quad("ceiling", {-w, kCeiling, -w}, {w, kCeiling, -w}, {w, kCeiling, w}, {-w, kCeiling, w}));
    s.camera.position = {0, 2, 5};
    s.camera.direction = {0, 0, -1};
    return s;
}

TEST(CausticPhotons, ALampSeenStraightThroughAFrostedScreenIsDirectLightings) {
    // A trans surface's specular transmission goes straight on, so direct lighting's shadow
    // rays cross the screen (as RADIANCE's do) and bring the lamp's light through it: the map,
    // which holds light that bent on its way (mirrors, refraction), keeps none of it. Before
    // shadow rays crossed trans, the map held exactly this light.
    Scene s = lamp_under_screen(kHalf);
    {
        RenderScene rs(s);
        CausticPhotonSettings set;
        set.photons = 200000;
        CausticPhotons map(rs, set);
        EXPECT_EQ(map.irradiance(Vec3{0, kCeiling, 0} - rs.embree->origin_offset(), {0, -1, 0}).x, 0.0);
    }
    // The ceiling over the lamp seen from below through a 1-degree view, camera rays only: its
    // radiance is rho / pi times the lamp's irradiance through the screen, t ts (undeviated,
    // colour 1). 16 x 16 pixels, 16 samples of 4 shadow rays: about 0.5 % noise.
    s.camera.position = {0, 2.5, 0};
    s.camera.direction = {0, 1, 0};
    s.camera.up = {0, 0, -1};
    s.camera.vfov_deg = 1;
    const double expected = 0.5 / kPi * kTransmissivity * kTransmittedSpecular * lamp_irradiance(0, 0, kCeiling);
    EXPECT_NEAR(testing::mean_luminance(testing::render_crex(s, "", 16, 16, 0, 4).image()) / expected, 1.0, 0.02);
}

TEST(CausticPhotons, ASceneWithoutMirrorsOrGlassHasNone) {
    Scene s = *builtin_scene("cornell_diffuse");
    RenderScene rs(s);
    CausticPhotons map(rs, {});
    EXPECT_TRUE(map.empty());
    EXPECT_EQ(map.irradiance({0, 0, 0}, {0, 1, 0}).x, 0.0);
}

TEST(CausticPhotons, TheMapDoesNotDependOnTheThreadCount) {
    Scene s = *builtin_scene("cornell");
    RenderScene rs(s);
    CausticPhotonSettings set;
    set.photons = 50000;
    std::vector<Vec3> one, two;
    for (int threads : {1, 2}) {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
        CausticPhotons map(rs, set);
        auto& out = threads == 1 ? one : two;
        for (int i = 0; i < 20; ++i) out.push_back(map.irradiance(Vec3{-0.9 + 0.09 * i, -1, 0.3} - rs.embree->origin_offset(), {0, 1, 0}));
    }
    EXPECT_EQ(one, two);
    double sum = 0;
    for (const Vec3& e : one) sum += e.x;
    EXPECT_GT(sum, 0.0);  // the glass ball's caustic lies on this line of the floor
}

// The map is built before the first camera ray and 20 million photons took 54 s without a
// word: it says how far it got, phase by phase, each from 0 to 1, and the map is the same.
TEST(CausticPhotons, TheBuildSaysHowFarItGotPhaseByPhase) {
    Scene s = *builtin_scene("cornell");
    RenderScene rs(s);
    CausticPhotonSettings set;
    set.photons = 150000;  // three chunks of 64 Ki photons
    CausticPhotons quiet(rs, set);
    std::vector<std::pair<std::string, double>> said;
    set.progress = [&](const char* phase, double done) { said.emplace_back(phase, done); };
    CausticPhotons told(rs, set);
    ASSERT_FALSE(said.empty());
    std::vector<std::string> phases;
    for (size_t i = 0; i < said.size(); ++i) {
        if (phases.empty() || phases.back() != said[i].first) {
            phases.push_back(said[i].first);
            EXPECT_EQ(said[i].second, 0.0) << said[i].first << " starts at 0";
        } else {
            EXPECT_GE(said[i].second, said[i - 1].second) << said[i].first;
        }
        if (i + 1 == said.size() || said[i + 1].first != said[i].first) {
            EXPECT_TRUE(said[i].first == "photon tree" || said[i].second == 1.0) << said[i].first << " ends at 1";
        }
    }
    EXPECT_EQ(phases, (std::vector<std::string>{"tracing", "photon tree", "density estimates"}));
    EXPECT_EQ(std::count_if(said.begin(), said.end(), [](const auto& p) { return p.first == "tracing"; }), 4) << "0, then per chunk";
    for (int i = 0; i < 20; ++i) {
        const Vec3 x = Vec3{-0.9 + 0.09 * i, -1, 0.3} - rs.embree->origin_offset();
        EXPECT_EQ(told.irradiance(x, {0, 1, 0}), quiet.irradiance(x, {0, 1, 0}));
    }
}

TEST(CausticPhotons, AQueryBlendsEveryEstimateWhoseDiscHoldsIt) {
    // The map finds a query's estimates through a grid of the cells their discs reach: the
    // answer must be the blend over all estimates, looked at one by one, whose disc holds the
    // point and faces its side, added in index order. Points on and near the Cornell box's
    // walls, floor and ceiling (where the glass ball's caustic and the mirror ball's
    // reflections land), and a few beyond it.
    Scene s = *builtin_scene("cornell");
    RenderScene rs(s);
    CausticPhotonSettings set;
    set.photons = 50000;
    CausticPhotons map(rs, set);
    ASSERT_FALSE(map.estimates().empty());
    auto blend_of_all = [&](const Vec3& x, const Vec3& n) {
        const float q[3] = {static_cast<float>(x.x), static_cast<float>(x.y), static_cast<float>(x.z)};
        double sum_w = 0;
        Vec3 sum{};
        for (const CausticPhotons::Estimate& e : map.estimates()) {
            const float dx = q[0] - e.position[0], dy = q[1] - e.position[1], dz = q[2] - e.position[2];
            const float d2 = dx * dx + dy * dy + dz * dz;
            if (!(d2 < e.radius2) || !(dot(Vec3{e.normal[0], e.normal[1], e.normal[2]}, n) > 0.5)) continue;
            const double w = (1 - d2 / e.radius2) / e.radius2;
            sum_w += w;
            sum += Vec3{e.irradiance[0], e.irradiance[1], e.irradiance[2]} * w;
        }
        return sum_w > 0 ? sum / sum_w : Vec3{};
    };
    const Vec3 offset = rs.embree->origin_offset();
    size_t lit = 0;
    uint64_t state = 0x9e3779b97f4a7c15ull;
    auto uniform = [&] { return static_cast<double>((state = state * 6364136223846793005ull + 1442695040888963407ull) >> 11) * 0x1.0p-53; };
    const Vec3 normals[6] = {{0, 1, 0}, {0, -1, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int i = 0; i < 20000; ++i) {
        const int face = i % 6;
        const Vec3 n = normals[face];
        // A point on the face the normal looks away from (the floor for up), within 0.02 of it.
        Vec3 p{2.4 * uniform() - 1.2, 2.4 * uniform() - 1.2, 2.4 * uniform() - 1.2};
        const double wall = -1 + 0.02 * uniform();
        if (n.x != 0) p.x = n.x * wall;
        if (n.y != 0) p.y = n.y * wall;
        if (n.z != 0) p.z = n.z * wall;
        const Vec3 x = p - offset;
        const Vec3 got = map.irradiance(x, n), want = blend_of_all(x, n);
        ASSERT_EQ(got, want) << "at " << p.x << ", " << p.y << ", " << p.z << " facing " << face;
        lit += got.x > 0;
    }
    RecordProperty("points_lit", static_cast<int>(lit));
    EXPECT_GT(lit, 1000u);  // the points meet the caustics, not only the dark
}

// E at points of the Cornell box's ceiling (lit only by bounces and the mirror ball's caustic)
// from a cache of the given seed, with or without the map.
std::vector<double> ceiling_irradiance(const RenderScene& rs, uint64_t seed, uint32_t photons) {
    IcSettings set;
    set.divisions = 64, set.bounces = 2, set.accuracy = 0.1, set.seed = seed, set.caustic_photons = photons;
    IrradianceCache cache(rs, set);
    std::vector<IcQuery> q;
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) {
            Vec3 p{-0.9 + 0.25 * i, 0.999, -0.9 + 0.25 * j};
            if (std::fabs(p.x) < 0.3 && std::fabs(p.z) < 0.3) continue;  // the lamp
            q.push_back({p - rs.embree->origin_offset(), {0, -1, 0}, 0.1f, 0, seed * 1000 + q.size() + 1});
        }
    std::vector<Vec3> e;
    cache.irradiance(q, 0, e);
    std::vector<double> out;
    for (const Vec3& v : e) out.push_back(luminance(v));
    return out;
}

// How much two caches that differ in their seed only disagree: the relative RMS difference of
// `values(seed)` over the seed pairs, and (in `mean`) the mean of all the values.
double seed_to_seed_spread(const std::function<std::vector<double>(uint64_t)>& values, const std::vector<std::pair<uint64_t, uint64_t>>& pairs,
                           double& mean) {
    double d2 = 0, m = 0;
    size_t count = 0;
    for (auto [first, second] : pairs) {
        std::vector<double> a = values(first), b = values(second);
        for (size_t i = 0; i < a.size(); ++i) d2 += (a[i] - b[i]) * (a[i] - b[i]), m += a[i] + b[i];
        count += a.size();
    }
    mean = m / (2.0 * static_cast<double>(count));
    return std::sqrt(d2 / static_cast<double>(count)) / mean;
}

// The same light estimated two ways, by the caustic map (200,000 photons) or by the records'
// hemisphere rays (none): the means of `values(seed, photons)` agree within 10 %, and the map's
// seed-to-seed spread is under half the rays'.
void expect_the_map_quieter_and_the_same(const std::function<std::vector<double>(uint64_t, uint32_t)>& values,
                                         const std::vector<std::pair<uint64_t, uint64_t>>& pairs) {
    double mean_map = 0, mean_rays = 0;
    const double with_map = seed_to_seed_spread([&](uint64_t seed) { return values(seed, 200000); }, pairs, mean_map);
    const double with_rays = seed_to_seed_spread([&](uint64_t seed) { return values(seed, 0); }, pairs, mean_rays);
    ::testing::Test::RecordProperty("seed_to_seed_relative_rms_with_map", std::to_string(with_map));
    ::testing::Test::RecordProperty("seed_to_seed_relative_rms_without", std::to_string(with_rays));
    EXPECT_LT(with_map, 0.5 * with_rays);
    EXPECT_NEAR(mean_map, mean_rays, 0.1 * mean_rays);
}

TEST(IrradianceCache, CausticsFromThePhotonMapAreFarQuieterThanFromHemisphereRays) {
    Scene s = *builtin_scene("cornell");
    RenderScene rs(s);
    expect_the_map_quieter_and_the_same([&](uint64_t seed, uint32_t photons) { return ceiling_irradiance(rs, seed, photons); }, {{1, 2}});
}

TEST(IrradianceCache, RecordsDoNotCountALampDirectLightingBringsThroughAClearScreen) {
    // A clear screen (all its light transmitted, straight on) between the lamp and the ceiling:
    // direct lighting's shadow rays cross it, so a hemisphere ray from the ceiling that passes
    // it and meets the lamp must take nothing (the ceiling faces nothing else that is lit). It
    // took the lamp's light, counting it twice, before shadow rays crossed trans surfaces.
    Scene s = lamp_under_screen(0.5);
    for (Material& m : s.materials)
        if (m.name == "screen") m.transmissivity = 1, m.transmitted_specular = 1;
    RenderScene rs(s);
    IcSettings set;
    set.divisions = 256, set.bounces = 2, set.accuracy = 0.1, set.caustic_photons = 0;
    IrradianceCache cache(rs, set);
    std::vector<IcQuery> q;
    for (int i = 0; i < 4; ++i) q.push_back({Vec3{-0.75 + 0.5 * i, kCeiling, 0.25} - rs.embree->origin_offset(), {0, -1, 0}, 0.1f, 0, q.size() + 1});
    std::vector<Vec3> e;
    cache.irradiance(q, 0, e);
    ASSERT_EQ(e.size(), q.size());
    for (const Vec3& v : e) EXPECT_EQ(luminance(v), 0.0);
}

TEST(IrradianceCache, AFileMadeWithoutTheCausticMapIsRefusedByOneWithIt) {
    Scene s = *builtin_scene("cornell");
    RenderScene rs(s);
    IcSettings without;
    without.divisions = 16, without.bounces = 1, without.caustic_photons = 0;
    IrradianceCache made(rs, without);
    std::vector<Vec3> e;
    made.irradiance({{Vec3{0, -0.999, 0} - rs.embree->origin_offset(), {0, 1, 0}, 0.2f, 0, 1}}, 0, e);
    std::string path = (std::filesystem::temp_directory_path() / ("crex_caustic_" + std::to_string(::getpid()) + ".ic")).string();
    ASSERT_EQ(made.save(path), "");
    IcSettings with = without;
    with.caustic_photons = 20000;
    IrradianceCache refuse(rs, with);
    EXPECT_NE(refuse.load(path), "");  // its records hold the caustics the map would add again
    EXPECT_TRUE(refuse.records().empty());
    IrradianceCache same(rs, without);
    EXPECT_EQ(same.load(path), "");
    std::filesystem::remove(path);
}

// Path tracing without the cache takes the same map (RunSettings::caustic_photons): a ceiling
// lit only by a lamp's image in a mirror comes out as bright as path tracing makes it (counted
// once: the D rays that find the image through the mirror bring nothing), and at 16 spp without
// the fireflies of the rare D rays that do find it.
TEST(CausticPhotons, PathTracingTakesAMirrorsCausticFromTheMap) {
    Scene s = mirror_under_lamp();
    s.camera.position = {0, 1.5, 1.5};  // above the lamp's dark back, looking up at the ceiling
    s.camera.direction = {0, 1, -0.6};
    s.camera.vfov_deg = 70;
    auto rendered = [&](uint32_t photons, uint32_t spp) {
        RunSettings o;
        o.width = o.height = 16;
        o.spp = spp;
        o.caustic_photons = photons;
        return render(s, testing::lower_or_die("(TTMRSGD)*"), o).image();
    };
    // 4096 spp: about 800 D rays find the image over the frame, so its mean is within 4 %.
    const std::vector<float> traced = rendered(0, 4096), mapped = rendered(200000, 16), traced16 = rendered(0, 16);
    const double truth = testing::mean_luminance(traced);
    ASSERT_GT(truth, 0.0);
    EXPECT_NEAR(testing::mean_luminance(mapped), truth, 0.12 * truth);  // counted twice, it would be twice as bright
    auto rms_from_traced = [&](const std::vector<float>& img) {
        double sum = 0;
        for (size_t i = 0; i < img.size(); ++i) sum += (img[i] - traced[i]) * (img[i] - traced[i]);
        return std::sqrt(sum / static_cast<double>(img.size()));
    };
    EXPECT_LT(rms_from_traced(mapped), 0.5 * rms_from_traced(traced16));
}

}  // namespace
}  // namespace crex
