// OBJ/MTL textures (issue 33): map_Kd, map_Ks, map_Ns, map_d, bump, norm, map_Ke, found
// relative to the MTL's own folder, with their options; texture coordinates and normals from
// vt and vn; a texture that is not there is a warning at its MTL line (it renders magenta);
// each map reads the channels it should from RGB, RGBA and grey images.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "runtime/texture/surface_textures.h"
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
                                       "usemtl screen\nf 1 2 3\n"
                                       "usemtl windows\nf 1/1 2/2 3/3\n";
    std::ofstream(dir / "mats" / "room.mtl") << "newmtl wood\nKd 0.8 0.6 0.4\nKs 0.2 0.2 0.2\nNs 100\n"
                                                "map_Kd -s 2 3 1 -o 0.5 0 0 tex/wood.png\nmap_Ks tex/spec.png\nmap_Ns tex/gloss.png\n"
                                                "bump -bm 2 tex/bumps.png\nnorm tex/normals.png\n"
                                                "newmtl leaf\nKd 0.3 0.6 0.2\nd 1\nmap_d -clamp on tex/leaf.png\n"
                                                "newmtl screen\nKd 0.05 0.05 0.05\nKe 1 1 1\nmap_Ke tex/screen.png\n"
                                                "map_Kd tex/missing.png\n"
                                                "newmtl windows\nKd 1 1 1\nmap_Kd .\\tex\\leaf.png\n";
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
    // A path written on Windows, with backslashes: found with slashes.
    const Material* windows = r.scene->find_material("room/windows");
    ASSERT_TRUE(windows && windows->textures.color);
    EXPECT_EQ(fs::path(windows->textures.color->file), fs::absolute(dir / "mats" / "tex" / "leaf.png").lexically_normal());
    // The missing texture: a warning at its line of the MTL (and only it).
    testing::expect_diagnostic(r, "missing texture", "W310", 18, 0, "tex/missing.png");
    EXPECT_EQ(r.find("W310")->span.file->name(), (dir / "mats" / "room.mtl").string());
    EXPECT_EQ(std::count_if(r.diagnostics.begin(), r.diagnostics.end(), [](const Diagnostic& d) { return d.code == "W310"; }), 1);
    fs::remove_all(dir);
}

// An uncompressed TGA of one colour: `bytes` its channels (grey; B G R; B G R A, as TGA
// stores them), 2 x 2 texels.
void write_tga(const std::filesystem::path& path, const std::vector<uint8_t>& bytes) {
    const bool grey = bytes.size() == 1;
    const uint8_t header[18] = {0, 0, uint8_t(grey ? 3 : 2), 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 2, 0, uint8_t(8 * bytes.size()),
                                uint8_t(bytes.size() == 4 ? 8 : 0)};
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(header), sizeof header);
    for (int texel = 0; texel < 4; ++texel) out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

double srgb_decoded(int byte) {
    const double c = byte / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// tinyobjloader gives every map but a bump -imfchan 'm' whether the MTL says so or not. Taken
// as channel 3 it dropped an RGB map_Kd (W311: the constant rendered instead) and made an RGBA
// one grey with its alpha. A colour map reads R, G, B; a scalar map the alpha where the image
// has one, else its first channel, or the channel -imfchan names.
TEST(SceneObjTextures, EachMapReadsItsChannelsFromRgbRgbaAndGreyImages) {
    const fs::path dir = fs::temp_directory_path() / ("crex_obj_channels_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    write_tga(dir / "rgb.tga", {153, 102, 51});       // R 51, G 102, B 153
    write_tga(dir / "rgba.tga", {102, 153, 204, 64});  // R 204, G 153, B 102, A 64
    write_tga(dir / "grey.tga", {191});
    std::ofstream(dir / "m.obj") << "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                                    "usemtl rgb\nf 1/1 2/2 3/3\nusemtl rgba\nf 1/1 2/2 3/3\nusemtl cut_rgba\nf 1/1 2/2 3/3\n"
                                    "usemtl cut_grey\nf 1/1 2/2 3/3\nusemtl cut_rgb\nf 1/1 2/2 3/3\nusemtl cut_green\nf 1/1 2/2 3/3\n";
    std::ofstream(dir / "m.mtl") << "newmtl rgb\nKd 1 1 1\nmap_Kd rgb.tga\n"
                                    "newmtl rgba\nKd 1 1 1\nmap_Kd rgba.tga\n"
                                    "newmtl cut_rgba\nKd 1 1 1\nmap_d rgba.tga\n"
                                    "newmtl cut_grey\nKd 1 1 1\nmap_d grey.tga\n"
                                    "newmtl cut_rgb\nKd 1 1 1\nmap_d rgb.tga\n"
                                    "newmtl cut_green\nKd 1 1 1\nmap_d -imfchan g rgba.tga\n";
    auto r = testing::load_path((dir / "m.obj").string());
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    std::vector<Diagnostic> warnings;
    const SurfaceTextures textures(*r.scene, size_t{16} << 20, warnings);
    for (const Diagnostic& w : warnings) ADD_FAILURE() << w.code << ": " << w.message;
    auto index = [&](const std::string& name) {
        const Material* m = r.scene->find_material("m/" + name);
        EXPECT_TRUE(m) << name;
        return static_cast<uint32_t>(m - r.scene->materials.data());
    };
    SurfacePoint p;
    p.u = p.v = 0.5;
    const Vec3 rgb = textures.values(index("rgb"), p).color, rgba = textures.values(index("rgba"), p).color;
    const double tolerance = 1e-3;
    EXPECT_NEAR(rgb.x, srgb_decoded(51), tolerance);
    EXPECT_NEAR(rgb.y, srgb_decoded(102), tolerance);
    EXPECT_NEAR(rgb.z, srgb_decoded(153), tolerance);
    EXPECT_NEAR(rgba.x, srgb_decoded(204), tolerance);
    EXPECT_NEAR(rgba.z, srgb_decoded(102), tolerance);
    EXPECT_NEAR(textures.opacity(index("cut_rgba"), p), 64 / 255.0, tolerance);   // its alpha
    EXPECT_NEAR(textures.opacity(index("cut_grey"), p), 191 / 255.0, tolerance);  // its one channel
    EXPECT_NEAR(textures.opacity(index("cut_rgb"), p), 51 / 255.0, tolerance);    // no alpha: its first
    EXPECT_NEAR(textures.opacity(index("cut_green"), p), 153 / 255.0, tolerance); // as -imfchan says
    fs::remove_all(dir);
}

}  // namespace
}  // namespace crex
