// RADIANCE scenes as RADIANCE users write them (issue 39): the file grammar (quotes, alias,
// redefinition, continued commands), xform carried out natively (transforms against points
// computed by hand, arrays and their names, -m, -n, -I, nested files read relative to the
// file naming them), the generators genbox, genprism and genrev, and tags on objects.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "runtime/scene/radiance/calc.h"
#include "runtime/scene/radiance/transform.h"
#include "runtime/scene/census.h"
#include "runtime/scene/shapes.h"
#include "tests/support/scene_helpers.h"

namespace crex {
namespace {

const char* kLight = "void light l 0 0 3 1 1 1\n";

void expect_near(const Vec3& a, const Vec3& b, double tol, const std::string& what) {
    EXPECT_NEAR(a.x, b.x, tol) << what;
    EXPECT_NEAR(a.y, b.y, tol) << what;
    EXPECT_NEAR(a.z, b.z, tol) << what;
}

using testing::shape_named;

// A directory of scene files for one test, removed afterwards.
class SceneDir {
public:
    explicit SceneDir(const std::string& name) : dir_(std::filesystem::temp_directory_path() / ("crex_rad_" + name + "_" + std::to_string(::getpid()))) {
        std::filesystem::create_directories(dir_);
    }
    ~SceneDir() {
        std::error_code ec;
        std::filesystem::remove_all(dir_, ec);
    }
    std::string write(const std::string& rel, const std::string& text) const {
        std::filesystem::path p = dir_ / rel;
        std::filesystem::create_directories(p.parent_path());
        std::ofstream(p) << text;
        return p.string();
    }

private:
    std::filesystem::path dir_;
};

TEST(RadianceTransform, MovesPointsAsXformDoes) {
    using radiance::Transform;
    // By hand: (1, 0, 0) rotated 90 degrees about z is (0, 1, 0); scaled by 2, (0, 2, 0);
    // then moved by (1, 2, 3), (1, 4, 3).
    std::vector<std::string> words = {"-rz", "90", "-s", "2", "-t", "1", "2", "3"};
    Transform t;
    size_t consumed = 0, bad = 0;
    std::string error;
    ASSERT_TRUE(radiance::parse_transform(words, 0, t, consumed, error, bad)) << error;
    EXPECT_EQ(consumed, words.size());
    expect_near(t.point({1, 0, 0}), {1, 4, 3}, 1e-12, "point");
    expect_near(t.vector({1, 0, 0}), {0, 2, 0}, 1e-12, "vector");
    EXPECT_DOUBLE_EQ(t.scale(), 2);
    // -rx 90 takes y to z, -ry 90 takes z to x (counter-clockwise looking down each axis).
    std::vector<std::string> rx = {"-rx", "90"}, ry = {"-ry", "90"};
    ASSERT_TRUE(radiance::parse_transform(rx, 0, t, consumed, error, bad));
    expect_near(t.point({0, 1, 0}), {0, 0, 1}, 1e-12, "-rx");
    ASSERT_TRUE(radiance::parse_transform(ry, 0, t, consumed, error, bad));
    expect_near(t.point({0, 0, 1}), {1, 0, 0}, 1e-12, "-ry");
    // -i 3 repeats what follows it (up to the next -i) three times; a mirror flips the scale.
    std::vector<std::string> repeat = {"-t", "1", "0", "0", "-i", "3", "-rz", "90", "-i", "1", "-mx"};
    ASSERT_TRUE(radiance::parse_transform(repeat, 0, t, consumed, error, bad));
    // (0,0,0) -> (1,0,0) -> rz 270: (0,-1,0) -> mirror x: (0,-1,0)
    expect_near(t.point({0, 0, 0}), {0, -1, 0}, 1e-12, "-i");
    EXPECT_TRUE(t.mirrors());
    std::vector<std::string> broken = {"-t", "1", "x", "0"};
    EXPECT_FALSE(radiance::parse_transform(broken, 0, t, consumed, error, bad));
    EXPECT_EQ(bad, 2u);
}

TEST(RadianceGrammar, QuotedWordsAliasRedefinitionAndVoid) {
    auto r = testing::load_rad_text(std::string(kLight) + R"(
void plastic "red paint" 0 0 5 .8 .1 .1 0 0
"red paint" sphere 'a ball' 0 0 4 0 0 0 1
void plastic base 0 0 5 .5 .5 .5 0 0
base sphere before 0 0 4 3 0 0 1
void alias other base
inherit alias same base
# Intentionally redefined: what follows uses the new one, what came before keeps the old.
void plastic base 0 0 5 .2 .3 .4 0 0
base sphere after 0 0 4 6 0 0 1
other sphere via_alias 0 0 4 9 0 0 1
same sphere via_inherit 0 0 4 12 0 0 1
void sphere invisible 0 0 4 15 0 0 1
)");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Scene& s = *r.scene;
    ASSERT_EQ(s.shapes.size(), 5u);  // the void sphere is invisible
    EXPECT_EQ(s.shapes[0].name, "a ball");
    EXPECT_EQ(s.find_material(s.shapes[0].material)->color, (Vec3{.8, .1, .1}));
    EXPECT_EQ(s.find_material(shape_named(s, "before")->material)->color, (Vec3{.5, .5, .5}));
    EXPECT_EQ(s.find_material(shape_named(s, "after")->material)->color, (Vec3{.2, .3, .4}));
    EXPECT_NE(shape_named(s, "before")->material, shape_named(s, "after")->material);
    // The aliases were made before the redefinition: they are the first 'base'.
    EXPECT_EQ(s.find_material(shape_named(s, "via_alias")->material)->color, (Vec3{.5, .5, .5}));
    EXPECT_EQ(s.find_material(shape_named(s, "via_inherit")->material)->color, (Vec3{.5, .5, .5}));
}

TEST(RadianceGrammar, ContinuedCommandsAndInvertedSurfaces) {
    auto r = testing::load_rad_text(std::string(kLight) + "!genbox l box 1 2 3 \\\n   -i\nl bubble b 0 0 4 0 0 0 1\nl cup c 0 0 8 0 0 0 0 0 1 1 .5\n"
                                                          "l tube t 0 0 7 0 0 0 0 0 1 1\nl cone same_radii 0 0 8 0 0 0 0 0 1 2 2\n");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Scene& s = *r.scene;
    ASSERT_EQ(s.shapes.size(), 10u);  // six faces, then the four primitives: the continuation is not a primitive
    EXPECT_TRUE(shape_named(s, "b")->inward);
    EXPECT_TRUE(shape_named(s, "c")->inward);
    EXPECT_TRUE(shape_named(s, "t")->inward);
    EXPECT_EQ(shape_named(s, "same_radii")->type, ShapeType::kCylinder);  // as RADIANCE takes a cone of equal radii
    // genbox -i: every face looks into the box (its normal points to the centre).
    const Vec3 centre{0.5, 1, 1.5};
    for (const auto& sh : s.shapes) {
        if (sh.type != ShapeType::kPolygon) continue;
        Vec3 a = sh.vertices[0], b = sh.vertices[1], c = sh.vertices[2];
        Vec3 n = cross(b - a, c - a), mid = (a + c) * 0.5;
        EXPECT_GT(dot(n, centre - mid), 0) << sh.name;
    }
}

TEST(RadianceGrammar, EveryNewTypeReadsItsArguments) {
    auto r = testing::load_rad_text(R"(
void plastic2 p2 6 1 0 0 . -rz 90 0 6 .5 .4 .3 .05 .1 .2
void metal2 m2 4 0 0 1 . 0 6 .9 .8 .7 .9 .05 .02
void trans2 t2 4 0 1 0 . 0 8 .6 .6 .6 .03 .05 .1 .5 .4
void interface water 0 0 8 .98 .97 .96 1.33 .9 .8 .7 1.5
void spotlight beam 0 0 7 10 20 30 40 0 0 -2
void glow dim 0 0 4 1 1 1 -1
void glass pane 0 0 3 .9 .9 .9
void illum window 1 pane 0 3 5 5 5
void illum hole 0 0 3 5 5 5
void light sun_mat 0 0 3 1e4 1e4 1e4
sun_mat source sun 0 0 4 0 -1 1 .5
p2 sphere a 0 0 4 0 0 0 1
m2 sphere b 0 0 4 3 0 0 1
t2 polygon c 0 0 9 0 0 5 1 0 5 0 1 5
water sphere d 0 0 4 6 0 0 1
beam ring e 0 0 8 0 0 9 0 0 -1 0 .1
dim sphere f 0 0 4 9 0 0 .1
window polygon g 0 0 12 0 0 7 1 0 7 1 1 7 0 1 7
hole polygon h 0 0 12 0 0 8 1 0 8 1 1 8 0 1 8
)");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Scene& s = *r.scene;
    const Material* p2 = s.find_material("p2");
    ASSERT_TRUE(p2 && p2->anisotropy);
    EXPECT_EQ(p2->type, MaterialType::kPlastic);
    EXPECT_DOUBLE_EQ(p2->roughness, 0.1);
    EXPECT_DOUBLE_EQ(p2->anisotropy->roughness_v, 0.2);
    expect_near(p2->anisotropy->orientation, {0, 1, 0}, 1e-12, "orientation turned by its transform (-rz 90)");
    EXPECT_EQ(s.find_material("m2")->type, MaterialType::kMetal);
    const Material* t2 = s.find_material("t2");
    EXPECT_EQ(t2->type, MaterialType::kTrans);
    EXPECT_DOUBLE_EQ(t2->transmissivity, 0.5);
    EXPECT_DOUBLE_EQ(t2->transmitted_specular, 0.4);
    const Material* water = s.find_material("water");
    EXPECT_EQ(water->type, MaterialType::kDielectric);
    EXPECT_DOUBLE_EQ(water->ior, 1.33);
    ASSERT_TRUE(water->outside);
    EXPECT_DOUBLE_EQ(water->outside->ior, 1.5);
    EXPECT_EQ(water->outside->color, (Vec3{.9, .8, .7}));
    const Material* beam = s.find_material("beam");
    EXPECT_EQ(beam->type, MaterialType::kLight);
    ASSERT_TRUE(beam->spot);
    EXPECT_DOUBLE_EQ(beam->spot->angle_deg, 40);
    EXPECT_EQ(beam->spot->direction, (Vec3{0, 0, -2}));
    EXPECT_DOUBLE_EQ(s.find_material("dim")->glow_radius, -1);
    EXPECT_EQ(s.find_material("window")->type, MaterialType::kIllum);
    EXPECT_EQ(s.find_material("window")->alternate, "pane");
    EXPECT_EQ(s.find_material("hole")->alternate, "");
    ASSERT_EQ(s.distant_lights.size(), 1u);
    EXPECT_EQ(s.distant_lights[0].direction, (Vec3{0, -1, 1}));
    EXPECT_DOUBLE_EQ(s.distant_lights[0].angle_deg, 0.5);
    EXPECT_EQ(s.distant_lights[0].material, "sun_mat");
    // The census: an illum's surface spawns what its glass does; the sun is a sampled emitter.
    Census c = take_census(s);
    for (const auto& m : c.materials) {
        if (m.name == "window") {
            EXPECT_EQ(component_set_letters(m.spawns), "T R");
        }
    }
    EXPECT_GE(c.sampled_emitters, 4u);  // the spotlight, the two illums, the sun
}

TEST(RadianceGrammar, WhatItReadsExportsToJsonAndBackUnchanged) {
    // Everything new in the scene model (distant lights and skies, spotlights, illum, glow
    // radii, anisotropy, interfaces, inward shapes, projections) survives --export-json.
    auto r = testing::load_rad_text(R"(#@crex view -vta -vp 0 0 1 -vd 0 1 0 -vu 0 0 1 -vh 180 -vv 170 -vo .2
void plastic2 p2 4 1 0 0 . 0 6 .5 .4 .3 .05 .1 .2
void interface water 0 0 8 .98 .97 .96 1.33 .9 .8 .7 1.5
void spotlight beam 0 0 7 10 20 30 40 0 0 -2
void glow dim 0 0 4 1 1 1 -1
void glass pane 0 0 3 .9 .9 .9
void illum window 1 pane 0 3 5 5 5
!gensky 6 21 14 -a 40 -o 105 -m 105
skyfunc glow sky_mat 0 0 4 1 1 1 0
sky_mat source sky 0 0 4 0 0 1 180
p2 sphere a 0 0 4 0 0 0 1
water bubble b 0 0 4 3 0 0 1
beam ring e 0 0 8 0 0 9 0 0 -1 0 .1
dim tube f 0 0 7 9 0 0 9 0 1 .1
window polygon g 0 0 12 0 0 7 1 0 7 1 1 7 0 1 7
)");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const nlohmann::json first = scene_to_json(*r.scene);
    ASSERT_EQ(first["distant_lights"].size(), 2u);  // the sun and the sky
    EXPECT_EQ(first["distant_lights"][1]["sky"]["type"], "clear");
    EXPECT_EQ(first["camera"]["projection"], "angular");
    auto back = testing::load_json_text(scene_json_text(*r.scene));
    ASSERT_TRUE(back.scene) << (back.diagnostics.empty() ? "" : back.diagnostics[0].message);
    EXPECT_EQ(scene_to_json(*back.scene), first);
}

TEST(RadianceViews, EveryViewTypeAndTheForeClip) {
    const std::pair<const char*, Projection> types[] = {{"-vtv", Projection::kPerspective}, {"-vtl", Projection::kParallel},
                                                        {"-vta", Projection::kAngular},     {"-vth", Projection::kHemispherical},
                                                        {"-vts", Projection::kStereographic}, {"-vtc", Projection::kCylindrical}};
    for (const auto& [option, projection] : types) {
        auto r = testing::load_rad_text(std::string(kLight) + "l sphere s 0 0 4 0 0 0 1\n",
                                        std::string("rview ") + option + " -vp 0 0 5 -vd 0 0 -1 -vu 0 1 0 -vh 90 -vv 60 -vo .5\n");
        ASSERT_TRUE(r.scene) << option;
        EXPECT_EQ(r.scene->camera.projection, projection) << option;
        EXPECT_DOUBLE_EQ(r.scene->camera.fore_clip, 0.5);
    }
}

TEST(RadianceProject, RendersBackFaceOptionAsRadReadsIt) {
    // rad joins every render line and reads -bv as check_bool does: bare toggles, + on, - off,
    // anything else leaves it; the variable's name may be cut to three letters. JSON keeps it.
    SceneDir dir("rif_bv");
    dir.write("room.rad", std::string(kLight) + "l sphere s 0 0 4 0 0 0 1\n");
    const std::pair<const char*, bool> cases[] = {{"", true},
                                                  {"render = -ab 1 -bv-\n", false},
                                                  {"ren = -bv\n", false},
                                                  {"render = -bv-\nrender = -bv+\n", true},
                                                  {"render = -bv -bv\n", true},
                                                  {"render = -bvx -bvv -bv0\n", false},
                                                  {"QUAL = -bv-\n", true}};
    for (const auto& [lines, visible] : cases) {
        const std::string rif = dir.write("p.rif", std::string("scene = room.rad\n") + lines + "view = -vp 0 0 5 -vd 0 0 -1 -vu 0 1 0\n");
        auto r = testing::load_path(rif);
        ASSERT_TRUE(r.scene) << lines << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
        EXPECT_EQ(r.scene->back_faces_visible, visible) << lines;
        auto back = testing::load_json_text(scene_json_text(*r.scene));
        ASSERT_TRUE(back.scene) << lines;
        EXPECT_EQ(back.scene->back_faces_visible, visible) << lines;
    }
}

TEST(RadianceCommands, GenboxFacesNamesAndNormals) {
    auto r = testing::load_rad_text(std::string(kLight) + "!genbox l crate 2 3 4\n");
    ASSERT_TRUE(r.scene);
    const Scene& s = *r.scene;
    ASSERT_EQ(s.shapes.size(), 6u);
    // genbox's names: the corners' digits; corner k has x from bit 0, y from bit 1, z from
    // bit 2, so "crate.1540" is the y = 0 face, checked by hand:
    const Shape* f = shape_named(s, "crate.1540");
    ASSERT_TRUE(f);
    expect_near(f->vertices[0], {2, 0, 0}, 0, "crate.1540 corner 1");
    expect_near(f->vertices[1], {2, 0, 4}, 0, "crate.1540 corner 5");
    expect_near(f->vertices[3], {0, 0, 0}, 0, "crate.1540 corner 0");
    double area = 0;
    const Vec3 centre{1, 1.5, 2};
    for (const auto& sh : s.shapes) {
        area += polygon_signed_area(sh.vertices);
        Vec3 n = cross(sh.vertices[1] - sh.vertices[0], sh.vertices[2] - sh.vertices[0]);
        EXPECT_LT(dot(n, centre - sh.vertices[0]), 0) << sh.name << " faces outward";
    }
    EXPECT_NEAR(area, 2 * (2 * 3 + 3 * 4 + 2 * 4), 1e-12);
    auto rounded = testing::load_rad_text(std::string(kLight) + "!genbox l r 1 1 1 -r .1\n");
    ASSERT_TRUE(rounded.scene);
    size_t spheres = 0, cylinders = 0, polygons = 0;
    for (const auto& sh : rounded.scene->shapes)
        spheres += sh.type == ShapeType::kSphere, cylinders += sh.type == ShapeType::kCylinder, polygons += sh.type == ShapeType::kPolygon;
    EXPECT_EQ(spheres, 8u);
    EXPECT_EQ(cylinders, 12u);
    EXPECT_EQ(polygons, 6u);
    auto bevelled = testing::load_rad_text(std::string(kLight) + "!genbox l b 1 1 1 -b .1\n");
    ASSERT_TRUE(bevelled.scene);
    EXPECT_EQ(bevelled.scene->shapes.size(), 6u + 12u + 8u);
}

TEST(RadianceCommands, GenprismWithSeamAndExtrusionThroughXform) {
    // RADIANCE's own test wall: a 5.2 x 3.2 outline with a 1 x 3 window, joined by a seam (-c:
    // the list is closed already), extruded 0.2 and stood up by xform.
    auto r = testing::load_rad_text(std::string(kLight) +
                                    "!genprism l end_wall 10  -.1 -.1  -.1 5.1  3.1 5.1  3.1 -.1  -.1 -.1 \\\n"
                                    "\t\t1 1  2 1  2 4  1 4  1 1  -l 0 0 .2 -c \\\n"
                                    "\t| xform -ry -90 -t -8 0 0\n");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Scene& s = *r.scene;
    const Shape* bottom = shape_named(s, "end_wall.b");
    ASSERT_TRUE(bottom);
    // The end caps: 5.2 x 3.2 less the 1 x 3 window.
    EXPECT_NEAR(polygon_signed_area(bottom->vertices), 5.2 * 3.2 - 3.0, 1e-9);
    double covered = 0;
    for (const auto& t : triangulate_polygon(bottom->vertices))
        covered += 0.5 * length(cross(bottom->vertices[t[1]] - bottom->vertices[t[0]], bottom->vertices[t[2]] - bottom->vertices[t[0]]));
    EXPECT_NEAR(covered, 5.2 * 3.2 - 3.0, 1e-9);
    // -ry -90 takes (x, y, 0) to (0, y, x)... then -t -8 0 0: the bottom cap lies in x = -8.
    for (const auto& v : bottom->vertices) EXPECT_NEAR(v.x, -8, 1e-12);
    const Shape* top = shape_named(s, "end_wall.t");
    ASSERT_TRUE(top);
    for (const auto& v : top->vertices) EXPECT_NEAR(v.x, -8.2, 1e-12);
    // Nine sides (ten vertices, the closing one left out by -c).
    size_t sides = 0;
    for (const auto& sh : s.shapes) sides += sh.name != "end_wall.b" && sh.name != "end_wall.t";
    EXPECT_EQ(sides, 9u);
}

TEST(RadianceCommands, GenrevSweepsItsCurve) {
    auto r = testing::load_rad_text(std::string(kLight) + "!genrev l torus 'sin(2*PI*t)' '2+cos(2*PI*t)' 32\n");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Scene& s = *r.scene;
    ASSERT_EQ(s.shapes.size(), 32u);
    // Segment k runs from t = (k-1)/32 to k/32: cones where z rises, cups where it falls.
    const Shape* first = shape_named(s, "torus.1");
    ASSERT_TRUE(first);
    EXPECT_EQ(first->type, ShapeType::kCone);
    EXPECT_FALSE(first->inward);
    EXPECT_NEAR(first->p1.z, std::sin(2 * M_PI / 32), 1e-12);
    EXPECT_NEAR(first->r1, 2 + std::cos(2 * M_PI / 32), 1e-12);
    EXPECT_TRUE(shape_named(s, "torus.10")->inward);  // t in [9/32, 10/32]: z falls
    auto bad = testing::load_rad_text(std::string(kLight) + "!genrev l x 't' 'sqrt(-1-t)' 4\n");
    EXPECT_FALSE(bad.scene);
    testing::expect_diagnostic(bad, "genrev_nan", "E302", 2, 17, "not a finite number");
}

TEST(RadianceCommands, XformArraysNamesModifiersAndNestedFiles) {
    SceneDir dir("xform");
    dir.write("parts/leg.rad", "wood cylinder leg 0 0 7 0 0 0 0 0 1 .05\n!xform -t 0 0 1 ./top.rad\n");
    dir.write("parts/top.rad", "wood ring top 0 0 8 0 0 0 0 0 1 0 .5\n");
    std::string main = dir.write("scene.rad", std::string(kLight) + "void plastic wood 0 0 5 .5 .4 .3 0 0\nvoid metal steel 0 0 5 .8 .8 .8 .9 0\n"
                                              "!xform -n table -a 3 -t 2 0 0 -i 1 -t 0 10 0 parts/leg.rad\n"
                                              "!xform -m steel -rz 90 parts/leg.rad\n"
                                              "!xform -I parts/top.rad\n");
    auto r = testing::load_path(main);
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Scene& s = *r.scene;
    // Copy k: moved 2k along x, then 10 along y; named table.k.<id>; the nested file's top,
    // read relative to leg.rad, rises 1 more.
    for (int k = 0; k < 3; ++k) {
        const Shape* leg = shape_named(s, "table." + std::to_string(k) + ".leg");
        ASSERT_TRUE(leg) << k;
        expect_near(leg->p0, {2.0 * k, 10, 0}, 1e-12, "leg");
        const Shape* top = shape_named(s, "table." + std::to_string(k) + ".top");
        ASSERT_TRUE(top) << k;
        expect_near(top->center, {2.0 * k, 10, 1}, 1e-12, "top");
        EXPECT_EQ(s.find_material(leg->material)->type, MaterialType::kPlastic);
    }
    // -m gives every surface the new modifier; -rz 90 turns the ring's normal (0, 0, 1) into itself.
    size_t steel = 0;
    for (const auto& sh : s.shapes) steel += s.find_material(sh.material)->type == MaterialType::kMetal;
    EXPECT_EQ(steel, 2u);
    // -I turns surfaces inside out: the ring's normal flips.
    size_t flipped = 0;
    for (const auto& sh : s.shapes) flipped += sh.type == ShapeType::kRing && sh.normal.z < 0;
    EXPECT_EQ(flipped, 1u);
}

TEST(RadianceCommands, AFileThatReadsItselfStops) {
    SceneDir dir("loop");
    std::string main = dir.write("loop.rad", std::string(kLight) + "!xform -t 1 0 0 loop.rad\n");
    auto r = testing::load_path(main);
    EXPECT_FALSE(r.scene);
    testing::expect_diagnostic(r, "self_include", "E301", 2, 2, "files nest more than 32 deep");
}

TEST(RadianceTags, AnObjectByCommandNamePrefixModifierOrBlock) {
    auto r = testing::load_rad_text(std::string(kLight) + R"(
void plastic paint 0 0 5 .5 .5 .5 0 0
void plastic sign 0 0 5 .9 .1 .1 0 0
#@crex tag name=crate task=3
!genbox paint crate 1 1 1
!genbox paint car.body 2 1 1
#@crex tag name=car task=2 object=car
#@crex tag name=signs distractor=true modifier=sign
sign polygon s1 0 0 12 0 0 5 1 0 5 1 1 5 0 1 5
sign polygon s2 0 0 12 0 0 6 1 0 6 1 1 6 0 1 6
#@crex tag name=shelf begin
paint sphere a 0 0 4 0 0 9 .1
paint sphere b 0 0 4 0 0 10 .1
#@crex tag end
paint sphere untagged 0 0 4 0 0 12 .1
#@crex tag name=nothing prefix=zzz
)");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    Census c = take_census(*r.scene);
    std::map<std::string, size_t> counts;
    for (size_t i = 0; i < c.tags.size(); ++i) counts[c.tags[i]] = c.tag_surfaces[i];
    EXPECT_EQ(counts["crate"], 6u);  // all six faces of the box, not just the first
    EXPECT_EQ(counts["car"], 6u);
    EXPECT_EQ(counts["signs"], 2u);
    EXPECT_EQ(counts["shelf"], 2u);
    EXPECT_EQ(counts.count("nothing"), 0u);
    EXPECT_FALSE(shape_named(*r.scene, "untagged")->tag);
    EXPECT_EQ(shape_named(*r.scene, "crate.1540")->tag->task, 3);
    EXPECT_TRUE(shape_named(*r.scene, "s1")->tag->distractor);
    testing::expect_diagnostic(r, "unused_tag", "W307", 17, 1, "tag 'nothing' tags no surface");
}

TEST(RadianceCalc, ExpressionsFunctionsAndTheLibrary) {
    radiance::calc::Program p;
    radiance::calc::Error e;
    ASSERT_TRUE(p.define("{ a comment {nested} } sq3(x) = x*x*x; fact(n) = if(n - .5, n*fact(n-1), 1); c : 2^3^2;", e)) << e.message;
    auto eval = [&](const std::string& text) {
        radiance::calc::Error err;
        auto n = p.parse(text, err);
        EXPECT_TRUE(n) << text << ": " << err.message;
        auto v = n ? p.evaluate(*n, {{}, {5, 7}}, err) : std::nullopt;
        EXPECT_TRUE(v) << text << ": " << err.message;
        return v.value_or(NAN);
    };
    EXPECT_DOUBLE_EQ(eval("sq3(2) + 1"), 9);
    EXPECT_DOUBLE_EQ(eval("fact(5)"), 120);
    EXPECT_DOUBLE_EQ(eval("c"), 512);  // ^ is right associative
    EXPECT_DOUBLE_EQ(eval("-2^2"), 4);  // and unary minus binds tighter, as in RADIANCE
    EXPECT_DOUBLE_EQ(eval("A1 + arg(2) + arg(0)"), 14);
    EXPECT_DOUBLE_EQ(eval("select(2, 10, 20, 30) + max(1, 5, 3) + abs(-2) + mod(7, 3)"), 28);
    EXPECT_NEAR(eval("Acos(2) + PI/DEGREE"), 180, 1e-9);
    radiance::calc::Error err;
    auto unknown = p.parse("wobble3(1, 2, 3)", err);
    ASSERT_TRUE(unknown);
    EXPECT_FALSE(p.evaluate(*unknown, {}, err));
    EXPECT_NE(err.message.find("unknown function 'wobble3'"), std::string::npos) << err.message;
    radiance::calc::Error deep;
    EXPECT_FALSE(p.parse(std::string(5000, '(') + "1" + std::string(5000, ')'), deep));
}

}  // namespace
}  // namespace crex
