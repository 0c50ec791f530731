// The tree over many emitters (runtime/render/light_tree.h) and the choice of emitter it makes
// for a shading point once a scene has more than LightSampler::kLocalChoiceMax of them: its
// probabilities add up to at most 1 (the rest: a descent into a group none of whose emitters can
// light the point, a sample that brings nothing), it never leaves out an emitter that can light the point,
// it picks by those probabilities, and the irradiance it estimates is the one choosing by
// power estimates, with far less variance in a hall of many lamps.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "runtime/render/light_tree.h"
#include "runtime/render/render_scene.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

Vec3 random_unit(std::mt19937_64& rng) {
    std::normal_distribution<double> N(0, 1);
    return normalize_or_zero({N(rng), N(rng), N(rng)});
}

// 300 emitters in a 10 m cube: flat ones facing any way (corners a, b, c) and balls.
struct Emitters {
    std::vector<LightBound> bounds;
    std::vector<std::array<Vec3, 3>> triangles;  // a ball: centre, (radius, 0, 0), unused
    std::vector<bool> ball;
};
Emitters random_emitters(size_t n) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U(0, 1);
    Emitters e;
    for (size_t i = 0; i < n; ++i) {
        const Vec3 c{10 * U(rng), 10 * U(rng), 10 * U(rng)};
        LightBound b;
        b.power = 0.1 + U(rng);
        if (i % 7 == 0) {
            const double r = 0.05 + 0.2 * U(rng);
            b.lo = c - Vec3{r, r, r}, b.hi = c + Vec3{r, r, r}, b.axis = {0, 0, 1}, b.cos_spread = -1;
            e.triangles.push_back({c, Vec3{r, 0, 0}, Vec3{}});
            e.ball.push_back(true);
        } else {
            const Vec3 p = c + random_unit(rng) * 0.3, q = c + random_unit(rng) * 0.3;
            b.lo = vmin(c, vmin(p, q)), b.hi = vmax(c, vmax(p, q));
            b.axis = normalize_or_zero(cross(p - c, q - c)), b.cos_spread = 1;
            e.triangles.push_back({c, p, q});
            e.ball.push_back(false);
        }
        e.bounds.push_back(b);
    }
    return e;
}

// Whether some point of emitter i lights x (normal n, or any side): a flat emitter must face x
// from one of its corners, and that corner be above x's horizon.
bool can_light(const Emitters& e, size_t i, const Vec3& x, const Vec3* n) {
    if (e.ball[i]) return !n || dot(e.triangles[i][0] - x, *n) > -e.triangles[i][1].x;
    const auto& t = e.triangles[i];
    const Vec3 normal = normalize_or_zero(cross(t[1] - t[0], t[2] - t[0]));
    if (!(dot(x - t[0], normal) > 0)) return false;
    if (!n) return true;
    for (const Vec3& corner : t)
        if (dot(corner - x, *n) > 0) return true;
    return false;
}

TEST(LightTree, ItsProbabilitiesAreADistributionThatLeavesOutNoEmitterThatCanLightThePoint) {
    const Emitters e = random_emitters(300);
    const LightTree tree(e.bounds);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> U(0, 1);
    for (int k = 0; k < 200; ++k) {
        const Vec3 x{-2 + 14 * U(rng), -2 + 14 * U(rng), -2 + 14 * U(rng)}, n = random_unit(rng);
        const Vec3* normal = k % 2 ? &n : nullptr;
        auto exact = [&](uint32_t slot) {
            const uint32_t i = tree.emitter_at(slot);
            return can_light(e, i, x, normal) ? e.bounds[i].power : 0.0;
        };
        double sum = 0;
        size_t lit = 0;
        for (uint32_t i = 0; i < e.bounds.size(); ++i) {
            const double p = tree.probability(i, x, normal, exact);
            sum += p;
            if (can_light(e, i, x, normal)) {
                ++lit;
                EXPECT_GT(p, 0) << "emitter " << i << " can light point " << k;
            } else {
                EXPECT_EQ(p, 0) << "emitter " << i << " cannot light point " << k;
            }
        }
        EXPECT_LE(sum, 1.0 + 1e-9) << "point " << k;
        if (lit > 0) {
            EXPECT_GT(sum, 0.0) << "point " << k;
        }
    }
}

