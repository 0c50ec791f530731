// `crex scene-info` as a user runs it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "tests/support/crex_cli.h"

namespace crex {
namespace {

using testing::crex_cli;

TEST(CrexSceneInfoCli, DefaultsToTheBuiltinCornellBox) {
    auto r = crex_cli({"scene-info"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("scene builtin:cornell"), std::string::npos);
    EXPECT_NE(r.out.find("T transmitted                      yes, from glass"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("cannot occur: G, S"), std::string::npos);
}

TEST(CrexSceneInfoCli, DiffuseOnlySceneSaysWhatCannotOccur) {
    auto r = crex_cli({"scene-info", CREX_SOURCE_DIR "/examples/scenes/cornell_diffuse/scene.json"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("cannot occur: G, S, T, R, M"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("spawn graph: {camera, D} -> {D}"), std::string::npos) << r.out;
}

TEST(CrexSceneInfoCli, JsonCensus) {
    auto r = crex_cli({"scene-info", "--format", "json", "builtin:cornell_diffuse"});
    EXPECT_EQ(r.exit_code, 0);
    auto j = nlohmann::json::parse(r.out);
    EXPECT_TRUE(j["census"]["components"]["D"]["can_occur"].get<bool>());
    for (const char* c : {"G", "S", "T", "R", "M"}) EXPECT_FALSE(j["census"]["components"][c]["can_occur"].get<bool>()) << c;
}

TEST(CrexSceneInfoCli, SaysWhenARifHidesBackFaces) {
    // A .rif whose render line has -bv-: the text says so, the JSON carries it.
    auto dir = std::filesystem::temp_directory_path() / ("crex_cli_bv_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "room.rad") << "void light l 0 0 3 1 1 1\nl sphere s 0 0 4 0 0 0 1\n";
    std::ofstream(dir / "room.rif") << "scene = room.rad\nrender = -ab 2 -bv-\nview = -vp 0 0 5 -vd 0 0 -1 -vu 0 1 0\n";
    const std::string rif = (dir / "room.rif").string();
    auto text = crex_cli({"scene-info", rif});
    auto json = crex_cli({"scene-info", "--format", "json", rif});
    std::filesystem::remove_all(dir);
    EXPECT_EQ(text.exit_code, 0) << text.err;
    EXPECT_NE(text.out.find("back faces hidden (RADIANCE -bv-)"), std::string::npos) << text.out;
    ASSERT_EQ(json.exit_code, 0) << json.err;
    EXPECT_FALSE(nlohmann::json::parse(json.out)["scene"]["back_faces_visible"].get<bool>());
    EXPECT_TRUE(nlohmann::json::parse(crex_cli({"scene-info", "--format", "json"}).out)["scene"]["back_faces_visible"].get<bool>());
}

TEST(CrexSceneInfoCli, ExitCodes) {
    EXPECT_EQ(crex_cli({"scene-info", "/nonexistent.json"}).exit_code, 3);
    EXPECT_EQ(crex_cli({"scene-info", "builtin:nope"}).exit_code, 3);
    auto path = std::filesystem::temp_directory_path() / "crex_cli_bad_scene.json";
    std::ofstream(path) << "{\"shapes\": [{\"type\": \"sphere\"}]}";
    auto r = crex_cli({"scene-info", path.string()});
    std::filesystem::remove(path);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("error[E304]"), std::string::npos) << r.err;
}

TEST(CrexSceneInfoCli, ExportWritesALoadableSceneAtomically) {
    auto dir = std::filesystem::temp_directory_path() / "crex_cli_export";
    std::filesystem::create_directories(dir);
    auto out = dir / "cornell.json";
    auto r = crex_cli({"scene-info", CREX_SOURCE_DIR "/examples/scenes/cornell/scene.rad", "--export-json", out.string()});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    auto again = crex_cli({"scene-info", out.string()});
    EXPECT_EQ(again.exit_code, 0) << again.err;
    size_t files = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
    EXPECT_EQ(files, 1u);  // no temporary left behind
    std::filesystem::remove(out);
    std::ofstream(dir / "a_file") << "not a directory";
    auto bad = crex_cli({"scene-info", "--export-json", (dir / "a_file" / "x.json").string()});
    EXPECT_EQ(bad.exit_code, 3);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace crex
