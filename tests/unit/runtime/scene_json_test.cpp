// The native scene format: every primitive and material loads, round trips are exact, and
// bad input is a located error, never a crash.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "runtime/scene/census.h"
#include "runtime/scene/shapes.h"
#include "tests/support/scene_helpers.h"

namespace crex {
namespace {

const char* kMaterials = R"([
  {"name": "p", "type": "plastic", "color": [0.5, 0.4, 0.3], "specularity": 0.1, "roughness": 0.2},
  {"name": "m", "type": "metal", "color": [0.9, 0.8, 0.7], "specularity": 0.8, "roughness": 0},
  {"name": "t", "type": "trans", "color": [0.6, 0.6, 0.6], "specularity": 0.03, "roughness": 0.05,
   "transmissivity": 0.5, "transmitted_specular": 0.4},
  {"name": "g", "type": "glass", "color": [0.96, 0.96, 0.96], "ior": 1.45, "thin": true},
  {"name": "d", "type": "dielectric", "color": [0.9, 0.9, 1.0], "ior": 1.33},
  {"name": "mi", "type": "mirror", "color": [0.95, 0.95, 0.95]},
  {"name": "l", "type": "light", "color": [10, 10, 10]},
  {"name": "gl", "type": "glow", "color": [1, 2, 3], "glow_radius": 4},
  {"name": "v", "type": "void"},
  {"name": "e", "type": "plastic", "color": [0.2, 0.2, 0.2], "emission": [0.1, 0.2, 0.3]}
])";

const char* kShapes = R"([
  {"type": "sphere", "material": "p", "center": [0, 0, 0], "radius": 1, "name": "ball",
   "tag": {"name": "target", "task": 2, "distractor": true}},
  {"type": "polygon", "material": "m", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]},
  {"type": "mesh", "material": "t", "vertices": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]], "triangles": [[0,1,2],[0,1,3]]},
  {"type": "box", "material": "g", "min": [0,0,0], "max": [1,2,3]},
  {"type": "ring", "material": "d", "center": [0,0,0], "normal": [0,0,1], "inner_radius": 0.5, "outer_radius": 1},
  {"type": "cone", "material": "mi", "p0": [0,0,0], "p1": [0,0,1], "r0": 1, "r1": 0},
  {"type": "cylinder", "material": "l", "p0": [0,0,0], "p1": [0,1,0], "radius": 0.5},
  {"type": "sphere", "material": "gl", "center": [3,0,0], "radius": 0.1},
  {"type": "sphere", "material": "v", "center": [4,0,0], "radius": 0.1},
  {"type": "sphere", "material": "e", "center": [5,0,0], "radius": 0.1}
])";

std::string every_kind() {
    return std::string(R"({"format": "crex-scene", "version": 1,
      "camera": {"position": [0,0,5], "look_at": [0,0,0], "up": [0,1,0], "vfov": 30, "hfov": 40, "view_distance": 2},
      "background": [0.1, 0.2, 0.3],
      "medium": {"extinction": [0.01, 0.01, 0.02], "albedo": [0.9, 0.9, 0.9], "eccentricity": 0.3, "box": [[-9, -8, -7], [7, 8, 9]]},
      "materials": )") + kMaterials + R"(, "shapes": )" + kShapes + "}";
}

