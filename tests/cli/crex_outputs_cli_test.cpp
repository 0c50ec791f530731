// Outputs as users expect them (issue 38): a plan drawn in the format its file name says.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "runtime/io/image_io.h"
#include "tests/support/crex_cli.h"
#include "tests/support/scratch_folder.h"

namespace crex {
namespace {

namespace fs = std::filesystem;
using testing::crex_cli;

class OutputsCli : public testing::ScratchFolderTest {
protected:
    OutputsCli() : ScratchFolderTest("crex_outputs_") {}
    std::string read(const std::string& file) const {
        std::ifstream in(file, std::ios::binary);
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    }
};

TEST_F(OutputsCli, APlansFormatFollowsTheExtensionOfItsFile) {
    for (const char* name : {"p.svg", "p.png", "p.json", "p.dot", "p.txt"})
        ASSERT_EQ(crex_cli({"plan", "-e", "TT{D}", "-o", path(name)}).exit_code, 0) << name;
    EXPECT_NE(read(path("p.svg")).find("<svg"), std::string::npos);  // drawn by Graphviz, not the text plan
    int w = 0, h = 0;
    std::vector<float> rgb;
    ASSERT_EQ(read_image(path("p.png"), w, h, rgb), "");
    EXPECT_GT(w, 64);
    EXPECT_GT(h, 32);
    EXPECT_EQ(nlohmann::json::parse(read(path("p.json")))["crex"]["source"], "TT{D}");
    EXPECT_EQ(read(path("p.dot")).rfind("digraph", 0), 0u);
    EXPECT_EQ(read(path("p.txt")).rfind("plan of TT{D}", 0), 0u) << read(path("p.txt"));
    // --format alone still writes to stdout.
    auto svg = crex_cli({"plan", "-e", "TT", "--format", "svg"});
    EXPECT_EQ(svg.exit_code, 0) << svg.err;
    EXPECT_NE(svg.out.find("</svg>"), std::string::npos);
}

TEST_F(OutputsCli, AFormatTheFileNameContradictsIsAUsageError) {
    auto r = crex_cli({"plan", "-e", "TT", "--format", "text", "-o", path("p.svg")});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--format text and -o " + path("p.svg") + " disagree"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("p.svg")));
    // A name that says no format takes the one given.
    EXPECT_EQ(crex_cli({"plan", "-e", "TT", "--format", "json", "-o", path("plan.out")}).exit_code, 0);
    EXPECT_EQ(nlohmann::json::parse(read(path("plan.out")))["crex"]["source"], "TT");
}

}  // namespace
}  // namespace crex
