// The RADIANCE importer: each supported primitive and material, the view, the twin of the
// Cornell box, and every kind of bad input as a located error.
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/scene/census.h"
#include "runtime/scene/shapes.h"
#include "tests/support/scene_helpers.h"

namespace crex {
namespace {

const char* kAllMaterials = R"(
void plastic p 0 0 5 .5 .4 .3 .05 .1
void metal m 0 0 5 .9 .8 .7 .9 0
void trans t 0 0 7 .6 .6 .6 .03 .05 .5 .4
void glass g3 0 0 3 .96 .96 .96
void glass g4 0 0 4 .96 .96 .96 1.45
void dielectric d 0 0 5 .9 .9 1 1.33 0
void mirror mi 0 0 3 .95 .95 .95
void light l 0 0 3 10 10 10
void glow gl 0 0 4 1 2 3 4
)";

TEST(SceneRadiance, EveryMaterialReadsItsArguments) {
    auto r = testing::load_rad_text(std::string(kAllMaterials) + "l sphere s 0 0 4 0 0 0 1\n");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Scene& s = *r.scene;
    ASSERT_EQ(s.materials.size(), 9u);
    EXPECT_EQ(s.materials[0].type, MaterialType::kPlastic);
    EXPECT_DOUBLE_EQ(s.materials[0].specularity, 0.05);
    EXPECT_DOUBLE_EQ(s.materials[0].roughness, 0.1);
    EXPECT_EQ(s.materials[1].type, MaterialType::kMetal);
    EXPECT_DOUBLE_EQ(s.materials[2].transmissivity, 0.5);
    EXPECT_DOUBLE_EQ(s.materials[2].transmitted_specular, 0.4);
    EXPECT_DOUBLE_EQ(s.materials[3].ior, 1.52);  // RADIANCE's default
    EXPECT_DOUBLE_EQ(s.materials[4].ior, 1.45);
    EXPECT_DOUBLE_EQ(s.materials[5].ior, 1.33);
    EXPECT_EQ(s.materials[6].type, MaterialType::kMirror);
    EXPECT_EQ(s.materials[7].color, (Vec3{10, 10, 10}));
    EXPECT_DOUBLE_EQ(s.materials[8].glow_radius, 4);
}

TEST(SceneRadiance, AMistOnAGenboxIsTheMediumInThatBox) {
    // RADIANCE's mist test set: a genbox moved by xform bounds the medium (extinction, albedo,
    // eccentricity); its surfaces are not seen. A mist with no coefficients only names sources
    // (W306: crex scatters every source's light) and adds nothing.
    auto r = testing::load_rad_text("void light l 0 0 3 1 1 1\nl sphere s 0 0 4 -1 1 1 .1\n"
                                    "void mist fog 0 0 7 .1 .2 .4 .9 .8 .7 .3\n!genbox fog box 2 3 4 | xform -t -3 -1 .5\n"
                                    "void mist beam 1 s 0 0\nbeam sphere cone 0 0 4 0 0 0 1\n");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    ASSERT_TRUE(r.scene->medium);
    const Medium& m = *r.scene->medium;
    EXPECT_EQ(m.extinction, (Vec3{.1, .2, .4}));
    EXPECT_EQ(m.albedo, (Vec3{.9, .8, .7}));
    EXPECT_DOUBLE_EQ(m.eccentricity, 0.3);
    EXPECT_TRUE(m.bounded);
    EXPECT_EQ(m.box_min, (Vec3{-3, -1, .5}));
    EXPECT_EQ(m.box_max, (Vec3{-1, 2, 4.5}));
    EXPECT_EQ(r.scene->shapes.size(), 1u);  // the lamp; neither mist's surfaces
    bool named = false;
    for (const Diagnostic& d : r.diagnostics) named = named || (d.code == "W306" && d.message.find("mist 'beam'") != std::string::npos);
    EXPECT_TRUE(named);
}

TEST(SceneRadiance, TheFuncMaterialsAndAshik2ReadTheirArguments) {
    // metfunc: its specular part coloured by the material (rspec c), the diffuse part
    // c (1 - rspec); transfunc: trans = .8 (1 - .1), tspec = trans .5, tdiff = c (trans - tspec),
    // rdiff = c (1 - trans - rspec). ashik2 as Ward: roughness sqrt(2 / n), diffuse kept.
    auto r = testing::load_rad_text("void metfunc m 2 grey . 0 7 .5 .4 .2 .1 0 0 1\nvoid transfunc t 2 grey . 0 9 .5 .5 .5 .1 .8 .5 0 0 1\n"
                                    "void ashik2 a 4 1 0 0 . 0 8 .3 .1 .05 .5 .5 .5 8 50\n"
                                    "m sphere s1 0 0 4 0 0 0 1\nt sphere s2 0 0 4 3 0 0 1\na sphere s3 0 0 4 6 0 0 1\n");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Material* m = r.scene->find_material("m");
    const Material* t = r.scene->find_material("t");
    const Material* a = r.scene->find_material("a");
    ASSERT_TRUE(m && t && a && m->directional && t->directional);
    EXPECT_LT(length(m->directional->reflect - Vec3{.05, .04, .02}), 1e-12);
    EXPECT_LT(length(m->directional->diffuse_reflect - Vec3{.45, .36, .18}), 1e-12);
    EXPECT_EQ(m->type, MaterialType::kPlastic);
    EXPECT_EQ(t->type, MaterialType::kTrans);
    EXPECT_NEAR(t->transmissivity, .72, 1e-12);
    EXPECT_NEAR(t->directional->transmit.x, .5 * .36, 1e-12);
    EXPECT_NEAR(t->directional->diffuse_transmit.x, .5 * (.72 - .36), 1e-12);
    EXPECT_NEAR(t->directional->diffuse_reflect.x, .5 * (1 - .72 - .1), 1e-12);
    ASSERT_TRUE(a->anisotropy);
    EXPECT_NEAR(a->roughness, std::sqrt(2.0 / 8), 1e-12);
    EXPECT_NEAR(a->anisotropy->roughness_v, std::sqrt(2.0 / 50), 1e-12);
    EXPECT_NEAR(a->specularity, 0.5, 1e-6);  // a grey specular colour's brightness
    EXPECT_NEAR(a->color.x * (1 - a->specularity), 0.3, 1e-6);  // the diffuse part kept
    bool warned = false;
    for (const auto& d : r.diagnostics) warned = warned || (d.code == "W306" && d.message.find("ashik2 'a'") != std::string::npos);
    EXPECT_TRUE(warned);
}

TEST(SceneRadiance, EveryPrimitiveReadsItsArguments) {
    auto r = testing::load_rad_text(R"(
void plastic w 0 0 5 .5 .5 .5 0 0
void light l 0 0 3 1 1 1
w polygon quad 0 0 12  0 0 0  1 0 0  1 1 0  0 1 0
w sphere ball 0 0 4  1 2 3 0.5
w ring disc 0 0 8  0 0 0  0 0 1  0.25 1
l cone c 0 0 8  0 0 0  0 0 2  1 0.5
w cylinder cyl 0 0 7  0 0 0  0 3 0  0.2
)");
    ASSERT_TRUE(r.scene);
    const auto& sh = r.scene->shapes;
    ASSERT_EQ(sh.size(), 5u);
    EXPECT_EQ(sh[0].type, ShapeType::kPolygon);
    EXPECT_EQ(sh[0].vertices.size(), 4u);
    EXPECT_EQ(sh[1].center, (Vec3{1, 2, 3}));
    EXPECT_DOUBLE_EQ(sh[1].radius, 0.5);
    EXPECT_EQ(sh[2].normal, (Vec3{0, 0, 1}));
    EXPECT_DOUBLE_EQ(sh[2].r0, 0.25);
    EXPECT_DOUBLE_EQ(sh[3].r1, 0.5);
    EXPECT_EQ(sh[3].material, "l");
    EXPECT_EQ(sh[4].p1, (Vec3{0, 3, 0}));
    EXPECT_EQ(sh[4].name, "cyl");
    // Tessellation: a quad is 2 triangles, a ring 2 per segment, a cone 2 per segment
    // (1 when an end radius is 0), a cylinder 2 per segment.
    EXPECT_EQ(triangle_count(sh[0]), 2u);
    EXPECT_EQ(triangle_count(sh[1]), 0u);
    EXPECT_EQ(triangle_count(sh[2]), 2u * kRoundSegments);
    EXPECT_EQ(triangle_count(sh[3]), 2u * kRoundSegments);
    EXPECT_EQ(triangle_count(sh[4]), 2u * kRoundSegments);
}

TEST(SceneRadiance, TagsAttachToTheNextSurface) {
    auto r = testing::load_rad_text(R"(
void light l 0 0 3 1 1 1
l sphere first 0 0 4 0 0 0 1
#@crex tag name=exit_sign task=3 distractor=true
l sphere second 0 0 4 3 0 0 1
l sphere third 0 0 4 6 0 0 1
)");
    ASSERT_TRUE(r.scene);
    EXPECT_FALSE(r.scene->shapes[0].tag);
    ASSERT_TRUE(r.scene->shapes[1].tag);
    EXPECT_EQ(r.scene->shapes[1].tag->name, "exit_sign");
    EXPECT_EQ(r.scene->shapes[1].tag->task, 3);
    EXPECT_TRUE(r.scene->shapes[1].tag->distractor);
    EXPECT_FALSE(r.scene->shapes[2].tag);
}

TEST(SceneRadiance, ViewOptionsSetTheCamera) {
    auto r = testing::load_rad_text("void light l 0 0 3 1 1 1\nl sphere s 0 0 4 0 0 0 1\n",
                                    "rview -vtv -vp 1 2 3 -vd 0 0 -1 -vu 0 1 0 -vh 50 -vv 30\n");
    ASSERT_TRUE(r.scene);
    const Camera& c = r.scene->camera;
    EXPECT_EQ(c.position, (Vec3{1, 2, 3}));
    EXPECT_EQ(c.direction, (Vec3{0, 0, -1}));
    EXPECT_DOUBLE_EQ(c.hfov_deg, 50);
    EXPECT_DOUBLE_EQ(c.vfov_deg, 30);
    auto inline_view = testing::load_rad_text("#@crex view -vp 1 2 3 -vd 0 1 0\nvoid light l 0 0 3 1 1 1\nl sphere s 0 0 4 0 0 0 1\n");
    ASSERT_TRUE(inline_view.scene);
    EXPECT_EQ(inline_view.scene->camera.up, (Vec3{0, 0, 1}));  // RADIANCE's default up
    EXPECT_DOUBLE_EQ(inline_view.scene->camera.vfov_deg, 45);
}

TEST(SceneRadiance, CornellTwinIsTheJsonSceneWithRadiancesSolidGlass) {
    auto rad = testing::load_path(CREX_SOURCE_DIR "/examples/scenes/cornell/scene.rad");
    auto json = testing::load_path(CREX_SOURCE_DIR "/examples/scenes/cornell/scene.json");
    ASSERT_TRUE(rad.scene);
    ASSERT_TRUE(json.scene);
    EXPECT_EQ(take_census(*rad.scene).hash, take_census(*json.scene).hash);
    // The one difference, said in scene.rad: RADIANCE's glass is a thin pane, so the twin's
    // solid ball is a clear dielectric where the JSON has crex's refracting glass.
    nlohmann::json rad_census = to_json(take_census(*rad.scene));
    size_t balls = 0;
    for (auto& m : rad_census["materials"])
        if (m["name"] == "glass") {
            EXPECT_EQ(m["type"], "dielectric");
            m["type"] = "glass";
            ++balls;
        }
    EXPECT_EQ(balls, 1u);
    EXPECT_EQ(rad_census, to_json(take_census(*json.scene)));
    auto counts = [](const Scene& s) {
        std::map<ShapeType, size_t> by_type;
        size_t triangles = 0;
        for (const auto& sh : s.shapes) ++by_type[sh.type], triangles += triangle_count(sh);
        return std::make_pair(by_type, triangles);
    };
    EXPECT_EQ(counts(*rad.scene), counts(*json.scene));
    const Camera &a = rad.scene->camera, &b = json.scene->camera;
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(a.position[i], b.position[i], 1e-6);
        EXPECT_NEAR(a.direction[i], b.direction[i], 1e-6);
        EXPECT_NEAR(a.up[i], b.up[i], 1e-6);
    }
    EXPECT_NEAR(a.vfov_deg, b.vfov_deg, 1e-6);
    EXPECT_NEAR(a.hfov_deg, b.hfov_deg, 1e-6);
}