TEST(SceneJson, LoadsEveryPrimitiveAndMaterial) {
    auto r = testing::load_json_text(every_kind());
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Scene& s = *r.scene;
    ASSERT_EQ(s.materials.size(), 10u);
    ASSERT_EQ(s.shapes.size(), 10u);
    EXPECT_EQ(s.materials[2].type, MaterialType::kTrans);
    EXPECT_DOUBLE_EQ(s.materials[2].transmitted_specular, 0.4);
    EXPECT_DOUBLE_EQ(s.materials[3].ior, 1.45);
    EXPECT_TRUE(s.materials[3].thin_glass);  // a pane; the round trip below keeps it
    EXPECT_DOUBLE_EQ(s.materials[7].glow_radius, 4);
    ASSERT_TRUE(s.materials[9].emission.has_value());
    EXPECT_EQ(s.shapes[0].tag->name, "target");
    EXPECT_EQ(s.shapes[0].tag->task, 2);
    EXPECT_TRUE(s.shapes[0].tag->distractor);
    EXPECT_EQ(s.shapes[2].triangles.size(), 2u);
    EXPECT_EQ(s.camera.direction, (Vec3{0, 0, -5}));  // from look_at
    EXPECT_DOUBLE_EQ(s.camera.hfov_deg, 40);
    ASSERT_TRUE(s.medium.has_value());
    EXPECT_DOUBLE_EQ(s.medium->eccentricity, 0.3);
    EXPECT_TRUE(s.medium->bounded);
    EXPECT_EQ(s.medium->box_min, (Vec3{-9, -8, -7}));
    EXPECT_EQ(s.medium->box_max, (Vec3{7, 8, 9}));
    EXPECT_EQ(s.background, (Vec3{0.1, 0.2, 0.3}));
    std::vector<ShapeType> types;
    for (const auto& sh : s.shapes) types.push_back(sh.type);
    EXPECT_EQ(types, (std::vector<ShapeType>{ShapeType::kSphere, ShapeType::kPolygon, ShapeType::kMesh, ShapeType::kBox,
                                             ShapeType::kRing, ShapeType::kCone, ShapeType::kCylinder, ShapeType::kSphere,
                                             ShapeType::kSphere, ShapeType::kSphere}));
}

TEST(SceneJson, RoundTripIsExact) {
    for (const std::string& text : {every_kind(), scene_json_text(*builtin_scene("cornell"))}) {
        auto a = testing::load_json_text(text);
        ASSERT_TRUE(a.scene);
        nlohmann::json first = scene_to_json(*a.scene);
        auto b = testing::load_json_text(scene_json_text(*a.scene));
        ASSERT_TRUE(b.scene);
        EXPECT_EQ(scene_to_json(*b.scene), first);
    }
}

TEST(SceneJson, BuiltinCornellEqualsItsExampleFile) {
    auto r = testing::load_path(CREX_SOURCE_DIR "/examples/scenes/cornell/scene.json");
    ASSERT_TRUE(r.scene);
    EXPECT_EQ(scene_to_json(*r.scene), scene_to_json(*builtin_scene("cornell")));
    auto d = testing::load_path(CREX_SOURCE_DIR "/examples/scenes/cornell_diffuse/scene.json");
    ASSERT_TRUE(d.scene);
    EXPECT_EQ(scene_to_json(*d.scene), scene_to_json(*builtin_scene("cornell_diffuse")));
}

TEST(SceneJson, CommentsAreAllowed) {
    auto r = testing::load_json_text("// a comment\n{ /* here too */ \"shapes\": [] }");
    EXPECT_TRUE(r.scene);
}

struct BadJson {
    const char* name;
    std::string text;
    const char* code;
    uint32_t line;
    uint32_t col;
    const char* message_part;
};

std::string with_shapes(const std::string& shapes, const std::string& materials =
                                                        R"([{"name": "w", "type": "plastic"}, {"name": "l", "type": "light", "color": [1,1,1]}])") {
    return "{\n\"materials\": " + materials + ",\n\"shapes\": " + shapes + "\n}";
}

class SceneJsonBadInput : public ::testing::TestWithParam<BadJson> {};

