// The report page of the built-in Cornell box, opened in headless Chromium (Debian's
// `chromium`): every image decodes, the plot draws its curves, and the error falls (issue 8).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "tests/support/crex_cli.h"

namespace crex {
namespace {

namespace fs = std::filesystem;

int body_attribute(const std::string& dom, const std::string& name) {
    std::smatch m;
    if (!std::regex_search(dom, m, std::regex(name + "=\"([0-9]+)\""))) return -1;
    return std::stoi(m[1]);
}

// The page's DOM after its script ran, as headless Chromium leaves it (profile under `dir`).
testing::CommandResult dump_dom(const fs::path& dir, const fs::path& page) {
    return testing::run_command({"/usr/bin/chromium", "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                                 "--user-data-dir=" + (dir / "chromium").string(), "--virtual-time-budget=10000", "--dump-dom",
                                 "file://" + page.string()});
}

TEST(ReportPage, OpensInChromiumWithEveryImageAndAFallingPlot) {
    ASSERT_TRUE(fs::exists("/usr/bin/chromium")) << "the page test needs Debian's chromium (tools/debian-packages.txt)";
    fs::path dir = fs::temp_directory_path() / ("crex_page_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    ::setenv("CREX_CACHE", (dir / "cache").c_str(), 1);
    ASSERT_EQ(testing::crex_cli({"reference", "--size", "48x48", "--spp", "64", "-q"}).exit_code, 0);
    auto run = testing::crex_cli({"run", CREX_SOURCE_DIR "/stdlib/pipelines/sel_rp.pipe", "--size", "48x48", "-o",
                                  (dir / "r.exr").string(), "--reference", "auto", "--report", (dir / "report").string(),
                                  "--maps", (dir / "maps").string(), "-q"});
    ASSERT_EQ(run.exit_code, 0) << run.err;
    auto page = dump_dom(dir, dir / "report" / "index.html");
    ASSERT_EQ(page.exit_code, 0) << page.err;
    EXPECT_NE(page.out.find("data-ready=\"yes\""), std::string::npos) << page.out.substr(0, 400);
    int total = body_attribute(page.out, "data-images-total"), loaded = body_attribute(page.out, "data-images-loaded");
    // final, preview, reference, the 5 components that got rays (no G or S bin in the Cornell
    // box: left out, not shown as black tiles), the FLIP map against the reference, the
    // saliency map, and the three heat pictures of --maps (samples, rays, components per pixel).
    EXPECT_EQ(total, 13);
    EXPECT_EQ(loaded, total);
    EXPECT_EQ(body_attribute(page.out, "data-images-blank"), 0);  // no picture of one colour
    EXPECT_EQ(body_attribute(page.out, "data-plot-overlaps"), 0);  // no label over another
    // A colour bar under every picture of numbers: the FLIP map, the map, the heat pictures.
    EXPECT_EQ(body_attribute(page.out, "data-colour-bars"), 5);
    EXPECT_EQ(body_attribute(page.out, "data-plot-curves"), 5);
    EXPECT_GT(body_attribute(page.out, "data-plot-width"), 100);
    // The curve the plot draws falls: the last checkpoint's FLIP is well below the first.
    std::ifstream in(dir / "report" / "checkpoints.json");
    auto j = nlohmann::json::parse(in);
    EXPECT_LT(j["checkpoints"].back()["flip"].get<double>(), 0.6 * j["checkpoints"].front()["flip"].get<double>());
    ::unsetenv("CREX_CACHE");
    fs::remove_all(dir);
}

// A sequence's page (issue 36): every frame of its strip decodes and none is blank; the three
// plots over frames draw their lines (time: whole frame and render; flicker; records) with no
// label over another.
TEST(ReportPage, ASequencesPageShowsItsFramesAndPlots) {
    ASSERT_TRUE(fs::exists("/usr/bin/chromium")) << "the page test needs Debian's chromium (tools/debian-packages.txt)";
    fs::path dir = fs::temp_directory_path() / ("crex_sequence_page_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / "walk.json") << R"({"keys": [
        {"time": 0, "position": [0, 1.6, 9.5], "look_at": [0, 1.4, 0]},
        {"time": 1, "position": [0, 1.6, 3.5], "look_at": [0, 1.4, -6]}]})";
    auto run = testing::crex_cli({"run", "--scene", CREX_SOURCE_DIR "/examples/scenes/corridor/scene.json", "--ic", "--size", "48x32",
                                  "--spp", "2", "--camera-path", (dir / "walk.json").string(), "--frames", "0..4", "-o",
                                  (dir / "w.png").string(), "--report", (dir / "report").string(), "-q"});
    ASSERT_EQ(run.exit_code, 0) << run.err;
    auto page = dump_dom(dir, dir / "report" / "index.html");
    ASSERT_EQ(page.exit_code, 0) << page.err;
    EXPECT_NE(page.out.find("data-ready=\"yes\""), std::string::npos) << page.out.substr(0, 400);
    EXPECT_EQ(body_attribute(page.out, "data-images-total"), 5);
    EXPECT_EQ(body_attribute(page.out, "data-images-loaded"), 5);
    EXPECT_EQ(body_attribute(page.out, "data-images-blank"), 0);
    EXPECT_EQ(body_attribute(page.out, "data-plots"), 3);
    EXPECT_EQ(body_attribute(page.out, "data-plots-curves"), 4);
    EXPECT_EQ(body_attribute(page.out, "data-plot-overlaps"), 0);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace crex
