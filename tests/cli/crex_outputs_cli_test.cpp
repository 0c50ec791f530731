// Outputs as users expect them (issue 38): a plan drawn in the format its file name says, a
// pipeline's `output` block written like -o (several images, component layers), report folders
// replaced whole, and a folder the user typed that does not exist said before anything renders.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "runtime/render/film.h"
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
    // A 16x16 pipeline on the built-in box whose output block is `output`.
    std::string pipeline(const std::string& output) const {
        const std::string file = path("p.pipe");
        std::ofstream(file) << "pipeline tiny {\n  scene \"builtin:cornell\"\n  image 16 x 16\n  seed 3\n"
                               "  preselective { crex \"TT\" spp 1 }\n  guidance { sal = saliency(preview) }\n"
                               "  selective { crex \"{TT}\" by sal  vary spp 1 .. 2 by sal }\n  output { "
                            << output << " }\n}\n";
        return file;
    }
    std::string quoted(const std::string& name) const { return "\"" + path(name) + "\""; }
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

TEST_F(OutputsCli, AnOutputBlocksComponentsGiveTheComponentLayers) {
    auto r = crex_cli({"run", pipeline("image " + quoted("c.exr") + " components true"), "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    int w = 0, h = 0;
    std::vector<float> rgb;
    for (size_t a = 0; a < kAovCount; ++a) EXPECT_EQ(read_image_layer(path("c.exr"), aov_name(a), w, h, rgb), "") << aov_name(a);
    // Without it, the composite only.
    ASSERT_EQ(crex_cli({"run", pipeline("image " + quoted("plain.exr")), "-q"}).exit_code, 0);
    EXPECT_NE(read_image_layer(path("plain.exr"), "D", w, h, rgb), "");
}

TEST_F(OutputsCli, AnOutputBlockWritesPngAndHdrAsMinusODoes) {
    const std::string pipe = pipeline("image " + quoted("a.exr") + " " + quoted("a.png") + " " + quoted("a.hdr"));
    auto r = crex_cli({"run", pipe, "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto o = crex_cli({"run", pipe, "-q", "-o", path("b.png"), "-o", path("b.hdr")});  // flags replace the block's images
    ASSERT_EQ(o.exit_code, 0) << o.err;
    int w = 0, h = 0;
    std::vector<float> a, b;
    bool display = false;
    ASSERT_EQ(read_image(path("a.png"), w, h, a, &display), "");
    ASSERT_EQ(read_image(path("b.png"), w, h, b), "");
    EXPECT_TRUE(display);  // tone-mapped 8-bit
    EXPECT_EQ(a, b);       // the same seed: the same picture (the headers differ in the render time)
    ASSERT_EQ(read_image(path("a.hdr"), w, h, a), "");
    ASSERT_EQ(read_image(path("b.hdr"), w, h, b), "");
    EXPECT_EQ(w, 16);
    EXPECT_EQ(a, b);
    ASSERT_EQ(read_image(path("a.exr"), w, h, a), "");
    // The plan lists every image; a name no writer takes is said at its place in the file.
    auto plan = crex_cli({"plan", pipe, "--format", "json"});
    ASSERT_EQ(plan.exit_code, 0) << plan.err;
    EXPECT_EQ(nlohmann::json::parse(plan.out)["outputs"]["images"].size(), 3u);
    auto bad = crex_cli({"check", pipeline("image " + quoted("a.exr") + " " + quoted("a.txt"))});
    EXPECT_EQ(bad.exit_code, 1);
    EXPECT_NE(bad.err.find("p.pipe:8:"), std::string::npos) << bad.err;
    EXPECT_NE(bad.err.find("error[E203]: image: unknown image format '.txt'"), std::string::npos) << bad.err;
}

TEST_F(OutputsCli, AReportReplacesItsFolderWhole) {
    const std::vector<std::string> run = {"run", "--size", "8x8", "--spp", "1", "-q", "-o", path("x.exr"), "--report", path("rep")};
    ASSERT_EQ(crex_cli(run).exit_code, 0);
    std::ofstream(path("rep/images/stale.png")) << "a picture of an earlier run";
    auto again = crex_cli(run);
    ASSERT_EQ(again.exit_code, 0) << again.err;
    EXPECT_FALSE(fs::exists(path("rep/images/stale.png")));
    EXPECT_TRUE(fs::exists(path("rep/images/final_image.png")));
    for (const auto& e : fs::directory_iterator(dir_)) EXPECT_EQ(e.path().filename().string().find(".rep.crex-staged"), std::string::npos);
    // An empty folder may become a report.
    fs::create_directories(path("empty"));
    EXPECT_EQ(crex_cli({"run", "--size", "8x8", "--spp", "1", "-q", "-o", path("x.exr"), "--report", path("empty")}).exit_code, 0);
    EXPECT_TRUE(fs::exists(path("empty/index.html")));
}

TEST_F(OutputsCli, AFolderThatIsNotAReportIsRefusedAndLeftAlone) {
    fs::create_directories(path("mine"));
    std::ofstream(path("mine/notes.txt")) << "mine";
    auto r = crex_cli({"run", "--size", "8x8", "--spp", "1", "-q", "-o", path("x.exr"), "--report", path("mine")});
    EXPECT_EQ(r.exit_code, 3);
    EXPECT_NE(r.err.find("--report " + path("mine") + ": the folder exists and is not a crex report"), std::string::npos) << r.err;
    EXPECT_EQ(read(path("mine/notes.txt")), "mine");
    EXPECT_FALSE(fs::exists(path("mine/index.html")));
    EXPECT_FALSE(fs::exists(path("x.exr")));  // refused before rendering
}

TEST_F(OutputsCli, AMissingFolderInATypedPathIsAnErrorBeforeRendering) {
    const std::string missing = path("no/such");
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"-o", missing + "/x.exr"}, missing + "/x.exr"},
        {{"-o", path("x.exr"), "--maps", missing + "/maps"}, missing + "/maps"},
        {{"-o", path("x.exr"), "--report", missing + "/rep"}, missing + "/rep"},
        {{"-o", path("x.exr"), "--save-profile", missing + "/p.json"}, missing + "/p.json"},
    };
    for (const auto& [flags, written] : cases) {
        std::vector<std::string> args = {"run", "--size", "8x8", "--spp", "1"};
        args.insert(args.end(), flags.begin(), flags.end());
        auto r = crex_cli(args);
        EXPECT_EQ(r.exit_code, 3) << flags[0];
        EXPECT_NE(r.err.find("crex run: error: cannot write '" + written + "': its folder '" + missing + "' does not exist"),
                  std::string::npos)
            << r.err;
        EXPECT_EQ(r.out, "");  // nothing rendered
    }
    auto plan = crex_cli({"plan", "-e", "TT", "-o", missing + "/p.json"});
    EXPECT_EQ(plan.exit_code, 3);
    EXPECT_NE(plan.err.find("crex plan: error: cannot write '" + missing + "/p.json': its folder"), std::string::npos) << plan.err;
    EXPECT_FALSE(fs::exists(path("no")));
    EXPECT_FALSE(fs::exists(path("x.exr")));
    // A pipeline's own paths are its defaults: their folders are made, as out/ is for out/render.exr.
    auto piped = crex_cli({"run", pipeline("image " + quoted("made/x.exr") + " report " + quoted("made/rep")), "-q"});
    EXPECT_EQ(piped.exit_code, 0) << piped.err;
    EXPECT_TRUE(fs::exists(path("made/x.exr")));
    EXPECT_TRUE(fs::exists(path("made/rep/index.html")));
    auto plain = testing::run_command({"/bin/sh", "-c", "cd '" + dir_.string() + "' && exec " CREX_BINARY " run --size 8x8 --spp 1 -q"});
    EXPECT_EQ(plain.exit_code, 0) << plain.err;
    EXPECT_TRUE(fs::exists(path("out/render.exr")));
    EXPECT_TRUE(fs::exists(path("out/render.png")));
}

}  // namespace
}  // namespace crex
