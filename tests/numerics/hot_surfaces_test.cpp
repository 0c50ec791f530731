// Hot surfaces (runtime/render/hot_surfaces.h): the inside of a lamp's shade, lit from a few
// centimetres, is found, its interreflection comes out as a closed box's energy balance says,
// and sampling it as a light leaves path tracing's mean where it was, with far less noise.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "runtime/render/hot_surfaces.h"
#include "runtime/scene/load_scene.h"
#include "tests/support/scene_helpers.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

// The names of the shapes that have hot surfaces in `s`.
std::set<std::string> hot_shape_names(const Scene& s) {
    RenderScene rs(s);
    const HotSurfaces& hot = *rs.hot;
    std::set<std::string> names;
    for (uint32_t g = 0; g < rs.embree->geometries().size(); ++g)
        for (uint32_t p = 0; p < rs.embree->geometries()[g].indices.size(); ++p)
            if (hot.contains(g, p)) names.insert(s.shapes[rs.embree->geometries()[g].shape].name);
    return names;
}

// The example: its floor lamp's shade and the top of its pole; not the desk under the desk
// lamp, whose bulb lights the room itself.
TEST(HotSurfaces, TheExamplesFloorLampShadeIsFound) {
    const std::set<std::string> names = hot_shape_names(*testing::load_path(CREX_SOURCE_DIR "/examples/scenes/floor_lamp/scene.json").scene);
    EXPECT_TRUE(names.count("floor_lamp_shade"));
    for (const std::string& name : names) EXPECT_TRUE(name.rfind("floor_lamp", 0) == 0) << name;
}

// A bulb in a closed box of walls of reflectance rho, each face cut into n x n squares: all
// of the box is hot, and every watt the bulb gives reaches its walls again rho f / (1 - rho f)
// times over after the first, where f is the share of what they reflect that meets them
// again. Returns the interreflected irradiance summed over the walls' area over that, which
// is 1 when it is right.
double interreflected_over_reflected(double kRho) {
    constexpr double kHalf = 0.1, kBulbRadius = 0.02, kRadiance = 1000;
    constexpr int kCells = 6;
    Scene s = testing::lamp_in_a_shade();
    s.shapes.resize(s.shapes.size() - 2);  // the floor stays: the scene's extent puts the box within reach
    s.materials.push_back(testing::make_material("walls", MaterialType::kPlastic, {kRho, kRho, kRho}));
    s.materials.push_back(testing::make_material("box_bulb", MaterialType::kLight, {kRadiance, kRadiance, kRadiance}));
    const Vec3 centre{0, 1.5, 0};
    s.shapes.push_back(build::sphere("box_bulb", centre, kBulbRadius));
    Shape box;
    box.type = ShapeType::kMesh, box.material = "walls", box.name = "box";
    for (int axis = 0; axis < 3; ++axis)
        for (int side = -1; side <= 1; side += 2)
            for (int i = 0; i < kCells; ++i)
                for (int j = 0; j < kCells; ++j) {
                    auto corner = [&](int a, int b) {
                        double c[3];
                        c[axis] = side * kHalf;
                        c[(axis + 1) % 3] = -kHalf + 2 * kHalf * (i + a) / kCells;
                        c[(axis + 2) % 3] = -kHalf + 2 * kHalf * (j + b) / kCells;
                        return centre + Vec3{c[0], c[1], c[2]};
                    };
                    const auto v = static_cast<uint32_t>(box.vertices.size());
                    box.vertices.insert(box.vertices.end(), {corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)});
                    box.triangles.push_back({v, v + 1, v + 2});
                    box.triangles.push_back({v, v + 2, v + 3});
                }
    s.shapes.push_back(box);
    RenderScene rs(s);
    const HotSurfaces& hot = *rs.hot;
    EXPECT_EQ(hot.size(), 6u * kCells * kCells * 2);
    double flux = 0;
    for (uint32_t g = 0; g < rs.embree->geometries().size(); ++g) {
        const GeometryInfo& geometry = rs.embree->geometries()[g];
        for (uint32_t p = 0; p < geometry.indices.size(); ++p) {
            const int i = hot.index_of(g, p);
            if (i < 0) continue;
            const auto& t = geometry.indices[p];
            const double area = 0.5 * length(cross(geometry.positions[t[1]] - geometry.positions[t[0]], geometry.positions[t[2]] - geometry.positions[t[0]]));
            // The mean over the triangle: at the centres of its 64 triangles of an 8 x 8 grid.
            double sum = 0;
            for (int a = 0; a < 8; ++a)
                for (int b = 0; a + b < 8; ++b) {
                    sum += luminance(hot.interreflected(static_cast<uint32_t>(i), (a + 1.0 / 3) / 8, (b + 1.0 / 3) / 8));
                    if (a + b < 7) sum += luminance(hot.interreflected(static_cast<uint32_t>(i), (a + 2.0 / 3) / 8, (b + 2.0 / 3) / 8));
                }
            flux += area * sum / 64;
        }
    }
    // Of the light the walls reflect, the bulb (which reflects nothing) takes its surface's
    // share of all the surface in the box, the walls' the rest: f.
    const double bulb_area = 4 * kPi * kBulbRadius * kBulbRadius, f = 1 - bulb_area / (24 * kHalf * kHalf);
    const double bulb = kRadiance * kPi * bulb_area;
    return flux / (bulb * kRho * f / (1 - kRho * f));
}