TEST_P(SceneJsonBadInput, IsALocatedErrorNamingTheField) {
    const BadJson& c = GetParam();
    auto r = testing::load_json_text(c.text);
    EXPECT_FALSE(r.scene) << c.name;
    testing::expect_diagnostic(r, c.name, c.code, c.line, c.col, c.message_part);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, SceneJsonBadInput,
    ::testing::Values(
        BadJson{"truncated", "{\"shapes\": [", "E301", 1, 13, "unexpected end of input"},
        BadJson{"trailing_comma", "{\"shapes\": [],}", "E301", 1, 0, "syntax error"},
        BadJson{"nan_literal", "{\"shapes\": [{\"type\": \"sphere\", \"radius\": NaN}]}", "E301", 1, 0, "syntax error"},
        BadJson{"infinite_number", "{\"background\": [1e999, 0, 0], \"shapes\": []}", "E301", 1, 0, "overflow"},
        BadJson{"not_an_object", "[1, 2]", "E302", 1, 1, "must hold a JSON object"},
        BadJson{"wrong_type", with_shapes(R"([{"type": "sphere", "material": "w", "center": [0,0,0], "radius": "big"}])"),
                "E302", 3, 77, "shapes[0].radius: expected a number > 0, got a string"},
        BadJson{"out_of_range",
                with_shapes("[]", R"([{"name": "w", "type": "plastic", "roughness": -0.3}])"), "E303", 2, 61,
                "materials[0].roughness: expected a number in [0, 1], got -0.3"},
        BadJson{"reflectance_above_one", with_shapes("[]", R"([{"name": "w", "type": "plastic", "color": [0.5, 1.5, 0]}])"),
                "E303", 2, 0, "materials[0].color[1]"},
        // A lamp of 1e100 overflowed the image's floats: every sample dropped, a black image.
        BadJson{"radiance_beyond_floats", with_shapes("[]", R"([{"name": "w", "type": "light", "color": [1, 1e100, 1]}])"),
                "E303", 2, 0, "materials[0].color[1]: expected a number in [0, 1e+30], got 1e+100"},
        BadJson{"background_beyond_floats", "{\"background\": [1e31, 0, 0], \"shapes\": []}", "E303", 1, 0, "background[0]"},
        BadJson{"missing_field", with_shapes(R"([{"type": "sphere", "material": "w", "center": [0,0,0]}])"), "E304", 3, 12,
                "missing required field 'radius'"},
        BadJson{"unknown_material", with_shapes(R"([{"type": "sphere", "material": "wite", "center": [0,0,0], "radius": 1}])"),
                "E305", 3, 43, "no material named 'wite'"},
        BadJson{"duplicate_material", with_shapes("[]", R"([{"name": "w", "type": "plastic"}, {"name": "w", "type": "mirror"}])"),
                "E305", 2, 0, "already defined"},
        BadJson{"duplicate_key", "{\"shapes\": [], \"shapes\": []}", "E301", 1, 16, "duplicate key"},
        BadJson{"degenerate_ring_normal",
                with_shapes(R"([{"type": "ring", "material": "w", "center": [0,0,0], "normal": [0,0,0], "outer_radius": 1}])"),
                "E306", 3, 0, "degenerate normal"},
        BadJson{"ring_radii", with_shapes(R"([{"type": "ring", "material": "w", "center": [0,0,0], "normal": [0,0,1], "inner_radius": 2, "outer_radius": 1}])"),
                "E306", 3, 0, "inner < outer"},
        BadJson{"cylinder_axis", with_shapes(R"([{"type": "cylinder", "material": "w", "p0": [1,1,1], "p1": [1,1,1], "radius": 1}])"),
                "E306", 3, 0, "axis is degenerate"},
        BadJson{"box_inverted", with_shapes(R"([{"type": "box", "material": "w", "min": [0,0,0], "max": [1,-1,1]}])"), "E306", 3, 0,
                "below 'max'"},
        BadJson{"mesh_index", with_shapes(R"([{"type": "mesh", "material": "w", "vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,7]]}])"),
                "E303", 3, 0, "vertex index 7 out of range"},
        BadJson{"camera_up_parallel", "{\"camera\": {\"direction\": [0,1,0], \"up\": [0,2,0]}, \"shapes\": []}", "E306", 1, 0,
                "parallel"},
        BadJson{"unknown_shape_type", with_shapes(R"([{"type": "torus", "material": "w"}])"), "E303", 3, 0, "unknown shape type 'torus'"},
        BadJson{"unknown_material_type", with_shapes("[]", R"([{"name": "w", "type": "lambert"}])"), "E303", 2, 0,
                "unknown material type 'lambert'"},
        BadJson{"tag_task_range", with_shapes(R"([{"type": "sphere", "material": "w", "center": [0,0,0], "radius": 1, "tag": {"name": "x", "task": 4}}])"),
                "E303", 3, 0, "expected an integer in 0 .. 3"}),
    [](const ::testing::TestParamInfo<BadJson>& p) { return std::string(p.param.name); });

