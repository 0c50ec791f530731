// A command's pipeline argument: a stdlib pipeline by its name alone, a file of the name first.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "compiler/pipeline/stdlib_pipelines.h"
#include "tests/support/scratch_folder.h"

namespace crex::pipeline {
namespace {

namespace fs = std::filesystem;

// A stdlib of two pipelines (and a file that is none) in $CREX_STDLIB, run from an empty folder.
class StdlibPipelines : public testing::ScratchFolderTest {
protected:
    StdlibPipelines() : ScratchFolderTest("crex_stdlib_names_") {}
    void SetUp() override {
        ScratchFolderTest::SetUp();
        fs::create_directories(dir_ / "lib" / "pipelines");
        fs::create_directories(dir_ / "work");
        for (const std::string name : {"sel_quiet", "prog_all"})
            std::ofstream(dir_ / "lib" / "pipelines" / (name + ".pipe")) << "pipeline " << name << " {\n}\n";
        std::ofstream(dir_ / "lib" / "pipelines" / "notes.txt") << "not a pipeline\n";
        ::setenv("CREX_STDLIB", (dir_ / "lib").c_str(), 1);
        was_ = fs::current_path();
        fs::current_path(dir_ / "work");
    }
    void TearDown() override {
        fs::current_path(was_);
        ::unsetenv("CREX_STDLIB");
        ScratchFolderTest::TearDown();
    }
    fs::path was_;
};

TEST_F(StdlibPipelines, TheNamesAreThePipelineFilesSorted) {
    EXPECT_EQ(stdlib_pipeline_names(), (std::vector<std::string>{"prog_all", "sel_quiet"}));
}

TEST_F(StdlibPipelines, ABareNameIsTheStdlibFile) {
    const PipelineArgument a = pipeline_argument("sel_quiet");
    EXPECT_TRUE(a.stdlib);
    EXPECT_EQ(fs::path(a.path), dir_ / "lib" / "pipelines" / "sel_quiet.pipe");
    EXPECT_EQ(a.hint, "");
}

TEST_F(StdlibPipelines, AFileOfTheNameInTheWorkingFolderComesFirst) {
    std::ofstream("sel_quiet") << "pipeline mine {\n}\n";
    const PipelineArgument a = pipeline_argument("sel_quiet");
    EXPECT_FALSE(a.stdlib);
    EXPECT_EQ(a.path, "sel_quiet");
}

TEST_F(StdlibPipelines, PathsAndCrexAreLeftAsGiven) {
    for (const std::string arg : {"x/sel_quiet", "sel_quiet.pipe", "./sel_quiet", "-", "(TTMRSGD)*", "TT{D}", "2D"}) {
        const PipelineArgument a = pipeline_argument(arg);
        EXPECT_FALSE(a.stdlib) << arg;
        EXPECT_EQ(a.path, arg);
        EXPECT_EQ(a.hint, "") << arg;
    }
}

TEST_F(StdlibPipelines, AnUnknownNameSaysWhatTheStdlibHas) {
    const PipelineArgument a = pipeline_argument("sel_quite");
    EXPECT_FALSE(a.stdlib);
    EXPECT_EQ(a.path, "sel_quite");
    EXPECT_NE(a.hint.find("did you mean 'sel_quiet'?"), std::string::npos) << a.hint;
    EXPECT_NE(a.hint.find("pipelines: prog_all, sel_quiet"), std::string::npos) << a.hint;
    EXPECT_EQ(pipeline_argument("zzz").hint.find("did you mean"), std::string::npos);  // nothing close: the list alone
}

}  // namespace
}  // namespace crex::pipeline