TEST(HotSurfaces, AClosedBoxGivesBackWhatItsWallsReflect) {
    // With walls of 0.9 the answer is ten times as sensitive to the sampled weights as with
    // 0.5 (measured: within 0.6 % at each).
    for (double rho : {0.1, 0.5, 0.7, 0.9}) EXPECT_NEAR(interreflected_over_reflected(rho), 1.0, 0.02) << rho;
}

// Path tracing the floor under the lamp, glossy (its G rays meet the shade's inside as its D
// rays do), 16x16 from 0.6 above it: the shade sampled as a light against the shade met by
// chance. `hot`: sampled as a light.
std::vector<float> floor_under_the_lamp(bool hot, uint32_t spp, uint64_t seed) {
    Scene s = testing::lamp_in_a_shade();
    s.materials[0].specularity = 0.05, s.materials[0].roughness = 0.1;
    RunSettings o;
    o.width = o.height = 16;
    o.spp = spp;
    o.seed = seed;
    o.executor.shade.hot_surface_lights = hot;
    return render(s, testing::lower_or_die("(TTMRSGD)*"), o).image();
}

// The same mean as the rays that meet the shade by chance bring (their own mean converged at
// 4,096 samples a pixel), at a fraction of their error for the same samples.
TEST(HotSurfaces, PathTracingSamplesTheShadeAsALightWithTheSameMean) {
    const std::vector<float> reference = floor_under_the_lamp(false, 4096, 9);
    const std::vector<float> by_chance = floor_under_the_lamp(false, 64, 1), as_light = floor_under_the_lamp(true, 64, 1);
    const double mean = testing::mean_luminance(reference);
    ::testing::Test::RecordProperty("mean_as_light_over_reference", std::to_string(testing::mean_luminance(as_light) / mean));
    ::testing::Test::RecordProperty("mse_by_chance", std::to_string(testing::mean_squared_difference(by_chance, reference)));
    ::testing::Test::RecordProperty("mse_as_light", std::to_string(testing::mean_squared_difference(as_light, reference)));
    EXPECT_NEAR(testing::mean_luminance(as_light) / mean, 1.0, 0.02);
    EXPECT_NEAR(testing::mean_luminance(floor_under_the_lamp(true, 1024, 2)) / mean, 1.0, 0.01);
    EXPECT_LT(testing::mean_squared_difference(as_light, reference), testing::mean_squared_difference(by_chance, reference) / 4);
    EXPECT_TRUE(testing::all_finite(as_light));
}

// A thousand lamps in their shades, in a 40 x 25 grid: too many for 4,096 rays each, every
// shade is still found with fewer.
TEST(HotSurfaces, EveryShadeOfAThousandLampsIsFound) {
    Scene s = testing::lamp_in_a_shade();
    const Shape bulb = s.shapes[s.shapes.size() - 2], shade = s.shapes.back();
    s.shapes.resize(s.shapes.size() - 2);
    for (int i = 0; i < 40; ++i)
        for (int j = 0; j < 25; ++j) {
            const Vec3 at{-1.95 + 0.1 * i, 0, -1.2 + 0.1 * j};
            Shape b = bulb, c = shade;
            b.center = b.center + at, c.p0 = c.p0 + at, c.p1 = c.p1 + at;
            b.radius = 0.005, c.radius = 0.04;
            b.name = "bulb" + std::to_string(i * 25 + j), c.name = "shade" + std::to_string(i * 25 + j);
            s.shapes.push_back(b), s.shapes.push_back(c);
        }
    const std::set<std::string> found = hot_shape_names(s);
    EXPECT_EQ(found.size(), 1000u);
    for (const std::string& name : found) EXPECT_EQ(name.rfind("shade", 0), 0u) << name;
}

}  // namespace
}  // namespace crex