TEST(SceneJson, UnknownFieldsWarnWithTheNearestName) {
    auto r = testing::load_json_text(with_shapes("[]", R"([{"name": "w", "type": "plastic", "colour": [1,1,1]}])"));
    EXPECT_TRUE(r.scene);
    const Diagnostic* d = r.find("W301");
    ASSERT_NE(d, nullptr);
    EXPECT_EQ(d->help, "did you mean 'color'?");
    EXPECT_EQ(r.where("W301").line, 2u);
}

TEST(SceneJson, SceneWithoutLightsWarns) {
    auto r = testing::load_json_text(with_shapes(R"([{"type": "sphere", "material": "w", "center": [0,0,0], "radius": 1}])"));
    ASSERT_TRUE(r.scene);
    EXPECT_NE(r.find("W302"), nullptr);
}

TEST(SceneJson, DegenerateMeshTrianglesAreDroppedWithAWarning) {
    auto r = testing::load_json_text(with_shapes(
        R"([{"type": "mesh", "material": "w", "vertices": [[0,0,0],[1,0,0],[0,1,0],[2,0,0]], "triangles": [[0,1,2],[0,1,3],[0,0,2]]},
            {"type": "sphere", "material": "l", "center": [0,5,0], "radius": 1}])"));
    ASSERT_TRUE(r.scene);
    const Diagnostic* d = r.find("W303");
    ASSERT_NE(d, nullptr);
    EXPECT_NE(d->message.find("2 of 3 triangles"), std::string::npos) << d->message;
    TriangleMesh m;
    tessellate(r.scene->shapes[0], m);
    EXPECT_EQ(m.indices.size(), 1u);
}

TEST(SceneJson, ReportsEveryErrorInOnePass) {
    auto r = testing::load_json_text(with_shapes(
        R"([{"type": "sphere", "material": "nope", "center": [0,0,0], "radius": -1},
            {"type": "box", "material": "w", "min": "x", "max": [1,1,1]}])",
        R"([{"name": "w", "type": "plastic", "specularity": 2}])"));
    EXPECT_FALSE(r.scene);
    EXPECT_GE(r.errors, 4u);
}

