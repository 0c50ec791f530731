// `crex check` as a user runs it: exit codes, which stream gets what, JSON for tools.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "tests/support/crex_cli.h"

namespace crex {
namespace {

using testing::crex_cli;

TEST(CrexCheckCli, ValidExpressionExitsZeroAndSaysOk) {
    auto r = crex_cli({"check", "-e", "TT{TTMRSGD}2"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("ok: TT{TTMRSGD}2"), std::string::npos) << r.out;
    EXPECT_EQ(r.err, "");
}

TEST(CrexCheckCli, BracketsAreNotMistakenForListsByTheOptionParser) {
    auto r = crex_cli({"check", "-e", "[G*]"});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("error[E005]"), std::string::npos) << r.err;
}

TEST(CrexCheckCli, ErrorsGoToStderrWithExitOne) {
    auto r = crex_cli({"check", "-e", "{D*}"});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("<expr>:1:3: error[E004]:"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");
}

TEST(CrexCheckCli, WarningsOnlyExitZero) {
    auto r = crex_cli({"check", "-e", "(T*)2"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.err.find("warning[W101]"), std::string::npos);
}

TEST(CrexCheckCli, UsageErrorsExitTwo) {
    EXPECT_EQ(crex_cli({}).exit_code, 2);
    EXPECT_EQ(crex_cli({"check"}).exit_code, 2);
    EXPECT_EQ(crex_cli({"check", "--no-such-flag", "-e", "D"}).exit_code, 2);
    EXPECT_EQ(crex_cli({"check", "--format", "xml", "-e", "D"}).exit_code, 2);
    EXPECT_EQ(crex_cli({"frobnicate"}).exit_code, 2);
}

TEST(CrexCheckCli, MissingFileExitsThreeAndNamesIt) {
    auto r = crex_cli({"check", "/nonexistent/x.crex"});
    EXPECT_EQ(r.exit_code, 3);
    EXPECT_NE(r.err.find("/nonexistent/x.crex"), std::string::npos);
}

TEST(CrexCheckCli, HelpTeachesAndExitsZero) {
    auto r = crex_cli({"check", "--help"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("Examples:"), std::string::npos);
    EXPECT_NE(r.out.find("Exit status"), std::string::npos);
}

TEST(CrexCheckCli, CrexFileReportsFileLineAndColumn) {
    auto path = std::filesystem::temp_directory_path() / "crex_cli_test.crex";
    std::ofstream(path) << "# thesis expressions\nTT\n\n  (TT[RS*]G)*D\n";
    auto r = crex_cli({"check", path.string()});
    std::filesystem::remove(path);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find(path.string() + ":4:9: error[E005]"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find(path.string() + ":2:1: ok: TT"), std::string::npos) << r.out;
}

TEST(CrexCheckCli, ReadsStandardInput) {
    auto r = crex_cli({"check", "-"}, "TT\nD0\n");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("<stdin>:2:2: error[E003]"), std::string::npos) << r.err;
}

TEST(CrexCheckCli, JsonOutputIsMachineReadable) {
    auto r = crex_cli({"check", "--format", "json", "-e", "<DG)", "-e", "T{RS}"});
    EXPECT_EQ(r.exit_code, 1);
    auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["diagnostics"].size(), 1u);
    const auto& d = j["diagnostics"][0];
    for (const char* key : {"file", "line", "col", "end_line", "end_col", "code", "severity", "message", "notes"})
        EXPECT_TRUE(d.contains(key)) << key;
    EXPECT_EQ(d["code"], "E002");
    EXPECT_EQ(j["crexes"][1]["preselective"], "T");
    EXPECT_EQ(j["crexes"][1]["selective"], "{RS}");
}

TEST(CrexCheckCli, ExplainPrintsSteps) {
    auto r = crex_cli({"check", "--explain", "-e", "<DGS>G"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("deferred"), std::string::npos);
    EXPECT_NE(r.out.find("2. G: execute the indirect glossy rays"), std::string::npos) << r.out;
}

TEST(CrexCheckCli, RandomArgumentsExitZeroOrOne) {
    std::mt19937 rng(3);
    for (int i = 0; i < 100; ++i) {
        std::string s;
        int len = std::uniform_int_distribution<int>(1, 20)(rng);
        for (int k = 0; k < len; ++k) s += static_cast<char>(std::uniform_int_distribution<int>(1, 255)(rng));
        auto r = crex_cli({"check", "-e", s});
        EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << "exit " << r.exit_code << " for " << s;
        auto j = crex_cli({"check", "--format", "json", "-e", s});
        EXPECT_TRUE(nlohmann::json::accept(j.out)) << j.out;
    }
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(CrexCheckCli, ChecksPipelineFiles) {
    auto ok = crex_cli({"check", CREX_SOURCE_DIR "/examples/pipelines/cornell_prog.pipe"});
    EXPECT_EQ(ok.exit_code, 0) << ok.err;
    EXPECT_NE(ok.out.find("cornell_prog.pipe:7:10: ok: pipeline cornell_prog"), std::string::npos) << ok.out;
    EXPECT_EQ(ok.err.find("warning"), std::string::npos) << ok.err;  // every part of it executes, its scene has the tag
    auto path = std::filesystem::temp_directory_path() / "crex_cli_bad.pipe";
    std::ofstream(path) << "pipeline p {\n  selective { crex \"{D*}\" }\n}\n";
    auto bad = crex_cli({"check", path.string()});
    std::filesystem::remove(path);
    EXPECT_EQ(bad.exit_code, 1);
    EXPECT_NE(bad.err.find("crex_cli_bad.pipe:2:23: error[E004]"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(CrexCheckCli, APipelineAgainstItsSceneWarnsWhereItAsksForWhatIsNotThere) {
    // spec §6: the scene must tag what the task map asks for, and the pre-selective crex must
    // fill every buffer guidance reads; both are warnings at the pipeline's line.
    auto path = std::filesystem::temp_directory_path() / ("crex_cli_scene_" + std::to_string(::getpid()) + ".pipe");
    std::ofstream(path) << "pipeline p {\n  scene \"" CREX_SOURCE_DIR "/examples/scenes/cornell/scene.json\"\n"
                           "  preselective { crex \"TT\" }\n"
                           "  guidance {\n    ic = edges(component(D))\n    task = task_map(tagged(\"exit_sign\"))\n"
                           "    imp = importance(task 0.5, ic 0.5)\n  }\n  selective { vary spp 1 .. 4 by imp }\n}\n";
    auto r = crex_cli({"check", path.string()});
    EXPECT_EQ(r.exit_code, 0) << r.err;  // warnings only
    EXPECT_NE(r.err.find(":5:16: warning[W204]: component(D)"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(":6:28: warning[W203]: no object of the scene is tagged 'exit_sign'"), std::string::npos) << r.err;
    // A scene that cannot be read is an error of check, not only of run.
    std::ofstream(path) << "pipeline p {\n  scene \"/nonexistent/scene.json\"\n}\n";
    auto missing = crex_cli({"check", path.string()});
    EXPECT_EQ(missing.exit_code, 3) << missing.err;
    std::filesystem::remove(path);
}

// media_samples needs a medium: W403 at the vary's range on the Cornell box, nothing on the
// mist (the same box in a medium).
TEST(CrexCheckCli, MediaSamplesOnASceneWithoutAMediumIsW403) {
    const std::string pipe = CREX_SOURCE_DIR "/stdlib/pipelines/prog_dis_media.pipe";
    auto box = testing::crex_cli({"check", pipe, "--scene", "builtin:cornell"});
    EXPECT_EQ(box.exit_code, 0) << box.err;
    EXPECT_NE(box.err.find("prog_dis_media.pipe:9:24: warning[W403]: 'media_samples' has no effect"), std::string::npos) << box.err;
    auto mist = testing::crex_cli({"check", pipe, "--scene", CREX_SOURCE_DIR "/examples/scenes/mist/scene.json"});
    EXPECT_EQ(mist.exit_code, 0) << mist.err;
    EXPECT_EQ(mist.err.find("W403"), std::string::npos) << mist.err;
}

}  // namespace
}  // namespace crex
