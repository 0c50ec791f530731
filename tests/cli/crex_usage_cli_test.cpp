// Usage errors in git's manner (issue 17) and the run driver's flags (issue 13): what was
// wrong, the nearest right thing, the subcommand named, exit code 2.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "runtime/io/image_io.h"
#include "tests/support/crex_cli.h"

namespace crex {
namespace {

namespace fs = std::filesystem;
using testing::crex_cli;

TEST(UsageCli, AMisspelledCommandIsNamedWithTheNearestOne) {
    auto r = crex_cli({"rnu"});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("crex: 'rnu' is not a crex command. Did you mean 'run'?"), std::string::npos) << r.err;
    auto c = crex_cli({"chek", "-e", "TT"});
    EXPECT_EQ(c.exit_code, 2);
    EXPECT_NE(c.err.find("Did you mean 'check'?"), std::string::npos) << c.err;
}

// `crex` alone, as `git` alone: the overview of the commands (on stderr, since no command ran),
// not only "a subcommand is required".
TEST(UsageCli, NoCommandShowsTheOverviewOfCommands) {
    auto r = crex_cli({});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_TRUE(r.out.empty()) << r.out;
    for (const char* command : {"check", "scene-info", "run", "plan", "compare", "reference", "help"})
        EXPECT_NE(r.err.find(std::string("\n  ") + command + " "), std::string::npos) << command << "\n" << r.err;
    EXPECT_NE(r.err.find("crex help <command>"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("crex: error: a command is required"), std::string::npos) << r.err;
}

// A command without the files it needs says which, and shows how it is called.
TEST(UsageCli, AMissingArgumentShowsTheCommandsUsage) {
    auto r = crex_cli({"compare"});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("crex compare: error: test is required"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("Usage: crex compare [OPTIONS] test reference"), std::string::npos) << r.err;
    auto one = crex_cli({"compare", "a.exr"});
    EXPECT_EQ(one.exit_code, 2);
    EXPECT_NE(one.err.find("reference is required"), std::string::npos) << one.err;
    EXPECT_NE(one.err.find("Usage: crex compare"), std::string::npos) << one.err;
}

TEST(UsageCli, AMisspelledFlagGetsTheNearestFlagAndTheCommandsName) {
    auto r = crex_cli({"run", "--sze", "64x64"});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("crex run: error: unknown option '--sze'. Did you mean '--size'?"), std::string::npos) << r.err;
}

TEST(UsageCli, RangeErrorsSayTheRange) {
    auto r = crex_cli({"run", "--spp=abc"});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("crex run: error: --spp: 'abc' is not a number: expected a whole number from 1 to 1048576"), std::string::npos) << r.err;
    auto zero = crex_cli({"run", "--spp", "0"});
    EXPECT_EQ(zero.exit_code, 2);
    EXPECT_NE(zero.err.find("crex run: error: --spp: '0' is out of range: expected a whole number from 1 to 1048576"), std::string::npos) << zero.err;
    // Range ends as people write them (not 1000000000000000019884624838656.000000).
    auto clamp = crex_cli({"run", "--clamp", "0"});
    EXPECT_EQ(clamp.exit_code, 2);
    EXPECT_NE(clamp.err.find("--clamp: '0' is out of range: expected a number from 1e-6 to 1e30"), std::string::npos) << clamp.err;
    auto size = crex_cli({"run", "--size", "0x64", "-q"});
    EXPECT_EQ(size.exit_code, 2);
    EXPECT_NE(size.err.find("each 1 to 16384"), std::string::npos) << size.err;
}

TEST(UsageCli, SeedsAreWholeNumbersNotWrappedNegatives) {
    // --seed -1 and --seed 1e23 both became 2^64 - 1.
    for (const char* bad : {"-1", "1e23", "18446744073709551615", "4.5"}) {
        auto r = crex_cli({"run", "--seed", bad, "--size", "8x8", "-q", "-o", "/tmp/crex_usage_never.exr"});
        EXPECT_EQ(r.exit_code, 2) << bad;
        EXPECT_NE(r.err.find("expected a whole number from 0 to 9007199254740992"), std::string::npos) << r.err;
    }
}

// `crex help COMMAND` is `crex COMMAND --help`, as git has it; a wrong name gets the nearest one.
TEST(UsageCli, HelpShowsACommandsHelp) {
    auto help = crex_cli({"help", "run"});
    EXPECT_EQ(help.exit_code, 0) << help.err;
    EXPECT_EQ(help.out, crex_cli({"run", "--help"}).out);
    EXPECT_NE(help.out.find("Usage: crex run"), std::string::npos) << help.out;
    auto overview = crex_cli({"help"});
    EXPECT_EQ(overview.exit_code, 0);
    EXPECT_EQ(overview.out, crex_cli({"--help"}).out);
    EXPECT_NE(overview.out.find("Subcommands:"), std::string::npos) << overview.out;
    auto wrong = crex_cli({"help", "plna"});
    EXPECT_EQ(wrong.exit_code, 2);
    EXPECT_NE(wrong.err.find("crex help: error: 'plna' is not a crex command. Did you mean 'plan'?"), std::string::npos) << wrong.err;
    EXPECT_EQ(wrong.out, "");
}