TEST(SceneLoad, MissingFileIsAnIoFailureNamingIt) {
    SceneSources sources;
    DiagnosticSink sink;
    SceneLoadFailure failure;
    EXPECT_FALSE(load_scene("/nonexistent/dir/scene.json", sources, sink, failure));
    EXPECT_NE(failure.message.find("/nonexistent/dir/scene.json"), std::string::npos);
    EXPECT_NE(failure.message.find("No such file"), std::string::npos);
    EXPECT_FALSE(load_scene("builtin:nope", sources, sink, failure));
    EXPECT_NE(failure.message.find("builtin:cornell"), std::string::npos);
    EXPECT_FALSE(load_scene("scene.xyz", sources, sink, failure));
    EXPECT_NE(failure.message.find(".rad"), std::string::npos);
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(SceneDegeneracy, ZeroAreaIsRelativeToTheShapeAndDroppedWithAWarning) {
    // A zero-area polygon is dropped with W304 (RADIANCE warns too), the scene still loads.
    auto zero = testing::load_json_text(
        with_shapes(R"([{"type": "polygon", "material": "w", "vertices": [[0,0,0],[1,0,0],[2,0,0]]}])"));
    EXPECT_TRUE(zero.scene);
    testing::expect_diagnostic(zero, "zero_area_polygon", "W304", 3, 12, "zero area for its size");
    // A +-1e6 ground plane used to raise the threshold until the 4 m2 floor was "zero-area".
    auto big = testing::load_json_text(with_shapes(R"([
      {"type": "polygon", "material": "w", "vertices": [[-1e6,-1,-1e6],[1e6,-1,-1e6],[1e6,-1,1e6],[-1e6,-1,1e6]]},
      {"type": "polygon", "material": "w", "vertices": [[-1,0,-1],[1,0,-1],[1,0,1],[-1,0,1]]},
      {"type": "cylinder", "material": "w", "p0": [0,0,0], "p1": [0,0.001,0], "radius": 0.01},
      {"type": "sphere", "material": "l", "center": [0,3,0], "radius": 0.5}])"));
    EXPECT_TRUE(big.scene);
    EXPECT_EQ(big.errors, 0u) << (big.diagnostics.empty() ? "" : big.diagnostics[0].message);
    EXPECT_EQ(big.find("W304"), nullptr);
}

// One sphere of `radius` at the origin, seen from `camera_z` along -z.
std::string one_sphere_scene_json(const char* camera_z, const char* radius) {
    return fmt::format("{{\"camera\": {{\"position\": [0, 0, {}], \"direction\": [0, 0, -1]}},\n\"materials\": "
                       "[{{\"name\": \"w\", \"type\": \"plastic\"}}],\n\"shapes\": [{{\"type\": \"sphere\", "
                       "\"material\": \"w\", \"center\": [0,0,0], \"radius\": {}}}]}}",
                       camera_z, radius);
}

TEST(SceneDegeneracy, ACameraBeyondWhatFloatRaysReachIsALocatedError) {
    // A camera coordinate above ~1.8e18 aborted inside Embree (exit 134); scene-info accepted it.
    auto far = testing::load_json_text(one_sphere_scene_json("2e18", "1"));
    EXPECT_FALSE(far.scene);
    ASSERT_NE(far.find("E303"), nullptr);
    EXPECT_NE(far.find("E303")->message.find("more than float rays can represent"), std::string::npos) << far.find("E303")->message;
}

TEST(SceneDegeneracy, ASceneTooSmallForFloatRaysIsALocatedError) {
    // 1e-15 across, Embree's float arithmetic fails: the box rendered a third as bright, silently.
    auto tiny = testing::load_json_text(one_sphere_scene_json("4e-15", "1e-15"));
    EXPECT_FALSE(tiny.scene);
    ASSERT_NE(tiny.find("E303"), nullptr);
    EXPECT_NE(tiny.find("E303")->message.find("less than float rays can resolve"), std::string::npos) << tiny.find("E303")->message;
    // 1e-11 across is within reach: no error.
    auto small = testing::load_json_text(one_sphere_scene_json("4e-11", "1e-11"));
    EXPECT_EQ(small.find("E303"), nullptr) << (small.diagnostics.empty() ? "" : small.diagnostics[0].message);
}

TEST(SceneDegeneracy, ACameraIsJudgedAgainstTheScenesCentreNotTheOrigin) {
    // Every camera a run renders from (--view, --camera, each frame of a path) goes through
    // camera_problem, as the scene's own does.
    SceneBox box;
    box.lo = {1e16 - 1, -1, -1};
    box.hi = {1e16 + 1, 1, 1};
    Camera near;
    near.position = {1e16, 0, 5};
    EXPECT_EQ(camera_problem(near, box), "");
    Camera far = near;
    far.position = {0, 0, 5};
    EXPECT_NE(camera_problem(far, box).find("1e+16 units from the scene"), std::string::npos) << camera_problem(far, box);
    far.position = {0, 1.5e308, 0};  // its distance overflows: still said in words, not "inf"
    EXPECT_NE(camera_problem(far, box).find("farther from the scene than float rays can represent"), std::string::npos);
    Camera nan = near;
    nan.direction.x = NAN;
    EXPECT_NE(camera_problem(nan, box).find("non-finite"), std::string::npos);
    EXPECT_EQ(camera_problem(far, SceneBox{}), "");  // a scene without shapes has no centre to be far from
    Camera up = near;
    up.direction = {0, 2, 0};  // along its up: every camera ray would be the same
    EXPECT_NE(camera_problem(up, box).find("looking along its up vector"), std::string::npos) << camera_problem(up, box);
    up.direction = {};
    EXPECT_NE(camera_problem(up, box).find("looking along its up vector"), std::string::npos);
}

}  // namespace
}  // namespace crex