TEST(LightTree, ItChoosesByItsProbabilities) {
    const Emitters e = random_emitters(120);
    const LightTree tree(e.bounds);
    const Vec3 x{5, 5, 1}, n{0, 0, 1};
    auto exact = [&](uint32_t slot) {
        const uint32_t i = tree.emitter_at(slot);
        return can_light(e, i, x, &n) ? e.bounds[i].power : 0.0;
    };
    const size_t draws = 400000;
    std::vector<size_t> count(e.bounds.size(), 0);
    size_t lost = 0;
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> U(0, 1);
    for (size_t k = 0; k < draws; ++k) {
        const LightTree::Choice c = tree.choose(x, &n, U(rng), exact);
        if (!(c.probability > 0)) {
            ++lost;
            continue;
        }
        ASSERT_LT(c.index, e.bounds.size());
        EXPECT_DOUBLE_EQ(c.probability, tree.probability(c.index, x, &n, exact));
        EXPECT_GE(c.rescaled, 0);
        EXPECT_LT(c.rescaled, 1);
        ++count[c.index];
    }
    // Each emitter's share within 5 binomial standard deviations of its probability; the
    // draws that found none, of what the probabilities leave.
    auto near_expected = [&](size_t seen, double p, const std::string& what) {
        const double sd = std::sqrt(draws * p * (1 - p));
        EXPECT_NEAR(static_cast<double>(seen), draws * p, 5 * sd + 1) << what;
    };
    double sum = 0;
    for (uint32_t i = 0; i < e.bounds.size(); ++i) {
        const double p = tree.probability(i, x, &n, exact);
        sum += p;
        near_expected(count[i], p, "emitter " + std::to_string(i));
    }
    near_expected(lost, std::fmax(0.0, 1 - sum), "none");
}

// The tree holds its bounds in single precision: a scene in microns or in kilometres (positions
// times s, powers times s^2, so what each emitter brings is the same) must get the same choices.
TEST(LightTree, ItsProbabilitiesDoNotDependOnTheScenesUnits) {
    const Emitters e = random_emitters(300);
    const LightTree tree(e.bounds);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> U(0, 1);
    for (const double s : {1e-5, 1e-2, 1e3, 1e6}) {
        std::vector<LightBound> scaled = e.bounds;
        for (LightBound& b : scaled) b.lo = b.lo * s, b.hi = b.hi * s, b.power *= s * s;
        const LightTree other(scaled);
        for (int k = 0; k < 20; ++k) {
            const Vec3 x{14 * U(rng) - 2, 14 * U(rng) - 2, 14 * U(rng) - 2}, n = random_unit(rng);
            auto exact = [&](uint32_t slot) {
                const uint32_t i = tree.emitter_at(slot);
                return can_light(e, i, x, &n) ? e.bounds[i].power : 0.0;
            };
            auto exact_scaled = [&](uint32_t slot) {
                const uint32_t i = other.emitter_at(slot);
                return can_light(e, i, x, &n) ? scaled[i].power : 0.0;
            };
            for (uint32_t i = 0; i < e.bounds.size(); ++i) {
                const double p = tree.probability(i, x, &n, exact), q = other.probability(i, x * s, &n, exact_scaled);
                EXPECT_NEAR(q, p, 1e-3 * p + 1e-12) << "scale " << s << ", point " << k << ", emitter " << i;
            }
        }
    }
}