TEST(UsageCli, VersionIsPrinted) {
    auto r = crex_cli({"--version"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_EQ(r.out.rfind("crex ", 0), 0u) << r.out;
}

TEST(DriverCli, BudgetsNeedTheirUnitAndAmbientRejectsNan) {
    auto budget = crex_cli({"run", "--size", "8x8", "--budget", "10", "-q", "-o", "/tmp/crex_usage_never.exr"});
    EXPECT_EQ(budget.exit_code, 2);
    EXPECT_NE(budget.err.find("expected a time with its unit"), std::string::npos) << budget.err;
    auto nan = crex_cli({"run", "--size", "8x8", "--ambient", "nan", "-q", "-o", "/tmp/crex_usage_never.exr"});
    EXPECT_EQ(nan.exit_code, 2);
    EXPECT_NE(nan.err.find("--ambient 'nan'"), std::string::npos) << nan.err;
    EXPECT_FALSE(fs::exists("/tmp/crex_usage_never.exr"));
}

// A budget or scene that comes from a pipeline file is said at its line in the file (exit 1);
// the same mistake on the command line names the flag (exit 2). --no-budget turns it off.
TEST(DriverCli, ABudgetOrSceneFromAPipelineIsSaidAtItsLine) {
    const std::string cbtcr = CREX_SOURCE_DIR "/stdlib/pipelines/cbtcr.pipe";
    auto pipe = crex_cli({"run", cbtcr, "--size", "8x8", "-q", "-o", "/tmp/crex_usage_never.exr"});
    EXPECT_EQ(pipe.exit_code, 1);
    EXPECT_NE(pipe.err.find("cbtcr.pipe:3:10: error: budget 50%: a budget in % needs"), std::string::npos) << pipe.err;
    auto flag = crex_cli({"run", "--size", "8x8", "--budget", "20%", "-q", "-o", "/tmp/crex_usage_never.exr"});
    EXPECT_EQ(flag.exit_code, 2);
    EXPECT_NE(flag.err.find("crex run: error: --budget 20%: a budget in % needs"), std::string::npos) << flag.err;
    EXPECT_EQ(crex_cli({"run", cbtcr, "--size", "8x8", "-q", "--no-budget", "-o", "/tmp/crex_usage_budget_off.png"}).exit_code, 0);
    std::remove("/tmp/crex_usage_budget_off.png");

    const std::string dir = ::testing::TempDir();
    const std::string noscene = dir + "/crex_noscene.pipe";
    {
        std::ofstream out(noscene);
        out << "pipeline p {\n  scene \"nowhere/scene.json\"\n  preselective { crex \"TT\" }\n}\n";
    }
    auto scene = crex_cli({"run", noscene, "-q", "-o", "/tmp/crex_usage_never.exr"});
    EXPECT_EQ(scene.exit_code, 3);
    EXPECT_NE(scene.err.find("crex_noscene.pipe:2:9: cannot read scene"), std::string::npos) << scene.err;
    std::remove(noscene.c_str());
}

TEST(DriverCli, AnEmptyCrexIsEmptyAsCheckAndPlanTakeIt) {
    fs::path out = fs::temp_directory_path() / ("crex_usage_empty_" + std::to_string(::getpid()) + ".exr");
    auto r = crex_cli({"run", "-e", "", "--size", "8x8", "--spp", "1", "--format", "json", "-q", "-o", out.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["crex"], "");
    for (const char* c : {"D", "G", "S", "T", "R", "M"}) EXPECT_EQ(j["components"][c]["rays"], 0) << c;
    EXPECT_EQ(j["components"]["camera"]["rays"], 64);
    fs::remove(out);
}

TEST(DriverCli, UniformMaxIsThePipelinesGoldAndPassesAreReported) {
    // --uniform max: every variable at its maximum (spp 1..16 by saliency -> 16 everywhere).
    fs::path out = fs::temp_directory_path() / ("crex_usage_gold_" + std::to_string(::getpid()) + ".exr");
    auto r = crex_cli({"run", CREX_SOURCE_DIR "/stdlib/pipelines/sel_rp.pipe", "--size", "12x8", "--uniform", "max", "--pass-samples",
                       "3", "--format", "json", "-q", "-o", out.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_GE(j["passes"].get<int>(), 2);
    int w = 0, h = 0;
    std::vector<float> rgb;
    ASSERT_EQ(read_image(out.string(), w, h, rgb), "");
    EXPECT_EQ(w, 12);
    fs::remove(out);
}

}  // namespace
}  // namespace crex
