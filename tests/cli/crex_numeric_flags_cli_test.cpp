// Every numeric flag of every command refuses NaN and infinities by name, with its range
// (issue 37: `--lw nan` ran for ever, `compare --ppd nan` crashed, NaN passed --clamp, --aa,
// --ar, --max-memory, --rank-timeout, --checkpoint-interval, --perr-threshold). The flags are
// found from each command's --help, so a flag added later is walked too: one whose value is a
// number (FLOAT, INT, UINT) must go through the one check (apps/crex/cli_values.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <set>

#include "tests/support/crex_cli.h"

namespace crex {
namespace {

namespace fs = std::filesystem;

using testing::crex_cli;
using testing::run_command;

struct NumericFlag {
    std::string command, flag, type;
};

// The commands, and what makes each exit at once should a value slip through the check: an
// output with no image format (run, reference), images that do not exist (compare).
const std::vector<std::pair<std::string, std::vector<std::string>>>& commands() {
    static const std::vector<std::pair<std::string, std::vector<std::string>>> c = {
        {"check", {"-e", "D"}},
        {"plan", {"-e", "D"}},
        {"run", {"--size", "1x1", "--scene", "builtin:none", "-o", "nowhere.unknown-format"}},
        {"compare", {"no-such-test.exr", "no-such-reference.exr"}},
        {"reference", {"builtin:none", "--size", "1x1", "-o", "nowhere.unknown-format"}},
        {"scene-info", {"builtin:none"}},
    };
    return c;
}

std::vector<NumericFlag> numeric_flags() {
    // "  --lw FLOAT:number from 0 to 1=0.001   Weight limit ..." and "  -e,--crex TEXT ...".
    static const std::regex option(R"(^\s+(?:-\w,)?(--[\w-]+)(?:,-\w)?\s+(FLOAT|INT|UINT|NUMBER)\b)");
    std::vector<NumericFlag> out;
    for (const auto& [command, _] : commands()) {
        auto help = crex_cli({command, "--help"});
        EXPECT_EQ(help.exit_code, 0) << command;
        std::istringstream lines(help.out);
        for (std::string line; std::getline(lines, line);) {
            std::smatch m;
            if (std::regex_search(line, m, option)) out.push_back({command, m[1], m[2]});
        }
    }
    return out;
}

TEST(NumericFlags, TheWalkFindsTheFlagsTheIssueNamed) {
    std::set<std::string> found;
    for (const auto& f : numeric_flags()) found.insert(f.command + " " + f.flag);
    for (const char* f : {"run --lw", "run --clamp", "run --aa", "run --ar", "run --max-memory", "run --rank-timeout",
                          "run --checkpoint-interval", "run --star-cap", "run --spp", "run --seed", "compare --ppd",
                          "compare --perr-threshold", "reference --spp"})
        EXPECT_TRUE(found.count(f)) << f << " is not listed as a number in its --help";
    EXPECT_GE(found.size(), 24u);
}

// Each flag takes NaN, and in turn +infinity or an overflow to -infinity: what refuses them is
// the one check every numeric flag goes through (a flag proves it is wired to it with any of
// them), and each kind of value still meets flags of every command. All three for every flag
// took 25 s under the sanitizers, a process each.
TEST(NumericFlags, EveryNumericFlagRefusesNanAndInfinityByNameWithItsRange) {
    const auto flags = numeric_flags();
    ASSERT_FALSE(flags.empty());
    for (size_t i = 0; i < flags.size(); ++i) {
        const NumericFlag& f = flags[i];
        std::vector<std::string> rest;
        for (const auto& [command, args] : commands())
            if (command == f.command) rest = args;
        for (const std::string& value : {std::string("nan"), std::string(i % 2 ? "inf" : "-1e999")}) {
            std::vector<std::string> args = {f.command, f.flag, value};
            args.insert(args.end(), rest.begin(), rest.end());
            auto r = crex_cli(args);
            const std::string where = f.command + " " + f.flag + " " + value + ": ";
            EXPECT_EQ(r.exit_code, 2) << where << r.err;
            // "crex run: error: --lw: 'nan' is not a number: expected a number from 0 to 1."
            EXPECT_NE(r.err.find("crex " + f.command + ": error: " + f.flag + ": '" + value + "' is "), std::string::npos) << where << r.err;
            EXPECT_TRUE(r.err.find("is not a number: expected a") != std::string::npos ||
                        r.err.find("is infinite: expected a") != std::string::npos)
                << where << r.err;
            EXPECT_NE(r.err.find(" from "), std::string::npos) << where << "no range: " << r.err;
        }
    }
}

// Out of range and malformed whole numbers say the range too: `--star-cap -1` said "Could not
// convert", `--seed 9007199254740993` is beyond what a seed holds exactly.
TEST(NumericFlags, WholeNumbersOutOfRangeSayTheRange) {
    struct Case {
        std::vector<std::string> args;
        std::string said;
    };
    for (const Case& c :
         {Case{{"run", "--star-cap", "-1"}, "--star-cap: '-1' is out of range: expected a whole number from 1 to 4294967295"},
          Case{{"run", "--seed", "9007199254740993"}, "--seed: '9007199254740993' is out of range: expected a whole number from 0 to "
                                                     "9007199254740992"},
          Case{{"run", "--spp", "1.5"}, "--spp: '1.5' is not a whole number: expected a whole number from 1 to 1048576"},
          Case{{"run", "--max-depth", "1e3"}, "--max-depth: '1e3' is not written in plain digits"},
          Case{{"run", "--lw", "2"}, "--lw: '2' is out of range: expected a number from 0 to 1"},
          Case{{"compare", "a.exr", "b.exr", "--ppd", "0.5"}, "--ppd: '0.5' is out of range: expected a number from 1 to 1000"}}) {
        auto r = crex_cli(c.args);
        EXPECT_EQ(r.exit_code, 2) << r.err;
        EXPECT_NE(r.err.find(c.said), std::string::npos) << r.err;
    }
}

}  // namespace
}  // namespace crex