// Degenerate groups: every emitter at one point, boxes of no size, a normal of zero length,
// emitters of no power, and the counts around a leaf's and a node's sizes. The probabilities stay
// a distribution with no NaN, and every choice is of an emitter that can be chosen.
TEST(LightTree, DegenerateEmittersStillGiveADistribution) {
    std::vector<std::vector<LightBound>> cases;
    for (const size_t n : {1, 2, 8, 9, 16, 17, 33, 65, 257}) {
        std::vector<LightBound> same(n), flat(n);
        for (size_t i = 0; i < n; ++i) {
            same[i].lo = same[i].hi = Vec3{1, 2, 3};
            same[i].axis = i % 3 ? Vec3{0, 0, -1} : Vec3{};  // some with no normal at all
            same[i].power = i % 4 ? 1.0 : 0.0;
            flat[i].lo = flat[i].hi = Vec3{static_cast<double>(i % 5), 0, static_cast<double>(i / 5)};
            flat[i].axis = {0, 1, 0};
            flat[i].power = 1e-20 * static_cast<double>(i + 1);
        }
        cases.push_back(same);
        cases.push_back(flat);
    }
    const Vec3 up{0, 1, 0}, down{0, -1, 0};
    for (const auto& lights : cases) {
        const LightTree tree(lights);
        ASSERT_EQ(tree.slots(), lights.size());
        for (const Vec3 x : {Vec3{1, 2, 3}, Vec3{1, 1, 3}, Vec3{2, 5, 2}, Vec3{-4, -1, 0}})
            for (const Vec3* normal : {static_cast<const Vec3*>(nullptr), &up, &down}) {
                auto power = [&](uint32_t slot) { return lights[tree.emitter_at(slot)].power; };
                double sum = 0;
                for (uint32_t i = 0; i < lights.size(); ++i) {
                    const double p = tree.probability(i, x, normal, power);
                    ASSERT_TRUE(std::isfinite(p) && p >= 0) << lights.size() << " emitters";
                    if (!(lights[i].power > 0)) {
                        EXPECT_EQ(p, 0);
                    }
                    sum += p;
                }
                EXPECT_LE(sum, 1 + 1e-9);
                for (const double u : {0.0, 0.3, 0.999999999}) {
                    const LightTree::Choice c = tree.choose(x, normal, u, power);
                    if (!(c.probability > 0)) continue;
                    ASSERT_LT(c.index, lights.size());
                    EXPECT_EQ(tree.emitter_at(c.slot), c.index);
                    EXPECT_GT(lights[c.index].power, 0);
                    EXPECT_DOUBLE_EQ(c.probability, tree.probability(c.index, x, normal, power));
                }
            }
    }
}

// A 20 x 20 m hall lit by 10 x 10 small panels 3 m up (200 triangles): the irradiance at a
// point of the floor, from samples chosen by the tree and chosen by power.
struct Irradiance {
    double mean = 0, variance = 0;
};
Irradiance floor_irradiance(const RenderScene& rs, const Vec3& at, bool by_tree, size_t n) {
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> U(0, 1);
    const Vec3 x = at - rs.embree->origin_offset(), up{0, 1, 0};
    double sum = 0, sum2 = 0;
    for (size_t i = 0; i < n; ++i) {
        const double a = U(rng), b = U(rng), c = U(rng);
        const LightSample ls = by_tree ? rs.lights->sample(rs.lights->weights_at(x, &up), a, b, c) : rs.lights->sample(a, b, c);
        double f = 0;
        if (ls.pdf_area > 0) {
            const Vec3 to = ls.position - x;
            const double d2 = dot(to, to);
            const Vec3 wi = to / std::sqrt(d2);
            f = ls.radiance.y * std::fmax(0.0, dot(wi, up)) * std::fmax(0.0, -dot(ls.normal, wi)) / (d2 * ls.pdf_area);
        }
        sum += f, sum2 += f * f;
    }
    const double mean = sum / static_cast<double>(n);
    return {mean, std::fmax(0.0, sum2 / static_cast<double>(n) - mean * mean)};
}

TEST(LightTree, AHallOfLampsGetsTheSameIrradianceWithFarLessVariance) {
    Scene s;
    s.materials.push_back(testing::make_material("lamp", MaterialType::kLight, {10, 10, 10}));
    const double h = 0.15;
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j) {
            const double x = 1 + 2 * i, z = 1 + 2 * j;
            s.shapes.push_back(testing::quad("lamp", {x - h, 3, z - h}, {x + h, 3, z - h}, {x + h, 3, z + h}, {x - h, 3, z + h}));  // faces down
        }
    s.camera.position = {10, 1.5, 25};
    s.camera.direction = {0, 0, -1};
    s.camera.up = {0, 1, 0};
    RenderScene rs(s);
    const size_t n = 400000;
    for (const Vec3 at : {Vec3{1, 0, 1}, Vec3{10, 0, 10}, Vec3{4.5, 0, 17.2}}) {
        const Irradiance tree = floor_irradiance(rs, at, true, n), power = floor_irradiance(rs, at, false, n);
        const double se = std::sqrt((tree.variance + power.variance) / static_cast<double>(n));
        EXPECT_NEAR(tree.mean, power.mean, 5 * se) << at.x << ", " << at.z;
        EXPECT_LT(tree.variance, 0.25 * power.variance) << at.x << ", " << at.z;
    }
}

}  // namespace
}  // namespace crex
