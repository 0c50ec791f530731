// Texture references in the native scene format: where a colour or a number goes, an object
// may go; every field is read, checked and located; a scene with textures, named cameras,
// units and embedded images round-trips; the census treats a textured parameter as possibly
// non-zero and a textured roughness as glossy.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "base/base64.h"
#include "runtime/scene/census.h"
#include "tests/support/scene_helpers.h"
#include "tests/support/scratch_folder.h"

namespace crex {
namespace {

std::string scene_with(const std::string& material, const std::string& extra_top = "") {
    return std::string(R"({"format": "crex-scene", )") + extra_top + R"(
      "materials": [)" + material + R"(, {"name": "lamp", "type": "light", "color": [1, 1, 1]}],
      "shapes": [{"type": "mesh", "material": "m", "vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,2]],
                  "uvs": [[0,0],[1,0],[0,1]], "normals": [[0,0,1],[0,0,1],[0,0,1]]},
                 {"type": "sphere", "material": "lamp", "center": [0,0,3], "radius": 0.1}]})";
}

TEST(SceneTextureJson, EveryFieldIsRead) {
    auto r = testing::load_json_text(scene_with(R"({"name": "m", "type": "plastic", "specularity": 0.04,
      "color": {"file": "wood.png", "color_space": "srgb", "wrap": ["clamp", "mirror"], "filter": "nearest", "scale": [0.5, 0.6, 0.7],
                "uv_transform": {"offset": [0.25, 0.5], "rotation": 0, "scale": [2, 4]}},
      "roughness": {"file": "mr.png", "channel": 1, "power": 2, "scale": 0.9},
      "metallic": {"file": "mr.png", "channel": 2, "color_space": "linear"},
      "opacity": {"file": "leaf.png", "channel": 3}, "alpha_mode": "blend", "alpha_cutoff": 0.3,
      "normal_map": {"file": "n.png", "scale": 0.5}, "bump_map": {"file": "h.png", "scale": 0.01},
      "specular_color": {"file": "s.png"},
      "emission": {"file": "screen.png", "mapping": "planar", "planar": [1, 0, 0, 0.5, 0, 0, 1, 0.5]}})"));
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Material& m = r.scene->materials[0];
    const MaterialTextures& t = m.textures;
    ASSERT_TRUE(t.color && t.roughness && t.metallic && t.opacity && t.normal && t.bump && t.specular_color && t.emission);
    // Relative paths resolve against the scene file's folder and come back absolute.
    EXPECT_TRUE(std::filesystem::path(t.color->file).is_absolute());
    EXPECT_EQ(std::filesystem::path(t.color->file).filename(), "wood.png");
    EXPECT_EQ(t.color->color_space, TextureColorSpace::kSrgb);
    EXPECT_EQ(t.color->wrap_s, TextureWrap::kClamp);
    EXPECT_EQ(t.color->wrap_t, TextureWrap::kMirror);
    EXPECT_EQ(t.color->filter, TextureFilter::kNearest);
    EXPECT_EQ(t.roughness->filter, TextureFilter::kSmooth);
    EXPECT_EQ(t.color->scale, (Vec3{0.5, 0.6, 0.7}));
    EXPECT_EQ(t.color->uv_transform, (UvTransform{2, 0, 0.25, 0, 4, 0.5}));
    EXPECT_EQ(t.roughness->channel, 1);
    EXPECT_DOUBLE_EQ(t.roughness->power, 2);
    EXPECT_EQ(t.roughness->scale, (Vec3{0.9, 0.9, 0.9}));
    EXPECT_EQ(t.metallic->color_space, TextureColorSpace::kLinear);
    EXPECT_EQ(m.alpha_mode, AlphaMode::kBlend);
    EXPECT_DOUBLE_EQ(m.alpha_cutoff, 0.3);
    EXPECT_EQ(t.emission->mapping, TextureMapping::kPlanar);
    EXPECT_DOUBLE_EQ(t.emission->planar[3], 0.5);
    ASSERT_EQ(r.scene->shapes[0].uvs.size(), 3u);
    ASSERT_EQ(r.scene->shapes[0].normals.size(), 3u);
    // Every missing file is a warning at its reference (they render magenta), not an error.
    EXPECT_EQ(r.errors, 0u);
    size_t missing = 0;
    for (const auto& d : r.diagnostics) missing += d.code == "W310";
    EXPECT_EQ(missing, 8u);
}

