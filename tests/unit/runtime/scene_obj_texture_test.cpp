// OBJ/MTL textures (issue 33): map_Kd, map_Ks, map_Ns, map_d, bump, norm, map_Ke, found
// relative to the MTL's own folder, with their options; texture coordinates and normals from
// vt and vn; a texture that is not there is a warning at its MTL line (it renders magenta).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "tests/support/scene_helpers.h"

namespace crex {
namespace {

namespace fs = std::filesystem;

TEST(SceneObjTextures, MtlTexturesAreFoundBesideTheMtl) {
    const fs::path dir = fs::temp_directory_path() / ("crex_obj_tex_" + std::to_string(::getpid()));
    fs::create_directories(dir / "mats" / "tex");
    for (const char* f : {"wood.png", "spec.png", "gloss.png", "leaf.png", "bumps.png", "normals.png", "screen.png"})
        std::ofstream(dir / "mats" / "tex" / f) << "texels";
    std::ofstream(dir / "room.obj") << "mtllib mats/room.mtl\n"
                                       "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
                                       "usemtl wood\nf 1/1/1 2/2/1 3/3/1\n"
                                       "usemtl leaf\nf 1/1 2/2 3/3\n"
                                       "usemtl screen\nf 1 2 3\n";
    std::ofstream(dir / "mats" / "room.mtl") << "newmtl wood\nKd 0.8 0.6 0.4\nKs 0.2 0.2 0.2\nNs 100\n"
                                                "map_Kd -s 2 3 1 -o 0.5 0 0 tex/wood.png\nmap_Ks tex/spec.png\nmap_Ns tex/gloss.png\n"
                                                "bump -bm 2 tex/bumps.png\nnorm tex/normals.png\n"
                                                "newmtl leaf\nKd 0.3 0.6 0.2\nd 1\nmap_d -clamp on tex/leaf.png\n"
                                                "newmtl screen\nKd 0.05 0.05 0.05\nKe 1 1 1\nmap_Ke tex/screen.png\n"
                                                "map_Kd tex/missing.png\n";
    auto r = testing::load_path((dir / "room.obj").string());
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Material* wood = r.scene->find_material("room/wood");
    ASSERT_TRUE(wood);
    EXPECT_EQ(wood->type, MaterialType::kPlastic);
    const MaterialTextures& t = wood->textures;
    ASSERT_TRUE(t.color && t.specular_color && t.roughness && t.bump && t.normal);
    EXPECT_EQ(fs::path(t.color->file), fs::absolute(dir / "mats" / "tex" / "wood.png").lexically_normal());
    // OBJ's v runs up, images' t down: t = 1 - (3 v + 0); s = 2 u + 0.5.
    EXPECT_EQ(t.color->uv_transform, (UvTransform{2, 0, 0.5, 0, -3, 1}));
    // Kd x texel: the colour's scale is what the diffuse lobe's Kd needs (Kd / (1 - s)).
    EXPECT_NEAR(t.color->scale.x * (1 - wood->specularity), 0.8, 1e-9);
    EXPECT_NEAR(t.specular_color->scale.x * wood->specularity, 0.2, 1e-9);
    EXPECT_DOUBLE_EQ(t.roughness->power, -0.5);  // roughness ~ (Ns texel / 2)^(-1/2)
    EXPECT_NEAR(t.bump->scale.x, 0.02, 1e-12);    // -bm 2, a texel of 1 = 1 cm
    const Material* leaf = r.scene->find_material("room/leaf");
    ASSERT_TRUE(leaf && leaf->textures.opacity);
    EXPECT_EQ(leaf->type, MaterialType::kPlastic);  // map_d is a cut-out, not glass
    EXPECT_EQ(leaf->textures.opacity->wrap_s, TextureWrap::kClamp);
    const Material* screen = r.scene->find_material("room/screen");
    ASSERT_TRUE(screen && screen->textures.emission);
    EXPECT_EQ(screen->type, MaterialType::kPlastic);  // a textured Ke glows; it is not a sampled lamp
    // vt and vn on every corner: the mesh has them; the leaf's faces lack normals.
    for (const auto& s : r.scene->shapes) {
        EXPECT_EQ(s.uvs.size(), s.material == "room/screen" ? 0u : s.vertices.size()) << s.material;
        EXPECT_EQ(s.normals.size(), s.material == "room/wood" ? s.vertices.size() : 0u) << s.material;
    }
    // The missing texture: a warning at its line of the MTL.
    testing::expect_diagnostic(r, "missing texture", "W310", 18, 0, "tex/missing.png");
    EXPECT_EQ(r.find("W310")->span.file->name(), (dir / "mats" / "room.mtl").string());
    fs::remove_all(dir);
}

}  // namespace
}  // namespace crex
