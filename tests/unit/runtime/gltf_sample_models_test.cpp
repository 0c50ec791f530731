// Every glTF 2.0 file of Debian's assimp-testmodels (written by others: valid models, and
// deliberately broken ones) loads, or is refused with errors that name the file and where in
// it; none crashes or hangs (ctest's timeout, and ASan in CI). Every texture of those that load
// can be read, files and images carried in the file alike.
#include <gtest/gtest.h>

#include <filesystem>

#include "runtime/scene/shapes.h"
#include "runtime/texture/surface_textures.h"
#include "tests/support/scene_helpers.h"

namespace crex {
namespace {

namespace fs = std::filesystem;

TEST(GltfSampleModels, EveryFileLoadsOrIsRefusedWithALocatedError) {
    const fs::path dir = "/usr/share/assimp/models/glTF2";
    if (!fs::is_directory(dir))
        GTEST_SKIP() << dir << " is absent: install Debian's assimp-testmodels (tools/debian-packages.txt lists it) to walk its glTF files";
    std::vector<fs::path> files;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        const std::string ext = e.path().extension().string();
        if (e.is_regular_file() && (ext == ".gltf" || ext == ".glb")) files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    ASSERT_GT(files.size(), 20u);
    size_t loaded = 0, refused = 0;
    for (const auto& f : files) {
        auto r = testing::load_path(f.string());
        if (r.scene) {
            ++loaded;
            EXPECT_FALSE(r.scene->shapes.empty()) << f;
            for (const auto& s : r.scene->shapes) {
                EXPECT_FALSE(shape_problem(s).has_value()) << f;
                for (const auto& v : s.vertices) ASSERT_TRUE(is_finite(v)) << f;
            }
            continue;
        }
        ++refused;
        ASSERT_GT(r.errors, 0u) << f << ": refused without an error";
        for (const auto& d : r.diagnostics) {
            if (d.severity != Severity::kError) continue;
            ASSERT_NE(d.span.file, nullptr) << f << ": " << d.message;
            EXPECT_EQ(d.span.file->name(), f.string()) << d.message;
        }
    }
    std::cout << files.size() << " glTF files: " << loaded << " load, " << refused << " refused with located errors\n";
    EXPECT_GT(loaded, files.size() / 2);
}

// Loading checks that an image's bytes reach the scene; this opens each through the texture
// cache. Every image carried in a .glb or a data URI rendered magenta (W310: OpenImageIO found
// no reader for the name 'BoxTextured.glb#image0') and no test said so.
TEST(GltfSampleModels, EveryTextureOfTheModelsThatLoadIsRead) {
    const fs::path dir = "/usr/share/assimp/models/glTF2";
    if (!fs::is_directory(dir)) GTEST_SKIP() << dir << " is absent: install Debian's assimp-testmodels";
    size_t images = 0, embedded = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        const std::string ext = e.path().extension().string();
        if (!e.is_regular_file() || (ext != ".gltf" && ext != ".glb")) continue;
        auto r = testing::load_path(e.path().string());
        if (!r.scene) continue;
        std::vector<Diagnostic> warnings;
        const TextureStats stats = SurfaceTextures(*r.scene, kDefaultTextureCacheBytes, warnings).stats();
        for (const Diagnostic& w : warnings) EXPECT_NE(w.code, "W310") << e.path() << ": " << w.message;
        images += stats.images.size();
        for (const TextureImage& i : stats.images) embedded += i.name.find('#') != std::string::npos;
    }
    std::cout << images << " images read, " << embedded << " of them carried in their glTF file\n";
    EXPECT_GT(embedded, 0u);
}

}  // namespace
}  // namespace crex
