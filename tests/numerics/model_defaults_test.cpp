// What a model file gets where it says nothing (runtime/scene/model_defaults.h).
// A camera: one that frames it, which sees no flat model edge-on.
// Light: an OBJ or glTF model rendered on its own with nothing that lights it (OBJ has no lights,
// most glTF models ship without any) used to render black with W302. It is lit as a model
// viewer lights a model, by a grey environment and a key light, and W313 says so; a model with a
// light of its own, or an OBJ named from a JSON scene, is left as its file says.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "runtime/api/run_inputs.h"
#include "runtime/scene/model_defaults.h"
#include "tests/support/scene_helpers.h"
#include "tests/support/scratch_folder.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

class ModelDefaults : public testing::ScratchFolderTest {
protected:
    ModelDefaults() : ScratchFolderTest("crex_model_defaults_") {}

    static long count(const testing::SceneResult& r, const std::string& code) {
        return std::count_if(r.diagnostics.begin(), r.diagnostics.end(), [&](const Diagnostic& d) { return d.code == code; });
    }
};

// A plane of albedo 0.5 facing the camera: the environment (radiance 0.5, which every ray
// leaving the plane sees, carrying the albedo as its weight exactly) and the key light, a 5
// degree sun in the direction (0.4, 0.8, 0.6) of the camera's right, up and back, of
// irradiance pi x 0.9 at normal incidence, so pi x 0.9 x 0.6 / |(0.4, 0.8, 0.6)| here (less a
// factor (1 + cos 2.5 deg) / 2 for the disc). Per pixel the sun's sample direction varies
// within its disc: the mean of 12x12 central pixels at 4 spp is within 0.002 of the value,
// each pixel within 0.02 (0.9 x 0.5 x sin 2.5 deg).
TEST_F(ModelDefaults, AnUnlitObjIsLitByTheStudioAndShowsItsAlbedo) {
    std::ofstream(path("plane.mtl")) << "newmtl grey\nKd 0.5 0.5 0.5\nKs 0 0 0\n";
    std::ofstream(path("plane.obj")) << "mtllib plane.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nusemtl grey\nf 1 2 3 4\n";
    auto r = testing::load_path(path("plane.obj"));
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    EXPECT_EQ(count(r, "W302"), 0);
    ASSERT_EQ(count(r, "W313"), 1);
    EXPECT_EQ(r.where("W313").line, 1u);
    EXPECT_EQ(r.scene->background, (Vec3{0.5, 0.5, 0.5}));
    ASSERT_EQ(r.scene->distant_lights.size(), 1u);
    EXPECT_EQ(sampled_light_count(*r.scene), 1u);

    const int n = 32;
    const std::vector<float> img = testing::render_crex(*r.scene, "D", n, 4).image();
    ASSERT_TRUE(testing::all_finite(img));
    const double cos_key = 0.6 / std::sqrt(0.4 * 0.4 + 0.8 * 0.8 + 0.6 * 0.6);
    const double expected = 0.5 * (0.5 + 0.9 * cos_key * (1 + std::cos(2.5 * kPi / 180)) / 2);
    double sum = 0;
    for (int y = 10; y < 22; ++y)
        for (int x = 10; x < 22; ++x) {
            const double v = img[3 * size_t(y * n + x) + 1];
            ASSERT_NEAR(v, expected, 0.02) << x << ", " << y;
            sum += v;
        }
    EXPECT_NEAR(sum / 144, expected, 0.002);
    // The corners of the image, past the plane, see the environment itself.
    EXPECT_NEAR(img[1], 0.5, 1e-6);
}

TEST_F(ModelDefaults, AModelWithALightOfItsOwnIsLeftAsItIs) {
    std::ofstream(path("lamp.mtl")) << "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl lamp\nKe 4 4 4\n";
    std::ofstream(path("lamp.obj")) << "mtllib lamp.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv 0 0 1\n"
                                       "usemtl grey\nf 1 2 3 4\nusemtl lamp\nf 1 2 5\n";
    auto r = testing::load_path(path("lamp.obj"));
    ASSERT_TRUE(r.scene);
    EXPECT_EQ(count(r, "W313"), 0);
    EXPECT_EQ(r.scene->background, Vec3{});
}

