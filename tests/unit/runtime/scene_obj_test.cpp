// OBJ + MTL through tinyobjloader: materials map onto ours, one mesh per material.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>
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

// What the scene's checks find in a mesh (W303: zero-area triangles dropped) is located at
// the `o` or `g` line that names it; it was line 1, column 1 of the file for every mesh.
TEST_F(SceneObj, AMeshesWarningIsLocatedAtTheLineNamingIt) {
    std::ofstream(dir_ / "named.obj") << "# two objects\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 2 0 0\n"
                                         "o floor\nf 1 2 3\ng  sliver \nf 1 2 4\nf 1 2 3\n";
    auto r = testing::load_path((dir_ / "named.obj").string());
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const LineCol at = r.where("W303");
    EXPECT_EQ(at.line, 8u);
    EXPECT_EQ(at.col, 1u);
}

// Material names with blanks (LightWave and 3ds Max write them; assimp's
// space_in_material_name.obj): tinyobjloader's usemtl read only the first word, so the faces
// fell back to the default material. A material that is not defined, and an MTL file that is
// not there, are warned at the usemtl and mtllib lines naming them (they were at line 1).
TEST_F(SceneObj, MaterialNamesWithBlanksAreFoundAndMissingOnesLocated) {
    std::ofstream(dir_ / "spaced.mtl") << "newmtl Hard Shiny Plastic White\nKd 0.9 0.8 0.7\nnewmtl  lead  \nKd 0.1 0.2 0.3\n";
    std::ofstream(dir_ / "spaced.obj") << "mtllib spaced.mtl\nmtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\n"
                                          "usemtl  Hard Shiny Plastic White \nf 1 2 3\nusemtl lead\nf 1 3 2\nusemtl Nowhere\nf 1 2 3\n";
    auto r = testing::load_path((dir_ / "spaced.obj").string());
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    std::set<std::string> used;
    for (const Shape& sh : r.scene->shapes) used.insert(sh.material);
    EXPECT_EQ(used, (std::set<std::string>{"spaced/Hard Shiny Plastic White", "spaced/lead", "spaced/default"}));
    const Material* white = r.scene->find_material("spaced/Hard Shiny Plastic White");
    ASSERT_TRUE(white);
    EXPECT_NEAR(white->color.y, 0.8, 1e-6);
    int missing_material = 0, missing_file = 0;
    for (const Diagnostic& d : r.diagnostics) {
        if (d.code != "W301") continue;
        const LineCol at = d.span.file->position(d.span.begin);
        if (d.message.find("'Nowhere'") != std::string::npos) {
            ++missing_material;
            EXPECT_EQ(at.line, 10u) << d.message;
        }
        if (d.message.find("gone.mtl") != std::string::npos) {
            ++missing_file;
            EXPECT_EQ(at.line, 2u) << d.message;
        }
    }
    EXPECT_EQ(missing_material, 1);
    EXPECT_EQ(missing_file, 1);
}

// `mtllib my\ mats.mtl` names one file with a blank in its name (tinyobjloader's escape): read
// as tinyobjloader reads it, and its values checked like every MTL's.
TEST_F(SceneObj, AnMtlNamedWithAnEscapedBlankIsReadAndChecked) {
    std::ofstream(dir_ / "my mats.mtl") << "newmtl red\nKd 0.8 0.1 0.1\n";
    std::ofstream(dir_ / "esc.obj") << "mtllib my\\ mats.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nusemtl red\nf 1 2 3\n";
    auto r = testing::load_path((dir_ / "esc.obj").string());
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    ASSERT_EQ(r.scene->shapes.size(), 1u);
    EXPECT_EQ(r.scene->shapes[0].material, "esc/red");
    std::ofstream(dir_ / "my mats.mtl") << "newmtl red\nKd 0.8 0.1 0.1\nKe -1 0 0\n";
    r = testing::load_path((dir_ / "esc.obj").string());
    EXPECT_FALSE(r.scene);
    EXPECT_EQ(r.where("E303").line, 3u);
}

