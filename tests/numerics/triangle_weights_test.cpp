// The local weights of a few flat emitters in vector code (runtime/render/triangle_weights.h):
// the rule of LightSampler's scalar weights, value for value, at points in front of, behind,
// inside the reach of and on the corners of the triangles, with and without a horizon, for
// any count of triangles (the last vector half full); a parallelogram's fourth corner counts.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "runtime/render/triangle_weights.h"

namespace crex {
namespace {

// The rule as docs/runtime.md states it, one triangle at a time.
double scalar_weight(const WeighedTriangle& t, const Vec3& x, const Vec3* horizon) {
    if (horizon && dot(t.a - x, *horizon) <= 0 && dot(t.b - x, *horizon) <= 0 && dot(t.c - x, *horizon) <= 0 && dot(t.d - x, *horizon) <= 0) return 0;
    if (!(dot(x - t.a, t.normal) > 0)) return 0;
    const Vec3 d = x - t.centre;
    const double d2 = dot(d, d);
    const double w = t.power / max_of(d2, t.area);
    if (!(d2 > t.reach * t.reach)) return w;
    const double inv_d = 1 / std::sqrt(d2), sin_b = t.reach * inv_d;
    double cosines = min_of(1.0, dot(d, t.normal) * inv_d + sin_b);
    if (horizon) cosines *= min_of(1.0, -dot(d, *horizon) * inv_d + sin_b);
    return w * max_of(cosines, 1e-9);
}

WeighedTriangle triangle(const Vec3& a, const Vec3& b, const Vec3& c, double luminance) {
    WeighedTriangle t;
    t.a = a, t.b = b, t.c = c, t.d = a;
    t.normal = normalize_or_zero(cross(b - a, c - a));
    t.area = 0.5 * length(cross(b - a, c - a));
    t.centre = (a + b + c) / 3.0;
    t.reach = std::fmax(length(a - t.centre), std::fmax(length(b - t.centre), length(c - t.centre)));
    t.power = t.area * luminance;
    return t;
}

TEST(TriangleWeights, EqualTheScalarRuleBitForBit) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> U(-1, 1);
    const auto point = [&](double scale) { return Vec3{U(rng), U(rng), U(rng)} * scale; };
    for (size_t count : {1, 2, 3, 7, 64}) {
        std::vector<WeighedTriangle> triangles;
        for (size_t i = 0; i < count; ++i) {
            const Vec3 at = point(3);
            const double size = std::exp(3 * U(rng));  // 0.05 to 20: points within their reach too
            triangles.push_back(triangle(at, at + point(size), at + point(size), std::exp(5 * U(rng))));
        }
        const TriangleWeights weights(triangles);
        ASSERT_EQ(weights.size(), count);
        std::vector<Vec3> points;
        for (int k = 0; k < 200; ++k) points.push_back(point(4));
        for (const WeighedTriangle& t : triangles) points.insert(points.end(), {t.a, t.centre, t.centre + t.normal * 1e-9});
        std::vector<double> w(count + 1, -1.0);
        size_t zero = 0, near = 0, far = 0;
        for (const Vec3& x : points) {
            for (bool with_horizon : {false, true}) {
                const Vec3 up = normalize_or_zero(point(1));
                const Vec3* horizon = with_horizon ? &up : nullptr;
                weights.weigh(x, horizon, w.data());
                for (size_t i = 0; i < count; ++i) {
                    const double expected = scalar_weight(triangles[i], x, horizon);
                    ASSERT_EQ(w[i], expected) << "triangle " << i << " of " << count;
                    ASSERT_TRUE(std::isfinite(w[i]));
                    const Vec3 d = x - triangles[i].centre;
                    zero += w[i] == 0, near += w[i] > 0 && !(dot(d, d) > triangles[i].reach * triangles[i].reach), far += w[i] > 0 && dot(d, d) > triangles[i].reach * triangles[i].reach;
                }
                EXPECT_EQ(w[count], -1.0) << "past the last triangle";
            }
        }
        // Every branch of the rule was taken.
        EXPECT_GT(zero, 0u);
        EXPECT_GT(near, 0u);
        EXPECT_GT(far, 0u);
    }
}

TEST(TriangleWeights, NothingBehindOrBelowTheHorizon) {
    // A unit triangle in the plane y = 1 facing down, and one facing up.
    const WeighedTriangle down = triangle({0, 1, 0}, {1, 1, 0}, {0, 1, 1}, 1);
    const WeighedTriangle up = triangle({0, 1, 0}, {0, 1, 1}, {1, 1, 0}, 1);
    ASSERT_LT(down.normal.y, 0);
    const TriangleWeights weights({down, up});
    double w[2];
    weights.weigh({0.2, 0, 0.2}, nullptr, w);
    EXPECT_GT(w[0], 0);
    EXPECT_EQ(w[1], 0);  // below the upward one: behind it
    const Vec3 floor{0, 1, 0}, ceiling{0, -1, 0};
    weights.weigh({0.2, 0, 0.2}, &floor, w);
    EXPECT_GT(w[0], 0);
    weights.weigh({0.2, 0, 0.2}, &ceiling, w);  // a surface under the lamp facing away from it
    EXPECT_EQ(w[0], 0);
}

TEST(TriangleWeights, AParallelogramIsAboveTheHorizonByItsFourthCorner) {
    // A parallelogram lamp facing down, x beside it with a horizon tipped so that only the
    // fourth corner (b + c - a) is above the surface's plane: it can light x.
    WeighedTriangle p = triangle({0, 1, 0}, {1, 1, 0}, {0, 1, 1}, 1);
    p.d = {1, 1, 1};
    p.area *= 2;
    p.centre = {0.5, 1, 0.5};
    const Vec3 x{0, 0, 0}, horizon = normalize_or_zero(Vec3{1, -1.5, 1});
    ASSERT_LE(dot(p.a - x, horizon), 0);
    ASSERT_LE(dot(p.b - x, horizon), 0);
    ASSERT_LE(dot(p.c - x, horizon), 0);
    ASSERT_GT(dot(p.d - x, horizon), 0);
    const TriangleWeights weights({p});
    double w[1];
    weights.weigh(x, &horizon, w);
    EXPECT_GT(w[0], 0);
    EXPECT_EQ(w[0], scalar_weight(p, x, &horizon));
}

}  // namespace
}  // namespace crex
