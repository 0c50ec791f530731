// `crex compare` as a user runs it: metrics as JSON, exit codes, the FLIP picture.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "runtime/io/image_io.h"
#include "tests/support/crex_cli.h"
#include "tests/support/float_map.h"

namespace crex {
namespace {

namespace fs = std::filesystem;
using testing::crex_cli;

class CompareCli : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("crex_compare_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
        std::vector<float> a(3 * 16 * 12, 0.25f), b = a;
        b[0] = 1.25f;  // one channel of one pixel brighter by 1
        ASSERT_EQ(write_image(path("a.exr"), 16, 12, {{"", a}}), "");
        ASSERT_EQ(write_image(path("b.exr"), 16, 12, {{"", b}}), "");
        ASSERT_EQ(write_image(path("small.exr"), 8, 8, {{"", std::vector<float>(3 * 64, 0.25f)}}), "");
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& f) const { return (dir_ / f).string(); }
    fs::path dir_;
};

TEST_F(CompareCli, MetricsAsJson) {
    auto same = crex_cli({"compare", path("a.exr"), path("a.exr"), "--format", "json"});
    ASSERT_EQ(same.exit_code, 0) << same.err;
    auto j = nlohmann::json::parse(same.out);
    EXPECT_EQ(j["rmse"], 0.0);
    EXPECT_EQ(j["flip"], 0.0);
    EXPECT_EQ(j["ssim"], 1.0);
    auto diff = crex_cli({"compare", path("b.exr"), path("a.exr"), "--format", "json", "--metric", "rmse,perr",
                          "--flip-map", path("flip.png")});
    ASSERT_EQ(diff.exit_code, 0) << diff.err;
    auto d = nlohmann::json::parse(diff.out);
    EXPECT_NEAR(d["rmse"].get<double>(), std::sqrt(1.0 / (3 * 16 * 12)), 1e-6);
    EXPECT_FALSE(d.contains("ssim"));  // only what was asked
    EXPECT_GT(d["perr"].get<double>(), 0.0);
    EXPECT_NE(d["display"].get<std::string>().find("HDR"), std::string::npos);  // EXR: the tone map is stated
    EXPECT_TRUE(fs::exists(path("flip.png")));
}

// The attention-weighted FLIP counts errors where the weights are: weight on the one changed
// pixel gives more than the plain mean, weight everywhere else less; no weight at all is an error.
TEST_F(CompareCli, AttentionWeightsTheFlipMap) {
    std::vector<float> at_change(3 * 16 * 12, 0.0f), elsewhere(3 * 16 * 12, 1.0f);
    for (int c = 0; c < 3; ++c) at_change[static_cast<size_t>(c)] = 1.0f, elsewhere[static_cast<size_t>(c)] = 0.0f;
    ASSERT_EQ(write_image(path("at_change.exr"), 16, 12, {{"", at_change}}), "");
    ASSERT_EQ(write_image(path("elsewhere.exr"), 16, 12, {{"", elsewhere}}), "");
    ASSERT_EQ(write_image(path("zero.exr"), 16, 12, {{"", std::vector<float>(3 * 16 * 12, 0.0f)}}), "");
    auto run = [&](const std::string& weights) {
        auto r = crex_cli({"compare", path("b.exr"), path("a.exr"), "--format", "json", "--metric", "flip", "--attention", weights});
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return nlohmann::json::parse(r.out);
    };
    auto on = run(path("at_change.exr")), off = run(path("elsewhere.exr")), sal = run("saliency");
    double flip = on["flip"].get<double>();
    EXPECT_GT(on["aflip"].get<double>(), 10 * flip);
    EXPECT_LT(off["aflip"].get<double>(), flip);
    EXPECT_NEAR(sal["aflip"].get<double>(), flip, 1e-9);  // a flat reference has no salient spot: plain FLIP
    auto zero = crex_cli({"compare", path("b.exr"), path("a.exr"), "--attention", path("zero.exr")});
    EXPECT_EQ(zero.exit_code, 1);
    EXPECT_NE(zero.err.find("zero everywhere"), std::string::npos);
    EXPECT_EQ(crex_cli({"compare", path("b.exr"), path("a.exr"), "--attention", path("small.exr")}).exit_code, 3);  // wrong size
}

// A weight that is negative or not finite is an error that names the first such pixel: until
// 2026-12-07 it was dropped from the weighted mean without a word. (A float map written by hand:
// crex's writer keeps images finite. PFM rows go bottom up: the file's first pixel is (0, 11).)
TEST_F(CompareCli, AttentionWeightsMustBeFiniteAndNotNegative) {
    for (const float bad : {std::nanf(""), -1.0f, INFINITY}) {
        std::vector<float> w(3 * 16 * 12, 1.0f);
        w[0] = bad;
        testing::write_pfm(path("w.pfm"), 16, 12, w);
        auto r = crex_cli({"compare", path("b.exr"), path("a.exr"), "--attention", path("w.pfm")});
        EXPECT_EQ(r.exit_code, 1) << bad << ": " << r.err;
        EXPECT_NE(r.err.find("holds 1 weight that is negative or not finite (NaN or Inf), the first at pixel (0, 11)"), std::string::npos)
            << r.err;
    }
}

// A PNG is already tone-mapped: against an EXR of the same render it is refused (exit 1, the
// flag named); with --assume-display the EXR is tone-mapped as crex writes PNGs and the two
// agree up to 8-bit rounding.
TEST_F(CompareCli, APngAndAnExrAreComparedOnlyAsDisplayed) {
    auto r = crex_cli({"run", "--size", "32x32", "--spp", "4", "-o", path("r.exr"), "-o", path("r.png"), "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto refused = crex_cli({"compare", path("r.png"), path("r.exr")});
    EXPECT_EQ(refused.exit_code, 1);
    EXPECT_NE(refused.err.find("--assume-display"), std::string::npos) << refused.err;
    EXPECT_NE(refused.err.find("r.png is display-referred"), std::string::npos) << refused.err;
    auto shown = crex_cli({"compare", path("r.png"), path("r.exr"), "--assume-display", "--format", "json", "--metric", "flip,perr"});
    ASSERT_EQ(shown.exit_code, 0) << shown.err;
    auto j = nlohmann::json::parse(shown.out);
    EXPECT_LT(j["flip"].get<double>(), 0.02);
    EXPECT_EQ(j["perr"].get<double>(), 0.0);
    EXPECT_NE(j["display"].get<std::string>().find("--assume-display"), std::string::npos);
    // Either order.
    EXPECT_EQ(crex_cli({"compare", path("r.exr"), path("r.png"), "--assume-display"}).exit_code, 0);
}

TEST_F(CompareCli, ExitCodesSayWhatWentWrong) {
    EXPECT_EQ(crex_cli({"compare", path("a.exr"), path("small.exr")}).exit_code, 1);  // sizes differ
    auto missing = crex_cli({"compare", path("a.exr"), path("nothing.exr")});
    EXPECT_EQ(missing.exit_code, 3);
    EXPECT_NE(missing.err.find("nothing.exr"), std::string::npos);
    EXPECT_EQ(crex_cli({"compare", path("a.exr"), path("a.exr"), "--metric", "vdp"}).exit_code, 2);
    EXPECT_EQ(crex_cli({"compare", path("a.exr")}).exit_code, 2);
}

// compare of NaN images reported 'nan' for every metric and exited 0: an input error now.
TEST_F(CompareCli, NonFiniteImagesAreAnInputErrorNotNan) {
    auto pfm = [&](const std::string& name, float value_5) {
        std::vector<float> rgb(4 * 2 * 3, 0.5f);
        rgb[5] = value_5;
        testing::write_pfm(path(name), 4, 2, rgb);
        return path(name);
    };
    std::string nan = pfm("nan.pfm", std::nanf("")), ok = pfm("ok.pfm", 0.5f);
    auto r = crex_cli({"compare", nan, ok});
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_NE(r.err.find("holds 1 non-finite value"), std::string::npos) << r.err;
    EXPECT_EQ(crex_cli({"compare", ok, ok}).exit_code, 0);
}

}  // namespace
}  // namespace crex