// glTF too: a quad without lights or emissive materials (its data in a data URI).
TEST_F(ModelDefaults, AnUnlitGltfIsLitByTheStudioToo) {
    std::ofstream(path("quad.gltf")) << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
      "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0}}],
      "buffers": [{"byteLength": 60, "uri": "data:application/octet-stream;base64,AACAvwAAgL8AAAAAAACAPwAAgL8AAAAAAACAPwAAgD8AAAAAAACAvwAAgD8AAAAAAAABAAIAAAACAAMA"}],
      "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
                    {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}]})";
    auto r = testing::load_path(path("quad.gltf"));
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    EXPECT_EQ(count(r, "W302"), 0);
    EXPECT_EQ(count(r, "W313"), 1);
    EXPECT_EQ(sampled_light_count(*r.scene), 1u);
}

// A panel in the yz plane was framed from +z, edge-on, and rendered as background alone; a
// picture facing z is still framed straight from +z, filling the middle of the image.
TEST_F(ModelDefaults, TheFramingCameraSeesAFlatModelFaceOn) {
    std::ofstream(path("side.obj")) << "v 0 -1 -1\nv 0 -1 1\nv 0 1 1\nv 0 1 -1\nf 1 2 3 4\n";
    auto r = testing::load_path(path("side.obj"));
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Vec3 d = normalize_or_zero(r.scene->camera.direction);
    EXPECT_GT(std::fabs(d.x), 0.4) << "the panel's normal is x";
    const int n = 32;
    const std::vector<float> img = testing::render_crex(*r.scene, "D", n, 1).image();
    int panel = 0;
    for (size_t i = 1; i < img.size(); i += 3) panel += std::fabs(img[i] - 0.5) > 1e-3;  // not the environment
    EXPECT_GT(panel, n * n / 10);

    std::ofstream(path("card.obj")) << "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n";
    r = testing::load_path(path("card.obj"));
    ASSERT_TRUE(r.scene);
    EXPECT_EQ(normalize_or_zero(r.scene->camera.direction), (Vec3{0, 0, -1}));
    EXPECT_EQ(r.scene->camera.position.x, 0);
    EXPECT_EQ(r.scene->camera.position.y, 0);
}

// The key light is placed from the camera: a view given after loading (crex run --view) moves
// it with the camera, so a model seen from behind is lit from behind the new camera, not from
// behind the file's (which lit the side the camera no longer sees).
TEST_F(ModelDefaults, TheKeyLightFollowsAViewGivenAfterLoading) {
    std::ofstream(path("box.obj")) << "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nf 1 2 3 4\n";
    std::ofstream(path("behind.vf")) << "rview -vtv -vp 0.3 0.2 -5 -vd 0 0 1 -vu 0 1 0 -vh 40 -vv 40\n";
    auto key_direction = [&](const std::string& view) {
        InputSpec spec;
        spec.scene = path("box.obj");
        spec.view = view;
        DiagnosticSink sink;
        RunInputs in = load_run_inputs(spec, sink);
        EXPECT_TRUE(in.failure.empty()) << in.failure;
        EXPECT_TRUE(in.scene && in.scene->scene);
        if (!in.scene || !in.scene->scene) return std::pair<Vec3, Camera>{};
        const Scene& scene = *in.scene->scene;
        EXPECT_EQ(scene.distant_lights.size(), 1u);
        return std::pair<Vec3, Camera>{normalize_or_zero(scene.distant_lights.at(0).direction), scene.camera};
    };
    for (const std::string& view : {std::string(), path("behind.vf")}) {
        const auto [key, camera] = key_direction(view);
        const Vec3 forward = normalize_or_zero(camera.direction), right = normalize_or_zero(cross(forward, camera.up));
        // Behind the camera, above it: (0.4, 0.8, 0.6) in its right, up and back.
        EXPECT_NEAR(dot(key, forward), -0.6 / std::sqrt(1.16), 1e-9) << view;
        EXPECT_NEAR(dot(key, cross(right, forward)), 0.8 / std::sqrt(1.16), 1e-9) << view;
        EXPECT_NEAR(dot(key, right), 0.4 / std::sqrt(1.16), 1e-9) << view;
    }
    // From behind, the key now points to -z, the side the view sees.
    EXPECT_LT(key_direction(path("behind.vf")).first.z, 0);
    EXPECT_GT(key_direction("").first.z, 0);
}

}  // namespace
}  // namespace crex
