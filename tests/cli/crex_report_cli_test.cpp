// `crex reference` and `crex run --reference/--report`: the cache, checkpoints, error curve
// and report files (issue 8).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "runtime/io/image_io.h"
#include "tests/support/crex_cli.h"

namespace crex {
namespace {

namespace fs = std::filesystem;
using testing::crex_cli;

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

class ReportCli : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("crex_report_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
        ::setenv("CREX_CACHE", (dir_ / "cache").c_str(), 1);
    }
    void TearDown() override {
        ::unsetenv("CREX_CACHE");
        fs::remove_all(dir_);
    }
    std::string path(const std::string& f) const { return (dir_ / f).string(); }
    fs::path dir_;
};

TEST_F(ReportCli, ReferencesAreCachedByContentAndFoundByAuto) {
    auto first = crex_cli({"reference", "--size", "24x16", "--spp", "16", "-q"});
    ASSERT_EQ(first.exit_code, 0) << first.err;
    std::string ref = first.out.substr(0, first.out.find('\n'));
    EXPECT_TRUE(fs::exists(ref)) << ref;
    EXPECT_EQ(ref.find(path("cache/references/")), 0u) << ref;
    auto again = crex_cli({"reference", "--size", "24x16", "--spp", "16"});
    EXPECT_EQ(again.out, first.out);
    EXPECT_NE(again.err.find("cached"), std::string::npos) << again.err;
    // A different scene is a different key.
    auto other = crex_cli({"reference", "builtin:cornell_diffuse", "--size", "24x16", "--spp", "16", "-q"});
    EXPECT_NE(other.out, first.out);
    // auto finds it at the render's size, and says how to make one when there is none.
    auto run = crex_cli({"run", "--size", "24x16", "--spp", "2", "-o", path("r.exr"), "--reference", "auto", "--format", "json", "-q"});
    ASSERT_EQ(run.exit_code, 0) << run.err;
    auto j = nlohmann::json::parse(run.out);
    EXPECT_EQ(j["reference"], ref);
    ASSERT_GE(j["error_curve"].size(), 3u);
    auto none = crex_cli({"run", "--size", "20x16", "-o", path("r.exr"), "--reference", "auto", "-q"});
    EXPECT_EQ(none.exit_code, 3);
    EXPECT_NE(none.err.find("crex reference builtin:cornell --size 20x16"), std::string::npos) << none.err;
    auto wrong_size = crex_cli({"run", "--size", "20x16", "-o", path("r.exr"), "--reference", ref, "-q"});
    EXPECT_EQ(wrong_size.exit_code, 1);
}

TEST_F(ReportCli, TheReportHoldsCheckpointsAFallingCurveAndThePage) {
    ASSERT_EQ(crex_cli({"reference", "--size", "32x32", "--spp", "64", "-q"}).exit_code, 0);
    auto r = crex_cli({"run", "--size", "32x32", "--spp", "4", "-o", path("r.exr"), "--reference", "auto", "--report", path("rep"),
                       "--budget", "30s", "--checkpoint-interval", "0.01", "--format", "json", "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const char* f : {"index.html", "checkpoints.json", "checkpoints.csv", "error_plot.svg", "plan.dot", "images/final_image.png",
                          "images/reference.png", "images/component_D.png"})
        EXPECT_TRUE(fs::exists(dir_ / "rep" / f)) << f;
    auto j = nlohmann::json::parse(slurp(dir_ / "rep" / "checkpoints.json"));
    const auto& cps = j["checkpoints"];
    ASSERT_GE(cps.size(), 3u);
    // Time only grows; the error at the end is far below the first checkpoint's.
    for (size_t i = 1; i < cps.size(); ++i) EXPECT_GE(cps[i]["seconds"].get<double>(), cps[i - 1]["seconds"].get<double>());
    EXPECT_LT(cps.back()["flip"].get<double>(), 0.6 * cps.front()["flip"].get<double>());
    EXPECT_LT(cps.back()["rmse"].get<double>(), cps.front()["rmse"].get<double>());
    EXPECT_EQ(cps.back()["event"], "end of render");
    EXPECT_EQ(j["budget_seconds"], 30);
    // CSV: a header and one row per checkpoint.
    std::string csv = slurp(dir_ / "rep" / "checkpoints.csv");
    EXPECT_EQ(csv.rfind("seconds,stage,event,rays,rmse,relmse,flip,perr,ssim\n", 0), 0u);
    EXPECT_EQ(static_cast<size_t>(std::count(csv.begin(), csv.end(), '\n')), cps.size() + 1);
    // The plot: one curve per metric, the budget line, a stage boundary.
    std::string svg = slurp(dir_ / "rep" / "error_plot.svg");
    size_t curves = 0;
    for (size_t at = svg.find("class=\"curve\""); at != std::string::npos; at = svg.find("class=\"curve\"", at + 1)) ++curves;
    EXPECT_EQ(curves, 5u);
    EXPECT_NE(svg.find("id=\"budget\""), std::string::npos);
    EXPECT_NE(svg.find("class=\"stage\""), std::string::npos);
    // The page is self-contained: no file references, images inline.
    std::string html = slurp(dir_ / "rep" / "index.html");
    EXPECT_EQ(html.find("src=\"images/"), std::string::npos);
    EXPECT_NE(html.find("data:image/png;base64,"), std::string::npos);
    EXPECT_NE(html.find("id=\"error-plot\""), std::string::npos);
    // Each component's caption gives its share of the image's light; with every component
    // shown (none stood in), the shares add up to the whole image (one decimal each).
    double total = 0;
    size_t components = 0;
    for (size_t at = html.find("<figcaption>component "); at != std::string::npos; at = html.find("<figcaption>component ", at + 1)) {
        const size_t colon = html.find(": ", at), end = html.find(" % of the image's light</figcaption>", at);
        ASSERT_NE(end, std::string::npos) << html.substr(at, 80);
        ASSERT_LT(colon, end);
        const std::string number = html.substr(colon + 2, end - colon - 2);
        if (number != "under 0.1") total += std::stod(number);
        ++components;
    }
    EXPECT_GE(components, 2u);
    EXPECT_NEAR(total, 100.0, 0.1 * static_cast<double>(components));
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(CyclicReportCli, TheRoundsOfTheCyclicPipelineShowInThePlanAndTheErrorCurve) {
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("crex_cyclic_report_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string pipe = CREX_SOURCE_DIR "/stdlib/pipelines/adaptive.pipe";
    const int rounds = 3;  // adaptive.pipe's `rounds 3`
    auto json = testing::crex_cli({"plan", pipe, "--format", "json"});
    ASSERT_EQ(json.exit_code, 0) << json.err;
    EXPECT_EQ(nlohmann::json::parse(json.out)["settings"]["rounds"], rounds);
    auto dot = testing::crex_cli({"plan", pipe, "--format", "dot"});
    EXPECT_NE(dot.out.find("rounds: " + std::to_string(rounds)), std::string::npos) << dot.out;
    // A reference of the same size, then the report: its checkpoints name every round.
    auto ref = testing::crex_cli({"run", "--size", "24x16", "--spp", "64", "-o", (dir / "ref.exr").string(), "-q"});
    ASSERT_EQ(ref.exit_code, 0) << ref.err;
    auto r = testing::crex_cli({"run", pipe, "--size", "24x16", "-o", (dir / "a.exr").string(), "--reference", (dir / "ref.exr").string(),
                                "--report", (dir / "rep").string(), "--checkpoint-interval", "0.0001", "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream in(dir / "rep" / "checkpoints.json");
    auto j = nlohmann::json::parse(in);
    std::string events;
    for (const auto& c : j["checkpoints"]) events += c["event"].get<std::string>() + "\n";
    for (int round = 1; round <= rounds; ++round)
        EXPECT_NE(events.find(fmt::format("end of guidance (round {}/{})", round, rounds)), std::string::npos) << events;
    // Inside a round the image only gets better: a checkpoint mid-pass shows a pixel whose new
    // samples still have rays waiting as it was when the pass began (once, every pass's new
    // samples counted black until their rays ran, and the curve jumped up at each pass).
    double at_round_start = 1e9;
    for (const auto& c : j["checkpoints"]) {
        const std::string event = c["event"];
        if (event.rfind("end of guidance", 0) == 0) at_round_start = c["rmse"];
        if (c["stage"] == "selective") {
            EXPECT_LE(c["rmse"].get<double>(), 1.05 * at_round_start) << event;
        }
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(ReferenceCli, AnExistingOutputIsReusedOnlyWhenItIsThisReference) {
    // `crex reference -o EXISTING` took any existing file as the cached reference (even
    // /etc/hostname, or a 64x64 image for a 16x16 request of another scene).
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("crex_reference_o_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string out = (dir / "ref.exr").string();
    std::ofstream(out) << "not an image\n";
    auto r = testing::crex_cli({"reference", "--size", "16x16", "--spp", "4", "-o", out});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.find("cached"), std::string::npos) << r.err;  // rendered, not taken
    int w = 0, h = 0;
    std::vector<float> rgb;
    ASSERT_EQ(read_image(out, w, h, rgb), "");
    EXPECT_EQ(w, 16);
    // The same request again: cached. Another scene or size: rendered again.
    auto again = testing::crex_cli({"reference", "--size", "16x16", "--spp", "4", "-o", out});
    EXPECT_NE(again.err.find("cached"), std::string::npos) << again.err;
    auto other = testing::crex_cli({"reference", "builtin:cornell_diffuse", "--size", "16x16", "--spp", "4", "-o", out});
    EXPECT_EQ(other.err.find("cached"), std::string::npos) << other.err;
    auto size = testing::crex_cli({"reference", "builtin:cornell_diffuse", "--size", "8x8", "--spp", "4", "-o", out});
    EXPECT_EQ(size.err.find("cached"), std::string::npos) << size.err;
    ASSERT_EQ(read_image(out, w, h, rgb), "");
    EXPECT_EQ(w, 8);
    fs::remove_all(dir);
}

// A stage of many samples goes in progressive passes (issue 38): sel_rp's selective stage (up
// to 16 spp a pixel) improves as it runs. In one pass its curve stayed flat until the pass
// ended; now half the stage has brought a good part of its fall (measured: two thirds).
// Checkpoints as close as their own cost allows (--checkpoint-interval 0.002): at 48x48 one
// takes about 2.4 ms to copy and score, and the stage about 50 ms in Release.
TEST_F(ReportCli, ThePipelinesErrorFallsThroughItsSelectiveStage) {
    ASSERT_EQ(crex_cli({"run", "--size", "48x48", "--spp", "64", "-o", path("ref.exr"), "-q"}).exit_code, 0);
    auto r = crex_cli({"run", CREX_SOURCE_DIR "/stdlib/pipelines/sel_rp.pipe", "--size", "48x48", "--reference", path("ref.exr"),
                       "--report", path("rep"), "--checkpoint-interval", "0.002", "-o", path("a.exr"), "-q", "--format", "json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_GE(nlohmann::json::parse(r.out)["passes"].get<size_t>(), 4u);  // one pass a new sample index, not one for the stage
    std::ifstream in(dir_ / "rep" / "checkpoints.json");
    const auto j = nlohmann::json::parse(in);
    std::vector<nlohmann::json> selective;
    for (const auto& c : j["checkpoints"])
        if (c["stage"] == "selective") selective.push_back(c);
    ASSERT_GE(selective.size(), 4u);
    const double t0 = selective.front()["seconds"], t1 = selective.back()["seconds"];
    const auto mid = *std::min_element(selective.begin(), selective.end(), [&](const auto& a, const auto& b) {
        return std::fabs(a["seconds"].template get<double>() - (t0 + t1) / 2) < std::fabs(b["seconds"].template get<double>() - (t0 + t1) / 2);
    });
    const double first = selective.front()["rmse"], middle = mid["rmse"], last = selective.back()["rmse"];
    ASSERT_LT(last, first);
    EXPECT_LT(middle, first - 0.25 * (first - last)) << first << " " << middle << " " << last;
}

// --equal-time (issue 38): uniform rendering gets the pipeline's render time, both are scored
// against the reference with the pipeline's task map as attention, and the report shows the pair.
TEST_F(ReportCli, EqualTimeScoresThePipelineBesideUniformRendering) {
    const std::string scene = CREX_SOURCE_DIR "/examples/scenes/corridor/scene.json";
    const std::string pipe = CREX_SOURCE_DIR "/stdlib/pipelines/sel_task.pipe";
    ASSERT_EQ(crex_cli({"run", "--scene", scene, "--size", "40x24", "--spp", "64", "-o", path("ref.exr"), "-q"}).exit_code, 0);
    auto r = crex_cli({"run", pipe, "--scene", scene, "--size", "40x24", "--no-budget", "--reference", path("ref.exr"), "--equal-time",
                       "--report", path("rep"), "-o", path("sel.exr"), "--format", "json", "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.contains("equal_time")) << r.out.substr(0, 400);
    const auto& e = j["equal_time"];
    EXPECT_EQ(e["seconds"].get<double>(), j["render_seconds"].get<double>());  // the budget is the pipeline's time
    EXPECT_NE(e["attention"].get<std::string>().find("task map 'task'"), std::string::npos) << e.dump();
    // The pipeline's figure is its final image's: the error curve ends on it.
    EXPECT_DOUBLE_EQ(e["pipeline"]["flip"].get<double>(), j["error_curve"].back()["flip"].get<double>());
    EXPECT_GE(e["uniform"]["spp"]["min"].get<int>(), 1);
    // The task pipeline spends its samples where the task map is high, uniform rendering does
    // not: measured with the task map's weights, the pipeline's error shrinks against its plain
    // FLIP much more than uniform rendering's (measured ratios: 0.51 against 0.93).
    const double pipeline_ratio = e["pipeline"]["aflip"].get<double>() / e["pipeline"]["flip"].get<double>();
    const double uniform_ratio = e["uniform"]["aflip"].get<double>() / e["uniform"]["flip"].get<double>();
    EXPECT_LT(pipeline_ratio, 0.8 * uniform_ratio) << e.dump();
    for (const char* png : {"equal_time_pipeline.png", "equal_time_uniform.png", "equal_time_pipeline_flip.png", "equal_time_uniform_flip.png"})
        EXPECT_TRUE(fs::exists(dir_ / "rep" / "images" / png)) << png;
    EXPECT_NE(slurp(dir_ / "rep" / "index.html").find("Equal time: the pipeline beside uniform rendering"), std::string::npos);
    // Nothing to compare against, or nothing selective to compare: usage errors, before rendering.
    auto no_reference = crex_cli({"run", pipe, "--scene", scene, "--size", "40x24", "--equal-time", "-o", path("x.exr"), "-q"});
    EXPECT_EQ(no_reference.exit_code, 2);
    EXPECT_NE(no_reference.err.find("--equal-time needs a pipeline"), std::string::npos) << no_reference.err;
    auto plain = crex_cli({"run", "--scene", scene, "--size", "40x24", "--reference", path("ref.exr"), "--equal-time", "-o", path("y.exr"), "-q"});
    EXPECT_EQ(plain.exit_code, 2);
    EXPECT_FALSE(fs::exists(path("x.exr")) || fs::exists(path("y.exr")));
}

// A budgeted run's report with --compare-policies: the same render under every policy, all
// their errors against time on one plot (issue 15).
TEST(PolicyReportCli, EveryPolicyOnOnePlot) {
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("crex_policy_report_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    auto ref = testing::crex_cli({"run", "--size", "24x16", "--spp", "64", "-o", (dir / "ref.exr").string(), "-q"});
    ASSERT_EQ(ref.exit_code, 0) << ref.err;
    auto r = testing::crex_cli({"run", "-e", "(TT[RS]GMD)*", "--size", "24x16", "--spp", "16", "--budget", "50ms", "--reference",
                                (dir / "ref.exr").string(), "--report", (dir / "rep").string(), "--compare-policies", "-o",
                                (dir / "a.exr").string(), "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream in(dir / "rep" / "checkpoints.json");
    auto j = nlohmann::json::parse(in);
    ASSERT_TRUE(j.contains("policies")) << j.dump().substr(0, 300);
    for (const char* policy : {"tasks", "batches", "queues", "progressive"}) {
        ASSERT_TRUE(j["policies"].contains(policy)) << policy;
        EXPECT_GE(j["policies"][policy].size(), 2u) << policy;
    }
    std::ifstream svg_in(dir / "rep" / "policies_plot.svg");
    std::string svg((std::istreambuf_iterator<char>(svg_in)), {});
    size_t curves = 0;
    for (size_t at = svg.find("class=\"curve\""); at != std::string::npos; at = svg.find("class=\"curve\"", at + 1)) ++curves;
    EXPECT_EQ(curves, 4u);
    // Without a budget there is nothing to compare: a usage error.
    auto no_budget = testing::crex_cli({"run", "--size", "24x16", "--reference", (dir / "ref.exr").string(), "--compare-policies",
                                        "-o", (dir / "b.exr").string(), "-q"});
    EXPECT_EQ(no_budget.exit_code, 2);
    EXPECT_NE(no_budget.err.find("--compare-policies needs a budget"), std::string::npos) << no_budget.err;
    fs::remove_all(dir);
}

}  // namespace
}  // namespace crex
