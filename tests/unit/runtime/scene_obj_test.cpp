// OBJ + MTL through tinyobjloader: materials map onto ours, one mesh per material.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "runtime/scene/census.h"
#include "runtime/scene/shapes.h"
#include "tests/support/scene_helpers.h"

namespace crex {
namespace {

class SceneObj : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = std::filesystem::temp_directory_path() / ("crex_obj_test_" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir_);
        std::ofstream(dir_ / "m.mtl") << "newmtl wall\nKd 0.6 0.5 0.4\n"
                                         "newmtl lamp\nKd 0 0 0\nKe 5 5 4\n"
                                         "newmtl shiny\nKd 0.2 0.2 0.2\nKs 0.6 0.6 0.6\nNs 200\n"
                                         "newmtl pane\nKd 1 1 1\nd 0.2\nNi 1.4\n";
        std::ofstream(dir_ / "m.obj") << "mtllib m.mtl\n"
                                         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
                                         "usemtl wall\nf 1 2 3 4\n"
                                         "usemtl lamp\nf 1 2 5\n"
                                         "usemtl shiny\nf 2 3 5\n"
                                         "usemtl pane\nf 3 4 5\n";
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }
    std::filesystem::path dir_;
};

TEST_F(SceneObj, MapsMaterialsAndSplitsMeshesByMaterial) {
    auto r = testing::load_path((dir_ / "m.obj").string());
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Scene& s = *r.scene;
    ASSERT_EQ(s.shapes.size(), 4u);
    size_t triangles = 0;
    for (const auto& sh : s.shapes) triangles += triangle_count(sh);
    EXPECT_EQ(triangles, 5u);  // the quad is triangulated
    EXPECT_EQ(s.find_material("m/wall")->type, MaterialType::kPlastic);
    EXPECT_EQ(s.find_material("m/lamp")->type, MaterialType::kLight);
    EXPECT_EQ(s.find_material("m/lamp")->color, (Vec3{5, 5, 4}));
    const Material* shiny = s.find_material("m/shiny");
    EXPECT_NEAR(shiny->specularity, 0.75, 1e-6);
    EXPECT_NEAR(shiny->roughness, std::sqrt(2.0 / 202.0), 1e-6);
    EXPECT_EQ(s.find_material("m/pane")->type, MaterialType::kGlass);
    EXPECT_NEAR(s.find_material("m/pane")->ior, 1.4, 1e-6);
    EXPECT_EQ(component_set_letters(take_census(s).spawnable), "D G T R");
}

TEST_F(SceneObj, JsonSceneCanReferenceAnObjWithAMaterialOverride) {
    std::ofstream(dir_ / "s.json") << R"({"materials": [{"name": "chrome", "type": "mirror"}, {"name": "l", "type": "light", "color": [1,1,1]}],
      "shapes": [{"type": "mesh", "file": "m.obj", "material": "chrome"},
                 {"type": "sphere", "material": "l", "center": [0, 5, 0], "radius": 1}]})";
    auto r = testing::load_path((dir_ / "s.json").string());
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    for (size_t i = 0; i + 1 < r.scene->shapes.size(); ++i) EXPECT_EQ(r.scene->shapes[i].material, "chrome");
    EXPECT_EQ(component_set_letters(take_census(*r.scene).spawnable), "M");
}

TEST_F(SceneObj, MissingObjIsALocatedError) {
    std::ofstream(dir_ / "s.json") << "{\"shapes\": [\n  {\"type\": \"mesh\", \"file\": \"nope.obj\"}]}";
    auto r = testing::load_path((dir_ / "s.json").string());
    EXPECT_FALSE(r.scene);
    ASSERT_NE(r.find("E308"), nullptr);
    bool located = false;
    for (const auto& d : r.diagnostics)
        if (d.code == "E308" && d.span.file->name().find("s.json") != std::string::npos)
            located = d.span.file->position(d.span.begin).line == 2;
    EXPECT_TRUE(located);
}

TEST_F(SceneObj, NonFiniteVertexNeverReachesTheScene) {
    std::ofstream(dir_ / "bad.obj") << "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n";
    auto r = testing::load_path((dir_ / "bad.obj").string());
    // tinyobjloader reads "nan" as a finite number; whatever it makes of it, a NaN never
    // reaches the scene, and if one is seen it is rejected at its line.
    if (r.scene) {
        for (const auto& sh : r.scene->shapes)
            for (const auto& v : sh.vertices) EXPECT_TRUE(is_finite(v));
    } else {
        EXPECT_EQ(r.where("E303").line, 3u);
    }
}

}  // namespace
}  // namespace crex