// A UTF-16 OBJ (assimp's box_UTF16BE.obj) read as no triangles (E306): it says what it is.
TEST_F(SceneObj, AUtf16ObjSaysSo) {
    for (const std::string& bom : {std::string("\xFE\xFF", 2), std::string("\xFF\xFE", 2)}) {
        std::string text = bom;
        for (char c : std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")) text += bom[0] == '\xFE' ? std::string{'\0', c} : std::string{c, '\0'};
        std::ofstream(dir_ / "utf16.obj", std::ios::binary) << text;
        auto r = testing::load_path((dir_ / "utf16.obj").string());
        EXPECT_FALSE(r.scene);
        ASSERT_FALSE(r.diagnostics.empty());
        EXPECT_EQ(r.diagnostics[0].code, "E308");
        EXPECT_NE(r.diagnostics[0].message.find("UTF-16"), std::string::npos) << r.diagnostics[0].message;
    }
}

// `Ni 0` on an opaque material (exporters write it; assimp's regr_3429812.mtl has it) refused
// the whole file with E303. It means nothing there; on glass it refracts as 1.5, warned at the
// material's newmtl line.
TEST_F(SceneObj, NiZeroLoadsAndOnGlassIsWarnedAtItsMaterial) {
    std::ofstream(dir_ / "ni.mtl") << "newmtl trim\nd 1\nNi 0\nKd 1 1 1\n\nnewmtl pane \nKd 1 1 1\nd 0.3\nNi 0\n";
    std::ofstream(dir_ / "ni.obj") << "mtllib ni.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nusemtl trim\nf 1 2 3\nusemtl pane\nf 1 3 2\n";
    auto r = testing::load_path((dir_ / "ni.obj").string());
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    EXPECT_EQ(r.errors, 0u);
    const Material* pane = r.scene->find_material("ni/pane");
    ASSERT_TRUE(pane);
    EXPECT_EQ(pane->type, MaterialType::kGlass);
    EXPECT_EQ(pane->ior, 1.5);
    EXPECT_EQ(r.where("W311").line, 6u);
    EXPECT_EQ(std::count_if(r.diagnostics.begin(), r.diagnostics.end(), [](const Diagnostic& d) { return d.code == "W311"; }), 1);
}

// An OBJ without a light of its own inside a scene that has one: the OBJ's "nothing lights
// this" (W302) belonged to the OBJ alone; the scene is asked as a whole, and warns only when
// nothing in it lights it.
TEST_F(SceneObj, AnObjWithoutLightsInALitSceneIsNotWarnedUnlit) {
    std::ofstream(dir_ / "dark.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n";
    auto count = [](const testing::SceneResult& r, const std::string& code) {
        return std::count_if(r.diagnostics.begin(), r.diagnostics.end(), [&](const Diagnostic& d) { return d.code == code; });
    };
    std::ofstream(dir_ / "lit.json") << R"({"materials": [{"name": "l", "type": "light", "color": [1,1,1]}],
      "shapes": [{"type": "mesh", "file": "dark.obj"}, {"type": "sphere", "material": "l", "center": [0, 5, 0], "radius": 1}]})";
    auto lit = testing::load_path((dir_ / "lit.json").string());
    ASSERT_TRUE(lit.scene);
    EXPECT_EQ(count(lit, "W302"), 0);
    std::ofstream(dir_ / "unlit.json") << R"({"shapes": [{"type": "mesh", "file": "dark.obj"}]})";
    auto unlit = testing::load_path((dir_ / "unlit.json").string());
    ASSERT_TRUE(unlit.scene);
    EXPECT_EQ(count(unlit, "W302"), 1);
    EXPECT_EQ(unlit.where("W302").line, 1u);
}

// `v x y z r g b` (MeshLab's and scanners' vertex colours): read when every vertex has them,
// clamped to [0, 1], and carried to each mesh vertex made from that position, whatever its
// texture coordinate; a file where one vertex lacks them has none (no white fill).
TEST_F(SceneObj, VertexColoursAreReadWhenEveryVertexHasThem) {
    std::ofstream(dir_ / "c.obj") << "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 2 -0.5 0.25\n"
                                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
                                     "f 1/1 2/2 3/3\nf 1/5 3/3 4/4\n";
    auto r = testing::load_path((dir_ / "c.obj").string());
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    ASSERT_EQ(r.scene->shapes.size(), 1u);
    const Shape& mesh = r.scene->shapes[0];
    ASSERT_EQ(mesh.colors.size(), mesh.vertices.size());
    ASSERT_EQ(mesh.vertices.size(), 5u);  // position 1 twice: two texture coordinates
    const Vec3 expected[4] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0.25}};
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
        const Vec3& v = mesh.vertices[i];
        const size_t position = v.x == 0 ? (v.y == 0 ? 0 : 3) : (v.y == 0 ? 1 : 2);
        EXPECT_EQ(mesh.colors[i], expected[position]) << i;
    }
    EXPECT_FALSE(shape_problem(mesh));

    std::ofstream(dir_ / "some.obj") << "v 0 0 0 1 0 0\nv 1 0 0\nv 1 1 0 0 0 1\nf 1 2 3\n";
    r = testing::load_path((dir_ / "some.obj").string());
    ASSERT_TRUE(r.scene);
    EXPECT_TRUE(r.scene->shapes[0].colors.empty());
    std::ofstream(dir_ / "none.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n";
    r = testing::load_path((dir_ / "none.obj").string());
    ASSERT_TRUE(r.scene);
    EXPECT_TRUE(r.scene->shapes[0].colors.empty());
}

// A face corner is a mesh vertex of its own per distinct (position, texture coordinate,
// normal) within its object and material: a seam's second corner, met again, is the vertex
// made the first time; a position another object uses again is a vertex of that object's.
TEST_F(SceneObj, CornersShareAVertexWithinTheirObjectOnly) {
    std::ofstream(dir_ / "s.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
                                     "o a\nf 1/1 2/2 3/3\nf 1/5 3/3 4/4\nf 1/5 4/4 2/2\nf 1/1 3/3 4/4\n"
                                     "o b\nf 4/4 1/5 3/3\n";
    auto r = testing::load_path((dir_ / "s.obj").string());
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    ASSERT_EQ(r.scene->shapes.size(), 2u);
    const Shape& a = r.scene->shapes[0];
    const Shape& b = r.scene->shapes[1];
    ASSERT_EQ(a.vertices.size(), 5u);  // 1/1, 2/2, 3/3, 1/5, 4/4
    const std::vector<std::array<uint32_t, 3>> a_triangles = {{0, 1, 2}, {3, 2, 4}, {3, 4, 1}, {0, 2, 4}};
    EXPECT_EQ(a.triangles, a_triangles);
    EXPECT_EQ(a.uvs[3], (std::array<double, 2>{0.5, 0.5}));
    ASSERT_EQ(b.vertices.size(), 3u);
    const std::vector<std::array<uint32_t, 3>> b_triangles = {{0, 1, 2}};
    EXPECT_EQ(b.triangles, b_triangles);
    EXPECT_EQ(b.uvs[1], (std::array<double, 2>{0.5, 0.5}));
}

}  // namespace
}  // namespace crex
