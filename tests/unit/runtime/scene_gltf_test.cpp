// glTF 2.0 import (issue 33): the node tree and its transforms, materials by the documented
// table, KHR_texture_transform, KHR_lights_punctual, cameras and --camera, tags from node
// names and extras, embedded images; and what it cannot render or read, located.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "base/base64.h"
#include "runtime/scene/census.h"
#include "runtime/scene/shapes.h"
#include "tests/support/scene_helpers.h"

namespace crex {
namespace {

namespace fs = std::filesystem;

fs::path scratch() { return testing::scratch_folder("crex_gltf_test_"); }

std::string write(const std::string& name, const std::string& bytes) {
    const std::string path = (scratch() / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
}

template <class T>
void append(std::string& out, const std::vector<T>& values) {
    out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

// One triangle's buffer: 3 float3 positions (36 bytes), then 3 uint16 indices (6 bytes + 2 pad),
// then 3 float2 uvs (24 bytes).
std::string triangle_buffer() {
    std::string b;
    append(b, std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0});
    append(b, std::vector<uint16_t>{0, 1, 2, 0});
    append(b, std::vector<float>{0, 0, 1, 0, 0, 1});
    return b;
}

const std::string kBufferViews = R"("bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                  {"buffer": 0, "byteOffset": 36, "byteLength": 6},
                  {"buffer": 0, "byteOffset": 44, "byteLength": 24}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]},
                {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
                {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"}])";

std::string buffers() {
    return R"("buffers": [{"byteLength": 68, "uri": "data:application/octet-stream;base64,)" + base64(triangle_buffer()) + R"("}])";
}

// The test scene: a root node moved by (1, 0, 0) whose child is turned a quarter turn about
// +y and scaled by 2, holding the triangle; materials of every kind; two cameras and an
// orthographic one; a point, a spot and a directional light; tagged nodes.
std::string room_gltf() {
    return R"({"asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_transmission", "KHR_texture_transform", "KHR_materials_emissive_strength"],
  "scene": 0,
  "scenes": [{"nodes": [0, 3, 4, 5, 6, 7, 8, 9, 10]}],
  "nodes": [
    {"name": "root", "translation": [1, 0, 0], "children": [1]},
    {"name": "task2:cup", "rotation": [0, 0.7071067811865476, 0, 0.7071067811865476], "scale": [2, 2, 2], "mesh": 0},
    {"name": "unused"},
    {"name": "screen", "mesh": 1, "extras": {"distractor": true, "tag": "tv"}},
    {"name": "lamp", "mesh": 2},
    {"name": "front", "camera": 0, "translation": [0, 0, 5]},
    {"name": "side", "camera": 1, "matrix": [0,0,-1,0, 0,1,0,0, 1,0,0,0, 5,0,0,1]},
    {"name": "plan", "camera": 2, "translation": [0, 5, 0]},
    {"name": "bulb", "translation": [0, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
    {"name": "sun", "rotation": [-0.7071067811865476, 0, 0, 0.7071067811865476], "extensions": {"KHR_lights_punctual": {"light": 1}}},
    {"name": "reading", "translation": [0, 3, 0], "rotation": [-0.7071067811865476, 0, 0, 0.7071067811865476],
     "extensions": {"KHR_lights_punctual": {"light": 2}}}],
  "meshes": [
    {"name": "cup", "primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 2}, "indices": 1, "material": 0}]},
    {"name": "screen", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 1},
                                      {"attributes": {"POSITION": 0},
                                       "mode": 1, "material": 1}]},
    {"name": "lamp", "primitives": [{"attributes": {"POSITION": 0}, "material": 2}]}],
  "materials": [
    {"name": "glaze", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.4, 1], "metallicFactor": 0.5, "roughnessFactor": 0.5,
       "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "scale": [2, 2]}}},
       "metallicRoughnessTexture": {"index": 0}},
     "alphaMode": "MASK", "alphaCutoff": 0.3,
     "extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.8}}},
    {"name": "glow", "emissiveTexture": {"index": 0}, "emissiveFactor": [1, 1, 1],
     "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}},
    {"name": "panel", "emissiveFactor": [1, 0.5, 0.25], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2}}}],
  "textures": [{"source": 0, "sampler": 0}],
  "samplers": [{"wrapS": 33071, "wrapT": 33648, "magFilter": 9728}],
  "images": [{"uri": "wood%20grain.png"}],
  "cameras": [{"name": "front", "type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1}},
              {"type": "perspective", "perspective": {"yfov": 1.0, "znear": 0.1}},
              {"type": "orthographic",
               "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}}],
  "extensions": {"KHR_lights_punctual": {"lights": [{"name": "bulb", "type": "point", "intensity": 10, "color": [1, 0.5, 1]},
                                                   {"name": "sun", "type": "directional", "intensity": 3},
                                                   {"name": "reading", "type": "spot", "intensity": 20,
                                                    "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}]}},
  )" + kBufferViews + ",\n  " + buffers() + "}";
}

using testing::shape_named;

TEST(SceneGltf, NodeTransformsApplyDownTheTree) {
    write("wood grain.png", "not read here");
    auto r = testing::load_path(write("room.gltf", room_gltf()));
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Shape* cup = shape_named(*r.scene, "task2:cup");
    ASSERT_TRUE(cup);
    ASSERT_EQ(cup->vertices.size(), 3u);
    // (1, 0, 0) scaled by 2, turned a quarter turn about +y (x -> -z), moved by (1, 0, 0).
    EXPECT_NEAR(cup->vertices[1].x, 1, 1e-9);
    EXPECT_NEAR(cup->vertices[1].y, 0, 1e-9);
    EXPECT_NEAR(cup->vertices[1].z, -2, 1e-9);
    EXPECT_NEAR(cup->vertices[2].y, 2, 1e-9);
    ASSERT_EQ(cup->uvs.size(), 3u);
    EXPECT_EQ(cup->uvs[1], (std::array<double, 2>{1, 0}));
    EXPECT_DOUBLE_EQ(r.scene->units.metres_per_unit, 1);
    EXPECT_EQ(r.scene->units.up, (Vec3{0, 1, 0}));
}

// A closed unit cube (its faces wound to look out) and three point lights: one in open space,
// one 1 cm above the cube's top, one inside the cube, as a bulb modelled inside a lamp's pole.
std::string lamp_in_pole_gltf() {
    std::string b;
    append(b, std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1});
    append(b, std::vector<uint16_t>{0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                    3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5});
    return R"({"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_lights_punctual"], "scene": 0,
  "scenes": [{"nodes": [0, 1, 2, 3]}],
  "nodes": [{"name": "pole", "mesh": 0},
            {"name": "open", "translation": [0.5, 4, 0.5], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "above", "translation": [0.5, 1.01, 0.5], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "inside", "translation": [0.5, 0.5, 0.5], "extensions": {"KHR_lights_punctual": {"light": 1}}}],
  "meshes": [{"name": "pole", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 96}, {"buffer": 0, "byteOffset": 96, "byteLength": 72}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3", "min": [0,0,0], "max": [1,1,1]},
                {"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"}],
  "extensions": {"KHR_lights_punctual": {"lights": [{"name": "bulb", "type": "point", "intensity": 10},
                                                   {"name": "buried", "type": "point", "intensity": 10}]}},
  "buffers": [{"byteLength": 168, "uri": "data:application/octet-stream;base64,)" + base64(b) + R"("}]})";
}

TEST(SceneGltf, APointLightsBulbFitsTheSpaceAroundIt) {
    auto r = testing::load_path(write("lamp.gltf", lamp_in_pole_gltf()));
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Scene& s = *r.scene;
    const Shape* pole = shape_named(s, "pole");
    ASSERT_TRUE(pole);
    std::vector<const Shape*> bulbs;
    for (const Shape& shape : s.shapes)
        if (shape.name.rfind("light:", 0) == 0) bulbs.push_back(&shape);
    ASSERT_EQ(bulbs.size(), 3u);
    const double extent = std::sqrt(1 + 4.0 * 4 + 1);  // the cube and the open light's node
    for (const Shape* bulb : bulbs) {
        // No bulb reaches a surface, and each keeps its intensity whatever its size.
        EXPECT_GT(distance_to_surface(*pole, bulb->center).distance, bulb->radius) << bulb->name;
        const Material* m = s.find_material(bulb->material);
        ASSERT_TRUE(m);
        EXPECT_NEAR(m->color.x * M_PI * bulb->radius * bulb->radius, 10, 1e-9) << bulb->name;
    }
    EXPECT_NEAR(bulbs[0]->radius, 2.5e-3 * extent, 1e-12);  // in open space: sized by the scene
    EXPECT_NEAR(bulbs[1]->radius, 0.005, 1e-6);             // 1 cm from the cube: half of that
    EXPECT_NEAR(bulbs[2]->radius, 2.5e-3 * extent, 1e-12);  // in the middle of the cube: room enough
    // The two nodes of the first light have bulbs of different sizes, so materials of their own.
    EXPECT_NE(bulbs[0]->material, bulbs[1]->material);
    // Only the buried one is warned about, located at its node.
    int warned = 0;
    for (const auto& d : r.diagnostics)
        if (d.code == "W311" && d.message.find("'buried'") != std::string::npos && d.message.find("'pole'") != std::string::npos) ++warned;
    EXPECT_EQ(warned, 1);
    EXPECT_EQ(r.diagnostics.size(), 1u);
}

TEST(SceneGltf, APointLightOnASurfaceIsWarnedAbout) {
    // The light 1 cm above the cube moved to 0.1 mm: its bulb shrinks to 0.05 mm, and it says so.
    std::string text = lamp_in_pole_gltf();
    const size_t at = text.find("[0.5, 1.01, 0.5]");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 16, "[0.5, 1.0001, 0.5]");
    auto r = testing::load_path(write("lamp_on_pole.gltf", text));
    ASSERT_TRUE(r.scene);
    int near = 0, buried = 0;
    for (const auto& d : r.diagnostics) {
        if (d.code != "W311") continue;
        if (d.message.find("'bulb' is only 0.0001 from 'pole'") != std::string::npos) ++near;
        if (d.message.find("'buried'") != std::string::npos) ++buried;
    }
    EXPECT_EQ(near, 1);
    EXPECT_EQ(buried, 1);
    EXPECT_EQ(r.diagnostics.size(), 2u);
}

TEST(SceneGltf, DistanceToASurfaceFindsFacesEdgesAndCorners) {
    Shape tri;
    tri.type = ShapeType::kMesh;
    tri.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    tri.triangles = {{0, 1, 2}};
    EXPECT_NEAR(distance_to_surface(tri, {0.25, 0.25, 2}).distance, 2, 1e-12);  // over the face
    EXPECT_FALSE(distance_to_surface(tri, {0.25, 0.25, 2}).behind);            // on its front (+z)
    // Behind its back, but an open sheet (a leaf, a wall's panel) encloses nothing.
    EXPECT_FALSE(distance_to_surface(tri, {0.25, 0.25, -2}).behind);
    EXPECT_NEAR(distance_to_surface(tri, {0.5, -1, 0}).distance, 1, 1e-12);       // beyond an edge
    EXPECT_NEAR(distance_to_surface(tri, {1, 1, 0}).distance, std::sqrt(0.5), 1e-12);  // the long edge
    EXPECT_NEAR(distance_to_surface(tri, {-3, -4, 0}).distance, 5, 1e-12);       // beyond a corner
    // A unit cube wound to look out: inside it is behind; with its top left off, a point inside
    // sees out and is not.
    Shape cube;
    cube.type = ShapeType::kMesh;
    cube.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    cube.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                      {3, 7, 6}, {3, 6, 2}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};
    EXPECT_TRUE(distance_to_surface(cube, {0.5, 0.5, 0.5}).behind);
    EXPECT_TRUE(distance_to_surface(cube, {0.5, 0.99, 0.5}).behind);
    EXPECT_FALSE(distance_to_surface(cube, {0.5, 1.01, 0.5}).behind);
    Shape open_box = cube;
    open_box.triangles.erase(open_box.triangles.begin() + 6, open_box.triangles.begin() + 8);  // the y = 1 face
    EXPECT_FALSE(distance_to_surface(open_box, {0.5, 0.9, 0.5}).behind);
    Shape ball;
    ball.type = ShapeType::kSphere;
    ball.center = {0, 0, 0};
    ball.radius = 2;
    EXPECT_NEAR(distance_to_surface(ball, {0, 0, 5}).distance, 3, 1e-12);
    EXPECT_TRUE(distance_to_surface(ball, {0, 0.5, 0}).behind);
    ball.inward = true;  // a bubble: its inside is its front
    EXPECT_FALSE(distance_to_surface(ball, {0, 0.5, 0}).behind);
}

TEST(SceneGltf, MaterialsFollowTheDocumentedTable) {
    auto r = testing::load_path(write("room.gltf", room_gltf()));
    ASSERT_TRUE(r.scene);
    const Material* glaze = r.scene->find_material("room/glaze");
    ASSERT_TRUE(glaze);
    EXPECT_EQ(glaze->type, MaterialType::kTrans);  // KHR_materials_transmission
    EXPECT_DOUBLE_EQ(glaze->transmissivity, 0.8);
    EXPECT_DOUBLE_EQ(glaze->transmitted_specular, 1);
    EXPECT_NEAR(glaze->specularity, 0.04, 1e-12);  // F0 at ior 1.5
    EXPECT_DOUBLE_EQ(glaze->metallic, 0.5);
    EXPECT_DOUBLE_EQ(glaze->roughness, 0.25);  // perceptual roughness squared
    EXPECT_EQ(glaze->alpha_mode, AlphaMode::kMask);
    EXPECT_DOUBLE_EQ(glaze->alpha_cutoff, 0.3);
    const MaterialTextures& t = glaze->textures;
    ASSERT_TRUE(t.color && t.roughness && t.metallic && t.opacity);
    EXPECT_EQ(fs::path(t.color->file).filename(), "wood grain.png");  // percent-decoded, beside the file
    EXPECT_EQ(t.color->scale, (Vec3{0.8, 0.6, 0.4}));
    EXPECT_EQ(t.color->wrap_s, TextureWrap::kClamp);
    EXPECT_EQ(t.color->wrap_t, TextureWrap::kMirror);
    EXPECT_EQ(t.color->filter, TextureFilter::kNearest);  // magFilter NEAREST
    EXPECT_EQ(t.color->uv_transform, (UvTransform{2, 0, 0.5, 0, 2, 0}));
    EXPECT_EQ(t.roughness->channel, 1);
    EXPECT_DOUBLE_EQ(t.roughness->power, 2);
    EXPECT_EQ(t.metallic->channel, 2);
    EXPECT_EQ(t.opacity->channel, 3);
    // A textured emission glows over a reflecting material, sampled; a constant one is a
    // sampled lamp.
    const Material* glow = r.scene->find_material("room/glow");
    ASSERT_TRUE(glow && glow->textures.emission);
    EXPECT_EQ(glow->type, MaterialType::kPlastic);
    EXPECT_TRUE(glow->emission_sampled);
    EXPECT_EQ(glow->textures.emission->scale, (Vec3{4, 4, 4}));
    const Material* panel = r.scene->find_material("room/panel");
    ASSERT_TRUE(panel);
    EXPECT_EQ(panel->type, MaterialType::kLight);
    EXPECT_EQ(panel->color, (Vec3{2, 1, 0.5}));
    // The census of the trans, metallic, textured glaze: D, G (textured roughness), T.
    const ComponentSet s = spawned_components(*glaze);
    EXPECT_EQ(component_set_letters(s), "D G T");
}

// An unlit material only shows its image, and {"crex_light": false} says a textured emission is
// not a lamp: direct lighting samples neither (docs/textures.md).
TEST(SceneGltf, UnlitAndCrexLightFalseTexturedEmissionsAreNotSampled) {
    const std::string strength = R"({"emissiveStrength": 4}})";  // the glow material's, the first
    const std::string factor = R"("emissiveFactor": [1, 1, 1],)";
    std::string unlit = room_gltf(), not_a_lamp = room_gltf();
    ASSERT_NE(unlit.find(strength), std::string::npos);
    unlit.replace(unlit.find(strength), strength.size(), R"({"emissiveStrength": 4}, "KHR_materials_unlit": {}})");
    ASSERT_NE(not_a_lamp.find(factor), std::string::npos);
    not_a_lamp.replace(not_a_lamp.find(factor), factor.size(), factor + R"( "extras": {"crex_light": false},)");
    for (const std::string& text : {unlit, not_a_lamp}) {
        auto r = testing::load_path(write("room.gltf", text));
        ASSERT_TRUE(r.scene);
        const Material* glow = r.scene->find_material("room/glow");
        ASSERT_TRUE(glow);
        EXPECT_FALSE(glow->emission_sampled);
        EXPECT_FALSE(samples_textured_emission(*glow));
        EXPECT_GE(take_census(*r.scene).unsampled_emitters, 1u);
    }
}

TEST(SceneGltf, CamerasLightsAndTags) {
    auto r = testing::load_path(write("room.gltf", room_gltf()));
    ASSERT_TRUE(r.scene);
    Scene s = *r.scene;
    ASSERT_EQ(s.cameras.size(), 3u);
    EXPECT_EQ(s.cameras[0].name, "front");
    EXPECT_EQ(s.cameras[1].name, "side");
    EXPECT_NEAR(s.camera.vfov_deg, 0.7 * 180 / M_PI, 1e-9);
    // The orthographic camera: crex's parallel view, its height and width twice ymag and xmag.
    EXPECT_EQ(s.cameras[2].camera.projection, Projection::kParallel);
    EXPECT_NEAR(s.cameras[2].camera.vfov_deg, 2, 1e-12);
    EXPECT_NEAR(s.cameras[2].camera.hfov_deg, 2, 1e-12);
    EXPECT_EQ(select_camera(s, "side"), "");
    EXPECT_NEAR(s.camera.position.x, 5, 1e-12);
    EXPECT_NEAR(s.camera.direction.x, -1, 1e-12);  // the node's -z turned to -x
    // The point light: a small sphere of `light`, its intensity kept (radiance x pi r^2).
    const Shape* bulb = shape_named(s, "light:bulb");
    ASSERT_TRUE(bulb);
    EXPECT_EQ(bulb->type, ShapeType::kSphere);
    EXPECT_EQ(bulb->center, (Vec3{0, 2, 0}));
    const Material* m = s.find_material(bulb->material);
    ASSERT_TRUE(m);
    EXPECT_NEAR(m->color.x * M_PI * bulb->radius * bulb->radius, 10, 1e-9);
    EXPECT_NEAR(m->color.y * M_PI * bulb->radius * bulb->radius, 5, 1e-9);
    EXPECT_FALSE(m->spot);
    // The spot light: the same sphere, with a hard cone at the outer angle (crex's angle is the
    // whole cone), pointing down (the node's -z turned to -y).
    const Shape* reading = shape_named(s, "light:reading");
    ASSERT_TRUE(reading);
    const Material* spot = s.find_material(reading->material);
    ASSERT_TRUE(spot && spot->spot);
    EXPECT_NEAR(spot->spot->angle_deg, 2 * 0.5 * 180 / M_PI, 1e-9);
    EXPECT_NEAR(normalize_or_zero(spot->spot->direction).y, -1, 1e-9);
    EXPECT_NEAR(spot->color.x * M_PI * reading->radius * reading->radius, 20, 1e-9);
    // The directional light: a distant light towards the node's +z (turned to +y: the sun is
    // overhead, shining down), its illuminance kept: radiance x the disk's solid angle.
    ASSERT_EQ(s.distant_lights.size(), 1u);
    const DistantLight& sun = s.distant_lights[0];
    EXPECT_NEAR(sun.direction.y, 1, 1e-9);
    const Material* sun_light = s.find_material(sun.material);
    ASSERT_TRUE(sun_light);
    EXPECT_EQ(sun_light->type, MaterialType::kLight);
    EXPECT_NEAR(sun_light->color.x * 2 * M_PI * (1 - std::cos(sun.angle_deg * M_PI / 360)), 3, 1e-9);
    const Census c = take_census(s);
    // The bulb, the spot, the sun, the panel and the mesh whose emission is an image ("glow").
    EXPECT_EQ(c.sampled_emitters, 5u);
    EXPECT_EQ(c.unsampled_emitters, 0u);
    // Tags from a node name and from extras (inherited by nothing else here).
    ASSERT_TRUE(shape_named(s, "task2:cup")->tag);
    EXPECT_EQ(shape_named(s, "task2:cup")->tag->name, "cup");
    EXPECT_EQ(shape_named(s, "task2:cup")->tag->task, 2);
    const Shape* screen = shape_named(s, "screen");
    ASSERT_TRUE(screen && screen->tag);
    EXPECT_EQ(screen->tag->name, "tv");
    EXPECT_TRUE(screen->tag->distractor);
}

TEST(SceneGltf, WhatItCannotRenderIsALocatedWarning) {
    auto r = testing::load_path(write("room.gltf", room_gltf()));
    ASSERT_TRUE(r.scene);
    // Lines (mode 1) and the spot's soft edge: each at its own line.
    const std::string text = room_gltf();
    auto line_of = [&](const std::string& needle) {
        const size_t at = text.find(needle);
        return static_cast<size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n') + 1);
    };
    std::vector<std::string> found;
    for (const auto& d : r.diagnostics) {
        if (d.code != "W311") continue;
        ASSERT_TRUE(d.span.file);
        const LineCol at = d.span.file->position(d.span.begin);
        if (d.message.find("mode 1") != std::string::npos) {
            EXPECT_EQ(at.line, line_of("\"mode\": 1"));
            found.push_back("lines");
        }
        if (d.message.find("soft edge") != std::string::npos) {
            EXPECT_EQ(at.line, line_of("\"extensions\": {\"KHR_lights_punctual\": {\"light\": 2}}"));
            found.push_back("spot");
        }
    }
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, (std::vector<std::string>{"lines", "spot"}));
}

TEST(SceneGltf, BrokenFilesAreLocatedErrors) {
    // An accessor reaching past its buffer view: refused at the accessor.
    std::string bad = room_gltf();
    const std::string count3 = R"("componentType": 5126, "count": 3, "type": "VEC2"})";
    bad.replace(bad.find(count3), count3.size(), R"("componentType": 5126, "count": 30, "type": "VEC2"})");
    auto r = testing::load_path(write("bad_accessor.gltf", bad));
    EXPECT_FALSE(r.scene);
    const Diagnostic* d = r.find("E303");
    ASSERT_TRUE(d);
    EXPECT_NE(d->message.find("do not fit"), std::string::npos) << d->message;
    EXPECT_GT(d->span.file->position(d->span.begin).line, 1u);
    // A required extension crex cannot read.
    std::string draco = room_gltf();
    draco.replace(draco.find("\"extensionsUsed\""), 0, "\"extensionsRequired\": [\"KHR_draco_mesh_compression\"],\n  ");
    r = testing::load_path(write("draco.gltf", draco));
    EXPECT_FALSE(r.scene);
    ASSERT_TRUE(r.find("E307"));
    EXPECT_EQ(r.where("E307").line, 2u);
    // Not JSON at all: a located syntax error.
    r = testing::load_path(write("garbage.gltf", "{\"asset\": {\"version\": \"2.0\"},\n \"nodes\": [}"));
    EXPECT_FALSE(r.scene);
    ASSERT_TRUE(r.find("E301"));
    EXPECT_EQ(r.where("E301").line, 2u);
    // A node that is its own child.
    std::string cycle = room_gltf();
    cycle.replace(cycle.find("\"children\": [1]"), std::strlen("\"children\": [1]"), "\"children\": [1, 0]");
    r = testing::load_path(write("cycle.gltf", cycle));
    EXPECT_FALSE(r.scene);
    ASSERT_TRUE(r.find("E303"));
    EXPECT_NE(r.find("E303")->message.find("tree"), std::string::npos);
}

// An image whose buffer view reaches past its buffer costs the image, not the scene: the
// fuzzer found such a scene loaded with an error beside it (E303 at the view, then W310).
TEST(SceneGltf, AnImageWhoseBufferViewIsTooShortRendersMagentaAndTheSceneLoads) {
    const std::string images = R"("images": [{"uri": "wood%20grain.png"}])";
    const std::string last_view = R"({"buffer": 0, "byteOffset": 44, "byteLength": 24}])";
    std::string json = room_gltf();
    json.replace(json.find(images), images.size(), R"("images": [{"bufferView": 3, "mimeType": "image/png"}])");
    json.replace(json.find(last_view), last_view.size(),
                 R"({"buffer": 0, "byteOffset": 44, "byteLength": 24}, {"buffer": 0, "byteOffset": 60, "byteLength": 100}])");
    auto r = testing::load_path(write("broken_image.gltf", json));
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    for (const Diagnostic& d : r.diagnostics) EXPECT_NE(d.severity, Severity::kError) << d.code << ": " << d.message;
    const Diagnostic* w = r.find("W310");
    ASSERT_TRUE(w);
    EXPECT_NE(w->message.find("image 0 cannot be read (its bufferView reaches past the end of its buffer): it renders magenta"), std::string::npos)
        << w->message;
    EXPECT_EQ(r.where("W310").line, 35u);  // the image's line
    const Material* glaze = r.scene->find_material("broken_image/glaze");
    ASSERT_TRUE(glaze && glaze->textures.color);  // read as missing: magenta, not the constant
}

// Images as data URIs: tinygltf decodes only the media types it lists; the rest (seen in the
// wild: "image/jpg", parameters, no media type, percent-encoding) were kept as three bytes of
// "data" and rendered magenta.
TEST(SceneGltf, DataUriImagesCarryTheirBytesWhateverTheirMediaType) {
    const std::string images = R"("images": [{"uri": "wood%20grain.png"}])";
    const std::string png = "\x89PNG\r\n\x1a\n-not-decoded-here-";
    const std::string percent = "%89PNG%0D%0A%1A%0A-not-decoded-here-";
    for (const std::string& uri : {"data:image/png;base64," + base64(png), "data:image/jpg;base64," + base64(png),
                                  "data:image/png;charset=binary;base64," + base64(png), "data:;base64," + base64(png),
                                  "data:image/webp;base64," + base64(png), "data:image/png," + percent}) {
        std::string json = room_gltf();
        json.replace(json.find(images), images.size(), R"("images": [{"uri": ")" + uri + R"("}])");
        auto r = testing::load_path(write("inline.gltf", json));
        ASSERT_TRUE(r.scene) << uri;
        EXPECT_FALSE(r.find("W310")) << uri << ": " << r.find("W310")->message;
        ASSERT_EQ(r.scene->images.size(), 1u) << uri;
        EXPECT_EQ(r.scene->images[0].bytes, png) << uri;
    }
    // Data that is not what its URI says is a located warning, and the scene still loads.
    std::string json = room_gltf();
    json.replace(json.find(images), images.size(), R"("images": [{"uri": "data:image/jpg;base64,@@@"}])");
    auto r = testing::load_path(write("inline.gltf", json));
    ASSERT_TRUE(r.scene);
    const Diagnostic* w = r.find("W310");
    ASSERT_TRUE(w);
    EXPECT_NE(w->message.find("its data URI says base64 but the data is not base64"), std::string::npos) << w->message;
    EXPECT_EQ(r.where("W310").line, 35u);  // the image's line
}

// COLOR_0 multiplies the base colour (glTF 2.0, 3.7.2.1): it was dropped without a word.
// Normalised bytes (RGBA, alpha unused) are read as [0, 1], and the colours round-trip through
// the native format.
TEST(SceneGltf, VertexColoursAreRead) {
    std::string json = room_gltf();
    std::string b = triangle_buffer();
    b += std::string("\xff\x00\x00\xff\x00\x80\x00\xff\x00\x00\xff\x80", 12);
    auto replace = [&](const std::string& from, const std::string& to) {
        ASSERT_NE(json.find(from), std::string::npos) << from;
        json.replace(json.find(from), from.size(), to);
    };
    replace(buffers(), R"("buffers": [{"byteLength": 80, "uri": "data:application/octet-stream;base64,)" + base64(b) + R"("}])");
    replace(R"({"buffer": 0, "byteOffset": 44, "byteLength": 24}])",
            R"({"buffer": 0, "byteOffset": 44, "byteLength": 24}, {"buffer": 0, "byteOffset": 68, "byteLength": 12}])");
    replace(R"({"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"}])",
            R"({"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"},
                {"bufferView": 3, "componentType": 5121, "normalized": true, "count": 3, "type": "VEC4"}])");
    replace(R"("POSITION": 0, "TEXCOORD_0": 2})", R"("POSITION": 0, "TEXCOORD_0": 2, "COLOR_0": 3})");
    auto r = testing::load_path(write("coloured.gltf", json));
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Shape* cup = shape_named(*r.scene, "task2:cup");
    ASSERT_TRUE(cup);
    ASSERT_EQ(cup->colors.size(), 3u);
    EXPECT_EQ(cup->colors[0], (Vec3{1, 0, 0}));
    EXPECT_NEAR(cup->colors[1].y, 128.0 / 255.0, 1e-12);
    EXPECT_EQ(cup->colors[2], (Vec3{0, 0, 1}));
    EXPECT_TRUE(shape_named(*r.scene, "screen")->colors.empty());
    auto back = testing::load_json_text(scene_json_text(*r.scene));
    ASSERT_TRUE(back.scene) << (back.diagnostics.empty() ? "" : back.diagnostics[0].message);
    EXPECT_EQ(shape_named(*back.scene, "task2:cup")->colors, cup->colors);

