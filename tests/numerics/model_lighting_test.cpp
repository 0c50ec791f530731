// An OBJ or glTF model rendered on its own with nothing that lights it (OBJ has no lights,
// most glTF models ship without any) used to render black with W302. It is lit by a uniform
// white environment of radiance 1, as a model viewer lights a model, and W313 says so; a model with a
// light of its own, or an OBJ named from a JSON scene, is left as its file says.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "tests/support/scene_helpers.h"
#include "tests/support/scratch_folder.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

class ModelLighting : public testing::ScratchFolderTest {
protected:
    ModelLighting() : ScratchFolderTest("crex_model_lighting_") {}

    static long count(const testing::SceneResult& r, const std::string& code) {
        return std::count_if(r.diagnostics.begin(), r.diagnostics.end(), [&](const Diagnostic& d) { return d.code == code; });
    }
};

// A plane of albedo 0.5 facing the camera in the white environment: every ray leaving it sees
// radiance 1 and carries the albedo as its weight, so every pixel is 0.5 exactly at 1 spp (as
// under a sampled sky it was only on average: pixels' standard deviation 0.04 at 16 spp).
TEST_F(ModelLighting, AnUnlitObjIsLitByAWhiteEnvironmentAndShowsItsAlbedo) {
    std::ofstream(path("plane.mtl")) << "newmtl grey\nKd 0.5 0.5 0.5\nKs 0 0 0\n";
    std::ofstream(path("plane.obj")) << "mtllib plane.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nusemtl grey\nf 1 2 3 4\n";
    auto r = testing::load_path(path("plane.obj"));
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    EXPECT_EQ(count(r, "W302"), 0);
    ASSERT_EQ(count(r, "W313"), 1);
    EXPECT_EQ(r.where("W313").line, 1u);
    EXPECT_EQ(r.scene->background, (Vec3{1, 1, 1}));

    const int n = 32;
    const std::vector<float> img = testing::render_crex(*r.scene, "D", n, 1).image();
    ASSERT_TRUE(testing::all_finite(img));
    for (int y = 10; y < 22; ++y)
        for (int x = 10; x < 22; ++x) ASSERT_NEAR(img[3 * size_t(y * n + x) + 1], 0.5, 1e-5) << x << ", " << y;
    // The corners of the image, past the plane, see the environment itself.
    EXPECT_NEAR(img[1], 1.0, 1e-6);
}

TEST_F(ModelLighting, AModelWithALightOfItsOwnIsLeftAsItIs) {
    std::ofstream(path("lamp.mtl")) << "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl lamp\nKe 4 4 4\n";
    std::ofstream(path("lamp.obj")) << "mtllib lamp.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv 0 0 1\n"
                                       "usemtl grey\nf 1 2 3 4\nusemtl lamp\nf 1 2 5\n";
    auto r = testing::load_path(path("lamp.obj"));
    ASSERT_TRUE(r.scene);
    EXPECT_EQ(count(r, "W313"), 0);
    EXPECT_EQ(r.scene->background, Vec3{});
}

// glTF too: a quad without lights or emissive materials (its data in a data URI).
TEST_F(ModelLighting, AnUnlitGltfIsLitByTheEnvironmentToo) {
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
    EXPECT_EQ(r.scene->background, (Vec3{1, 1, 1}));
}

}  // namespace
}  // namespace crex