TEST(SceneTextureJson, UvTransformFollowsKhrTextureTransform) {
    // Scale, then rotate, then offset: (1, 0) scaled by 2 is (2, 0); turned a quarter as the
    // extension's test model turns it ((u, v) to (c u + s v, c v - s u)), (0, -2); offset by
    // (0.5, 0), (0.5, -2).
    const UvTransform m = uv_transform_of(0.5, 0, std::acos(-1.0) / 2, 2, 3);
    EXPECT_NEAR(m[0] * 1 + m[1] * 0 + m[2], 0.5, 1e-12);
    EXPECT_NEAR(m[3] * 1 + m[4] * 0 + m[5], -2, 1e-12);
}

TEST(SceneTextureJson, BadReferencesAreLocatedErrors) {
    struct Case {
        const char* name;
        std::string material;
        const char* code;
        size_t line;
    };
    const Case cases[] = {
        {"neither file nor image", R"({"name": "m", "type": "plastic",
 "color": {"wrap": "clamp"}})", "E304", 2},
        {"unknown wrap", R"({"name": "m", "type": "plastic",
 "color": {"file": "a.png", "wrap": "spiral"}})", "E303", 2},
        {"unknown filter", R"({"name": "m", "type": "plastic",
 "color": {"file": "a.png", "filter": "blurry"}})", "E303", 2},
        {"unknown colour space", R"({"name": "m", "type": "plastic",
 "color": {"file": "a.png", "color_space": "acescg"}})", "E303", 2},
        {"channel out of range", R"({"name": "m", "type": "plastic",
 "roughness": {"file": "a.png", "channel": 99}})", "E303", 2},
        {"normal map must be a texture", R"({"name": "m", "type": "plastic",
 "normal_map": [0, 0, 1]})", "E302", 2},
        {"unknown image", R"({"name": "m", "type": "plastic",
 "color": {"image": "nowhere"}})", "E305", 2},
        {"texture on an emitter", R"({"name": "m",
 "type": "glow", "color": {"file": "a.png"}})", "E307", 2},
        {"bad alpha mode", R"({"name": "m", "type": "plastic",
 "alpha_mode": "dither"})", "E303", 2},
    };
    for (const Case& c : cases) {
        auto r = testing::load_json_text(scene_with(c.material));
        EXPECT_FALSE(r.scene) << c.name;
        testing::expect_diagnostic(r, c.name, c.code, c.line + 1, 0, "");
    }
    // Per-vertex attributes must match the vertices.
    auto r = testing::load_json_text(R"({"materials": [{"name": "m", "type": "plastic"}],
      "shapes": [{"type": "mesh", "material": "m", "vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,2]],
                  "uvs": [[0,0],[1,0]]}]})");
    EXPECT_FALSE(r.scene);
    testing::expect_diagnostic(r, "two uvs for three vertices", "E303", 3, 0, "2 texture coordinates for 3 vertices");
}

TEST(SceneTextureJson, TexturesCamerasUnitsAndImagesRoundTrip) {
    const std::string png = base64("\x89PNG not really");
    auto a = testing::load_json_text(scene_with(R"({"name": "m", "type": "plastic", "metallic": 0.5, "opacity": 0.7,
      "color": {"image": "poster", "uv_transform": {"matrix": [1, 0, 0, 0, -1, 1]}},
      "roughness": {"file": "/tmp/r.png", "power": 2, "wrap": "black", "filter": "nearest"}})",
                                            R"("images": [{"name": "poster", "mime_type": "image/png", "data": ")" + png + R"("}],
      "cameras": [{"name": "door", "position": [0,0,5], "look_at": [0,0,0]}, {"name": "desk", "position": [3,0,5], "look_at": [0,0,0]}],
      "units": {"metres_per_unit": 0.01, "up": [0, 0, 1]},)"));
    ASSERT_TRUE(a.scene) << (a.diagnostics.empty() ? "" : a.diagnostics[0].message);
    ASSERT_EQ(a.scene->images.size(), 1u);
    EXPECT_EQ(a.scene->images[0].bytes, "\x89PNG not really");
    ASSERT_EQ(a.scene->cameras.size(), 2u);
    EXPECT_EQ(a.scene->camera.position, (Vec3{0, 0, 5}));  // the first named camera, without "camera"
    EXPECT_DOUBLE_EQ(a.scene->units.metres_per_unit, 0.01);
    auto b = testing::load_json_text(scene_json_text(*a.scene));
    ASSERT_TRUE(b.scene) << (b.diagnostics.empty() ? "" : b.diagnostics[0].message);
    EXPECT_EQ(scene_to_json(*b.scene), scene_to_json(*a.scene));
    EXPECT_EQ(b.scene->materials[0].textures, a.scene->materials[0].textures);
    EXPECT_EQ(b.scene->shapes[0].uvs, a.scene->shapes[0].uvs);
}

