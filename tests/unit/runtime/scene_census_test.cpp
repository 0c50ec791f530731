// The component split of each material (spec/crex.md §1) and the census of whole scenes.
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/scene/census.h"
#include "runtime/scene/shapes.h"
#include "tests/support/scene_helpers.h"

namespace crex {
namespace {

std::string split(MaterialType type, double spec = 0, double rough = 0, Vec3 color = {0.5, 0.5, 0.5},
                  double trans = 0, double tspec = 0) {
    Material m;
    m.type = type;
    m.specularity = spec;
    m.roughness = rough;
    m.color = color;
    m.transmissivity = trans;
    m.transmitted_specular = tspec;
    return component_set_letters(spawned_components(m));
}

TEST(MaterialSplit, FollowsTheComponentTable) {
    EXPECT_EQ(split(MaterialType::kPlastic), "D");
    EXPECT_EQ(split(MaterialType::kPlastic, 0.1, 0.2), "D G");
    EXPECT_EQ(split(MaterialType::kPlastic, 0.1, 0.0), "D S");
    EXPECT_EQ(split(MaterialType::kMetal, 1.0, 0.0), "S");  // all specular: no diffuse lobe
    EXPECT_EQ(split(MaterialType::kTrans, 0.05, 0.1, {0.5, 0.5, 0.5}, 0.5, 0.0), "D G");
    EXPECT_EQ(split(MaterialType::kTrans, 0.05, 0.0, {0.5, 0.5, 0.5}, 0.5, 0.5), "D S T");
    EXPECT_EQ(split(MaterialType::kTrans, 0.0, 0.0, {0.5, 0.5, 0.5}, 0.5, 1.0), "D T");
    EXPECT_EQ(split(MaterialType::kGlass), "T R");
    EXPECT_EQ(split(MaterialType::kDielectric), "T R");
    EXPECT_EQ(split(MaterialType::kGlass, 0, 0, {0, 0, 0}), "R");  // black glass still reflects
    EXPECT_EQ(split(MaterialType::kMirror), "M");
    EXPECT_EQ(split(MaterialType::kMirror, 0, 0, {0, 0, 0}), "");
    EXPECT_EQ(split(MaterialType::kPlastic, 0, 0, {0, 0, 0}), "");
    EXPECT_EQ(split(MaterialType::kLight), "");
    EXPECT_EQ(split(MaterialType::kGlow), "");
    EXPECT_EQ(split(MaterialType::kVoid), "");
}

TEST(Census, CornellBoxes) {
    Census full = take_census(*builtin_scene("cornell"));
    EXPECT_EQ(component_set_letters(full.spawnable), "D T R M");
    EXPECT_EQ(full.sampled_emitters, 1u);
    Census diffuse = take_census(*builtin_scene("cornell_diffuse"));
    EXPECT_EQ(component_set_letters(diffuse.spawnable), "D");
    for (Component c : {Component::kG, Component::kS, Component::kT, Component::kR, Component::kM}) {
        EXPECT_FALSE(diffuse.can_occur(c));
        EXPECT_FALSE(diffuse.can_spawn(std::nullopt, c));
        EXPECT_FALSE(diffuse.can_spawn(Component::kD, c));
    }
    EXPECT_TRUE(diffuse.can_spawn(std::nullopt, Component::kD));
    EXPECT_TRUE(diffuse.can_spawn(Component::kD, Component::kD));
    EXPECT_NE(full.hash, diffuse.hash);
}

TEST(Census, CountsOnlyMaterialsInUse) {
    Scene s = *builtin_scene("cornell_diffuse");
    Material unused;
    unused.name = "unused_glass";
    unused.type = MaterialType::kGlass;
    s.materials.push_back(unused);
    EXPECT_EQ(component_set_letters(take_census(s).spawnable), "D");
    EXPECT_EQ(take_census(s).hash, take_census(*builtin_scene("cornell_diffuse")).hash);
}

TEST(Census, CorridorHasEverythingButMirrorsAndItsTags) {
    auto r = testing::load_path(CREX_SOURCE_DIR "/examples/scenes/corridor/scene.json");
    ASSERT_TRUE(r.scene);
    Census c = take_census(*r.scene);
    EXPECT_EQ(component_set_letters(c.spawnable), "D G S T R");
    EXPECT_EQ(c.tags, (std::vector<std::string>{"exit_sign", "fire_alarm", "fire_extinguisher", "poster"}));
    EXPECT_EQ(c.sampled_emitters, 3u);
    EXPECT_EQ(c.unsampled_emitters, 1u);
}

TEST(Census, HashIsStable) {
    // The hash is stored in plans: it must not change between runs or builds.
    EXPECT_EQ(census_hash_hex(take_census(*builtin_scene("cornell")).hash), "d5579704575b1302");
}

double polygon_area(const std::vector<Vec3>& v, const std::vector<std::array<uint32_t, 3>>& tris) {
    double a = 0;
    for (const auto& t : tris) a += 0.5 * length(cross(v[t[1]] - v[t[0]], v[t[2]] - v[t[0]]));
    return a;
}

TEST(Tessellation, EarClippingHandlesNonConvexPolygons) {
    // An L shape (area 3) in the plane z = 1, both windings.
    std::vector<Vec3> l = {{0, 0, 1}, {2, 0, 1}, {2, 1, 1}, {1, 1, 1}, {1, 2, 1}, {0, 2, 1}};
    auto tris = triangulate_polygon(l);
    EXPECT_EQ(tris.size(), 4u);
    EXPECT_NEAR(polygon_area(l, tris), 3.0, 1e-12);
    std::vector<Vec3> r(l.rbegin(), l.rend());
    EXPECT_NEAR(polygon_area(r, triangulate_polygon(r)), 3.0, 1e-12);
}

TEST(Tessellation, BoxIsClosedAndOutwardFacing) {
    Shape box;
    box.type = ShapeType::kBox;
    box.min = {0, 0, 0};
    box.max = {1, 2, 3};
    TriangleMesh m;
    tessellate(box, m);
    ASSERT_EQ(m.indices.size(), 12u);
    Vec3 centre{0.5, 1, 1.5};
    double area = 0;
    for (const auto& t : m.indices) {
        Vec3 n = cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
        EXPECT_GT(dot(n, m.positions[t[0]] - centre), 0);  // normal points away from the centre
        area += 0.5 * length(n);
    }
    EXPECT_NEAR(area, 2 * (1 * 2 + 2 * 3 + 1 * 3), 1e-12);
}

TEST(Tessellation, RoundShapesApproximateTheirArea) {
    Shape cyl;
    cyl.type = ShapeType::kCylinder;
    cyl.p0 = {0, 0, 0};
    cyl.p1 = {0, 0, 2};
    cyl.radius = 1;
    TriangleMesh m;
    tessellate(cyl, m);
    double area = 0;
    for (const auto& t : m.indices)
        area += 0.5 * length(cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]));
    double exact = 2 * M_PI * 1 * 2;
    EXPECT_NEAR(area / exact, 1.0, 0.01);  // 48 segments: within 1 % of the true surface
}

}  // namespace
}  // namespace crex