    // Colours for fewer vertices than the mesh has (invalid glTF) are left out, with a located warning.
    replace(R"("normalized": true, "count": 3, "type": "VEC4")", R"("normalized": true, "count": 2, "type": "VEC4")");
    auto short_colors = testing::load_path(write("coloured.gltf", json));
    ASSERT_TRUE(short_colors.scene);
    EXPECT_TRUE(shape_named(*short_colors.scene, "task2:cup")->colors.empty());
    const auto said = std::count_if(short_colors.diagnostics.begin(), short_colors.diagnostics.end(), [](const Diagnostic& d) {
        return d.code == "W311" && d.message == "mesh 'cup' primitive 0: COLOR_0 has 2 elements for 3 vertices: it is not used";
    });
    EXPECT_EQ(said, 1);
}

TEST(SceneGltf, BinaryFilesCarryTheirImages) {
    // A .glb whose base colour image is a buffer view: the image travels with the scene.
    std::string json = room_gltf();
    const std::string png = "\x89PNG\r\n\x1a\n-not-decoded-here-";
    std::string bin = triangle_buffer();
    const size_t image_at = bin.size();
    bin += png;
    while (bin.size() % 4) bin += '\0';
    json.replace(json.find(R"("images": [{"uri": "wood%20grain.png"}])"), std::strlen(R"("images": [{"uri": "wood%20grain.png"}])"),
                 R"("images": [{"bufferView": 3, "mimeType": "image/png"}])");
    json.replace(json.find(R"({"buffer": 0, "byteOffset": 44, "byteLength": 24}])"),
                 std::strlen(R"({"buffer": 0, "byteOffset": 44, "byteLength": 24}])"),
                 R"({"buffer": 0, "byteOffset": 44, "byteLength": 24}, {"buffer": 0, "byteOffset": )" + std::to_string(image_at) +
                     R"(, "byteLength": )" + std::to_string(png.size()) + "}]");
    json.replace(json.find(buffers()), buffers().size(), R"("buffers": [{"byteLength": )" + std::to_string(bin.size()) + "}]");
    while (json.size() % 4) json += ' ';
    std::string glb = "glTF";
    auto u32 = [&](uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
    u32(2), u32(static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
    u32(static_cast<uint32_t>(json.size())), glb += "JSON", glb += json;
    u32(static_cast<uint32_t>(bin.size())), glb += std::string("BIN\0", 4), glb += bin;
    auto r = testing::load_path(write("room.glb", glb));
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    ASSERT_EQ(r.scene->images.size(), 1u);
    EXPECT_EQ(r.scene->images[0].bytes, png);
    const Material* glaze = r.scene->find_material("room/glaze");
    ASSERT_TRUE(glaze && glaze->textures.color);
    EXPECT_EQ(glaze->textures.color->image, r.scene->images[0].name);
    // It round-trips through the native format, image bytes and all.
    auto back = testing::load_json_text(scene_json_text(*r.scene));
    ASSERT_TRUE(back.scene) << (back.diagnostics.empty() ? "" : back.diagnostics[0].message);
    EXPECT_EQ(back.scene->images[0].bytes, png);
}

}  // namespace
}  // namespace crex
