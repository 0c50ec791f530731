// Stdlib pipelines by their names alone (`crex run sel_rp`), wherever crex is installed: run,
// plan and check take them as they take the files, and a name that is neither says what is.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/support/crex_cli.h"
#include "tests/support/scratch_folder.h"

namespace crex {
namespace {

using testing::crex_cli;

bool says(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class CrexStdlibNamesCli : public testing::ScratchFolderTest {
protected:
    CrexStdlibNamesCli() : ScratchFolderTest("crex_stdlib_names_cli_") {}
};

TEST_F(CrexStdlibNamesCli, RunPlanAndCheckTakeAStdlibPipelineByName) {
    auto run = crex_cli({"run", "sel_rp", "--scene", "builtin:cornell", "--size", "8x8", "-o", path("a.exr"), "-q"});
    EXPECT_EQ(run.exit_code, 0) << run.err;
    EXPECT_TRUE(std::filesystem::exists(path("a.exr")));
    auto plan = crex_cli({"plan", "prog_all", "--format", "json"});
    EXPECT_EQ(plan.exit_code, 0) << plan.err;
    EXPECT_TRUE(says(plan.out, "\"prog_all\"")) << plan.out.substr(0, 400);
    auto check = crex_cli({"check", "sel_quiet"});
    EXPECT_EQ(check.exit_code, 0) << check.err;
    EXPECT_TRUE(says(check.out, "ok: pipeline sel_quiet")) << check.out;
}

TEST_F(CrexStdlibNamesCli, ANameThatIsNeitherAFileNorAStdlibPipelineSaysTheNearest) {
    for (const std::string command : {"run", "plan", "check"}) {
        auto r = crex_cli({command, "sel_quite"});
        EXPECT_EQ(r.exit_code, 3) << command << ": " << r.err;
        EXPECT_TRUE(says(r.err, "cannot read 'sel_quite'")) << r.err;
        EXPECT_TRUE(says(r.err, "crex " + command + ": error: cannot read 'sel_quite': No such file or directory; nor is it a stdlib "
                                "pipeline (did you mean 'sel_quiet'?); the stdlib's, in ")) << r.err;
        EXPECT_TRUE(says(r.err, "prog_all, prog_dis_all")) << r.err;
    }
}

TEST_F(CrexStdlibNamesCli, RunHelpListsTheStdlibPipelines) {
    auto r = crex_cli({"run", "--help"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_TRUE(says(r.out, "A stdlib pipeline runs by its name alone")) << r.out;
    for (const char* name : {"prog_all", "sel_quiet", "capict", "tpict"}) EXPECT_TRUE(says(r.out, name)) << name;
}

}  // namespace
}  // namespace crex