// A scene's identity (what its hash and a reference's key are made of) names each texture file
// by its bytes: the same scene in two folders is the same, an edited image is not. Committed
// references of the textured living room failed in every other checkout when paths counted.
TEST(SceneTextureJson, IdentityNamesTextureFilesByTheirBytesNotTheirPaths) {
    namespace fs = std::filesystem;
    const fs::path root = testing::scratch_folder("crex_scene_identity_");
    auto scene_in = [&](const std::string& folder, const std::string& bytes) {
        fs::create_directories(root / folder);
        std::ofstream((root / folder / "wood.png").string(), std::ios::binary) << bytes;
        auto r = testing::load_json_text(scene_with(R"({"name": "m", "type": "plastic", "color": {"file": ")" +
                                                    (root / folder / "wood.png").string() + R"("}})"));
        EXPECT_TRUE(r.scene);
        return r.scene ? scene_identity_text(*r.scene) : std::string();
    };
    const std::string a = scene_in("a", "grain"), b = scene_in("b", "grain"), edited = scene_in("c", "grain, sanded");
    EXPECT_EQ(a, b);
    EXPECT_NE(a, edited);
    EXPECT_EQ(a.find(root.string()), std::string::npos) << "a path is part of the identity";
    EXPECT_NE(a.find("wood.png"), std::string::npos);
    // A file that cannot be read keeps its path: the scene is still told apart from others.
    auto missing = testing::load_json_text(scene_with(R"({"name": "m", "type": "plastic", "color": {"file": "/nonexistent/crex/wood.png"}})"));
    ASSERT_TRUE(missing.scene);
    EXPECT_NE(scene_identity_text(*missing.scene).find("/nonexistent/crex/wood.png"), std::string::npos);
    fs::remove_all(root);
}

TEST(SceneTextureJson, CameraIsChosenByNameOrIndex) {
    auto r = testing::load_json_text(scene_with(R"({"name": "m", "type": "plastic"})",
                                                R"("cameras": [{"name": "door", "position": [0,0,5], "look_at": [0,0,0]},
                                                               {"name": "desk", "position": [3,0,5], "look_at": [0,0,0]}],)"));
    ASSERT_TRUE(r.scene);
    Scene s = *r.scene;
    EXPECT_EQ(select_camera(s, "desk"), "");
    EXPECT_EQ(s.camera.position, (Vec3{3, 0, 5}));
    EXPECT_EQ(select_camera(s, "0"), "");
    EXPECT_EQ(s.camera.position, (Vec3{0, 0, 5}));
    const std::string error = select_camera(s, "attic");
    EXPECT_NE(error.find("0 'door', 1 'desk'"), std::string::npos) << error;
    EXPECT_NE(select_camera(s, "2"), "");
}

TEST(SceneTextureJson, CensusCountsTexturesAsPossiblyNonZero) {
    // A black colour with a colour texture is still diffuse; a textured roughness is glossy
    // even where the constant says ideal specular; a textured metallic may be fully metal.
    auto r = testing::load_json_text(scene_with(R"({"name": "m", "type": "plastic", "color": {"file": "black.png"},
      "specularity": 0.04, "roughness": {"file": "r.png"}})"));
    ASSERT_TRUE(r.scene);
    const ComponentSet s = spawned_components(r.scene->materials[0]);
    EXPECT_TRUE(s.test(static_cast<size_t>(Component::kD)));
    EXPECT_TRUE(s.test(static_cast<size_t>(Component::kG)));
    EXPECT_FALSE(s.test(static_cast<size_t>(Component::kS)));
    Material metal = r.scene->materials[0];
    metal.textures = {};
    metal.metallic = 1;
    metal.specularity = 0;
    metal.roughness = 0;
    // A conductor of its colour: no D at all, its specular lobe is the colour (S when smooth).
    const ComponentSet ms = spawned_components(metal);
    EXPECT_FALSE(ms.test(static_cast<size_t>(Component::kD)));
    EXPECT_TRUE(ms.test(static_cast<size_t>(Component::kS)));
    // An emission texture makes a material emissive (the census counts it).
    Material screen = r.scene->materials[0];
    TextureRef screen_texture;
    screen_texture.file = "screen.png";
    screen.textures.emission = screen_texture;
    EXPECT_TRUE(is_emissive(screen));
}

TEST(SceneTextureJson, Base64RoundTripsAndRejectsGarbage) {
    for (const std::string& bytes : {std::string(""), std::string("a"), std::string("ab"), std::string("abc"), std::string("\0\xff\x10 z", 5)})
        EXPECT_EQ(base64_decode(base64(bytes)), bytes);
    EXPECT_FALSE(base64_decode("ab$c"));
    EXPECT_FALSE(base64_decode("YQ==YQ"));
}

}  // namespace
}  // namespace crex
