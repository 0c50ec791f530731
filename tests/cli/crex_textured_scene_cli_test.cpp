// The textured example scene (examples/scenes/living_room, written by the build) as a user
// meets it: `crex scene-info` lists what issue 33 asks of it (100k+ triangles, eight textures
// or more, two light kinds, a tagged task object and a distractor) with its textures' files,
// sizes and memory; `crex run --format json` reports the texture cache and lookups; `--camera`
// chooses among its cameras.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "tests/support/crex_cli.h"

namespace crex {
namespace {

using testing::crex_cli;

const std::string kRoom = CREX_LIVING_ROOM "/scene.gltf";

TEST(TexturedSceneCli, SceneInfoShowsWhatTheExampleHolds) {
    auto r = crex_cli({"scene-info", "--format", "json", kRoom});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_GE(j["scene"]["triangles"].get<size_t>(), 100000u);
    EXPECT_EQ(j["scene"]["metres_per_unit"].get<double>(), 1.0);
    ASSERT_GE(j["textures"].size(), 8u);
    for (const auto& t : j["textures"]) {
        EXPECT_FALSE(t.contains("error")) << t.dump();
        EXPECT_GT(t["file_bytes"].get<uint64_t>(), 0u);
        EXPECT_GE(t["memory_bytes"].get<uint64_t>(), t["width"].get<uint64_t>() * t["height"].get<uint64_t>());
    }
    // Three sampled lights: the ceiling panel, the lamp's point light and the screen, whose
    // emission is an image.
    EXPECT_GE(j["census"]["sampled_emitters"].get<size_t>(), 3u);
    EXPECT_EQ(j["census"]["unsampled_emitters"].get<size_t>(), 0u);
    EXPECT_EQ(j["census"]["tags"], nlohmann::json::array({"mug", "tv"}));
    auto text = crex_cli({"scene-info", kRoom});
    EXPECT_NE(text.out.find("units      1 m per unit, up (0, 1, 0)"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("textured: color, roughness, metallic"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("wood_floor.png  512x512, 3 channels"), std::string::npos) << text.out;
}

TEST(TexturedSceneCli, RunReportsTheTextureCache) {
    auto r = crex_cli({"run", "--scene", kRoom, "--size", "32x24", "--spp", "1", "-e", "D", "--format", "json", "-q", "-o",
                       (std::filesystem::temp_directory_path() / "crex_cli_living_room.exr").string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.contains("textures")) << r.out;
    const auto& t = j["textures"];
    EXPECT_GT(t["lookups"].get<uint64_t>(), 0u);
    EXPECT_GT(t["cache"]["queries"].get<uint64_t>(), 0u);
    // The cache's limit is its share of --max-memory (1 GiB by default: 128 MiB).
    EXPECT_EQ(t["cache"]["memory_limit_bytes"].get<uint64_t>(), uint64_t{128} << 20);
    const double share = t["lookup_share_of_render"].get<double>();
    EXPECT_GT(share, 0.0);
    EXPECT_LT(share, 1.0);
    // The text summary says it once (the line was printed twice after a merge).
    auto text = crex_cli({"run", "--scene", kRoom, "--size", "32x24", "--spp", "1", "-e", "D", "-o",
                          (std::filesystem::temp_directory_path() / "crex_cli_living_room.exr").string()});
    ASSERT_EQ(text.exit_code, 0) << text.err;
    const std::string said = text.out + text.err;
    const size_t first = said.find("  textures: ");
    ASSERT_NE(first, std::string::npos) << said;
    EXPECT_EQ(said.find("  textures: ", first + 1), std::string::npos) << said;
    // With the cache on, its hemisphere rays read the coarse copies, and the line counts them too,
    // and the cut-out tests answered from masks.
    auto cached = crex_cli({"run", "--scene", kRoom, "--size", "32x24", "--spp", "1", "--ic", "--ad", "64", "-o",
                            (std::filesystem::temp_directory_path() / "crex_cli_living_room.exr").string()});
    ASSERT_EQ(cached.exit_code, 0) << cached.err;
    const std::string cached_said = cached.out + cached.err;
    const size_t line = cached_said.find("  textures: ");
    ASSERT_NE(line, std::string::npos) << cached_said;
    const std::string textures_line = cached_said.substr(line, cached_said.find('\n', line) - line);
    EXPECT_NE(textures_line.find(" from coarse copies"), std::string::npos) << cached_said;
    // The plant's leaves are alpha cut-outs: their tests are answered from its opacity mask.
    EXPECT_NE(textures_line.find(" cut-out tests from opacity masks"), std::string::npos) << cached_said;
    std::filesystem::remove(std::filesystem::temp_directory_path() / "crex_cli_living_room.exr");
}

TEST(TexturedSceneCli, CameraChoosesAmongTheScenesCameras) {
    auto bad = crex_cli({"run", "--scene", kRoom, "--camera", "attic", "--size", "8x6", "-q", "-o", "/dev/null.exr"});
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.err.find("the scene's cameras are 0 'view'"), std::string::npos) << bad.err;
    auto info = crex_cli({"scene-info", kRoom, "--camera", "0"});
    EXPECT_EQ(info.exit_code, 0) << info.err;
}

}  // namespace
}  // namespace crex
