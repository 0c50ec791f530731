// RADIANCE's noise functions (issue 39): the values RADIANCE's own noise3.c computes at
// chosen points (reference values from RADIANCE 5.4a's code, compiled outside this
// repository), so a pattern written for RADIANCE looks the same in crex; and the function
// language calls them by their RADIANCE names.
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/scene/radiance/calc.h"
#include "runtime/scene/radiance/noise.h"

namespace crex::radiance {
namespace {

struct Reference {
    double x, y, z, noise, dx, dy, dz, fractal;
};

// noise3, noise3x, noise3y, noise3z, fnoise3 at each point, as RADIANCE computes them.
constexpr Reference kReferences[] = {
    {0.1, 0.2, 0.3, 0.351229248781, 0.283692327547, -0.827412843741, 0.854856756404, -0.38033074593},
    {1.5, -2.25, 3.75, 0.0182971954346, 0.0276711213893, -0.147406565367, -0.227924455796, 0.19316203231},
    {-0.7, 0.45, -1.3, 0.108096094471, -0.421599175254, -0.310487988996, -0.512749355, 0.168121945185},
    {10.1, 20.2, -30.3, 0.268966157452, 0.425019199912, 0.0055283752598, -0.122630198924, 0.337429892758},
    {0.5, 0.5, 0.5, -0.25, -0.687968124688, 0.249531250312, 0, -0.341255115502},
    {-3, 2, 1.0001, 9.99750020999e-12, -1.00000249536, 0.999997501864, -1.25872457425e-06, 0.563896189214},
};

TEST(RadianceNoise, MatchesRadiancesOwnValues) {
    for (const Reference& r : kReferences) {
        EXPECT_NEAR(noise3(r.x, r.y, r.z), r.noise, 1e-9) << r.x << " " << r.y << " " << r.z;
        EXPECT_NEAR(noise3_partial(r.x, r.y, r.z, 0), r.dx, 1e-6) << r.x;
        EXPECT_NEAR(noise3_partial(r.x, r.y, r.z, 1), r.dy, 1e-6) << r.x;
        EXPECT_NEAR(noise3_partial(r.x, r.y, r.z, 2), r.dz, 1e-6) << r.x;
        EXPECT_NEAR(fnoise3(r.x, r.y, r.z), r.fractal, 1e-9) << r.x;
    }
}

TEST(RadianceNoise, ZeroOnTheLatticeAndFiniteEverywhere) {
    for (int i = -3; i <= 3; ++i) EXPECT_EQ(noise3(i, 2 * i, -i), 0.0);
    for (double big : {1e300, -1e300, HUGE_VAL, std::nan("")}) {
        EXPECT_TRUE(std::isfinite(noise3(big, 0, 0)));
        EXPECT_TRUE(std::isfinite(fnoise3(0, big, 0)));
        EXPECT_TRUE(std::isfinite(noise3_partial(0, 0, big, 2)));
    }
}

TEST(RadianceNoise, TheFunctionLanguageCallsThem) {
    calc::Program program;
    calc::Error e;
    ASSERT_TRUE(program.define("n = 1 - .35*(1+fnoise3(3*A1,3*A2,3*A3)); g = noise3x(A1,A2,A3) + noise3a(A1,A2,A3);", e)) << e.message;
    calc::Environment env;
    env.args = {0.1 / 3, 0.2 / 3, 0.3 / 3};
    env.variable = [](const std::string&) -> std::optional<double> { return std::nullopt; };
    auto n = program.parse("n", e), g = program.parse("g", e);
    ASSERT_TRUE(n && g);
    EXPECT_NEAR(*program.evaluate(*n, env, e), 1 - .35 * (1 + fnoise3(0.1, 0.2, 0.3)), 1e-12);
    EXPECT_NEAR(*program.evaluate(*g, env, e), 2 * noise3_partial(env.args[0], env.args[1], env.args[2], 0), 1e-12);
}

}  // namespace
}  // namespace crex::radiance