TEST(SceneRadiance, KeepsGoingAfterAnUnsupportedPrimitive) {
    auto r = testing::load_rad_text("void light l 0 0 3 1 1 1\nl instance a 1 a.oct 0 0\nl mesh b 1 b.rtm 0 0\nl sphere s 0 0 4 0 0 0 0\n");
    size_t e307 = 0, e308 = 0, e306 = 0;
    for (const auto& d : r.diagnostics) e307 += d.code == "E307", e308 += d.code == "E308", e306 += d.code == "E306";
    EXPECT_EQ(e307, 0u);
    EXPECT_EQ(e308, 2u);  // the octree and the mesh file that are not there
    EXPECT_EQ(e306, 0u);  // geometry is validated only once the file reads cleanly
    EXPECT_FALSE(r.scene);
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(SceneRadianceDegeneracy, ADegenerateEmitterPolygonIsDroppedNotFatal) {
    // One degenerate polygon among the emitters rejected the whole scene (E306); RADIANCE warns.
    auto r = testing::load_rad_text("void light l 0 0 3 1 1 1\nl polygon p 0 0 9 0 0 0 1 1 1 2 2 2\n"
                                    "l polygon q 0 0 9 0 0 0 1 0 0 0 0 1\n");
    EXPECT_TRUE(r.scene);
    testing::expect_diagnostic(r, "degenerate_emitter", "W304", 2, 3, "zero area");
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

// W308's test for a polygon its triangles cover only in part: a wall a few millimetres out of
// its plane (the published Cornell box's red wall: x from 549.6 to 556 mm over a 559 x 549 mm
// wall) is covered whole; a bow tie crossing itself is not.
TEST(PolygonCover, AWallSlightlyOutOfItsPlaneIsCoveredWholeABowTieIsNot) {
    Shape wall;
    wall.type = ShapeType::kPolygon;
    wall.vertices = {{552.8, 0, 0}, {549.6, 0, 559.2}, {556, 548.8, 559.2}, {556, 548.8, 0}};
    EXPECT_TRUE(polygon_fully_triangulated(wall));
    Shape bow = wall;
    bow.vertices = {{0, 0, 0}, {2, 2, 0}, {2, 0, 0}, {0, 1, 0}};
    EXPECT_FALSE(polygon_fully_triangulated(bow));
}

}  // namespace
}  // namespace crex
