// `crex compare` as a user runs it: metrics as JSON, exit codes, the FLIP picture.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "runtime/io/image_io.h"
#include "tests/support/crex_cli.h"

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

TEST_F(CompareCli, ExitCodesSayWhatWentWrong) {
    EXPECT_EQ(crex_cli({"compare", path("a.exr"), path("small.exr")}).exit_code, 1);  // sizes differ
    auto missing = crex_cli({"compare", path("a.exr"), path("nothing.exr")});
    EXPECT_EQ(missing.exit_code, 3);
    EXPECT_NE(missing.err.find("nothing.exr"), std::string::npos);
    EXPECT_EQ(crex_cli({"compare", path("a.exr"), path("a.exr"), "--metric", "vdp"}).exit_code, 2);
    EXPECT_EQ(crex_cli({"compare", path("a.exr")}).exit_code, 2);
}

}  // namespace
}  // namespace crex

#include <cmath>
#include <cstring>
#include <fstream>

namespace crex {
namespace {

TEST(CompareNonFiniteCli, NonFiniteImagesAreAnInputErrorNotNan) {
    // compare of NaN images reported 'nan' for every metric and exited 0. PFM is written by
    // hand here: crex's own writers never let NaN into a file.
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("crex_compare_nan_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    auto pfm = [&](const std::string& name, float value_5) {
        std::vector<float> rgb(4 * 2 * 3, 0.5f);
        rgb[5] = value_5;
        std::ofstream out(dir / name, std::ios::binary);
        out << "PF\n4 2\n-1.0\n";
        out.write(reinterpret_cast<const char*>(rgb.data()), static_cast<std::streamsize>(rgb.size() * sizeof(float)));
        return (dir / name).string();
    };
    std::string nan = pfm("nan.pfm", std::nanf("")), ok = pfm("ok.pfm", 0.5f);
    auto r = testing::crex_cli({"compare", nan, ok});
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_NE(r.err.find("holds 1 non-finite value"), std::string::npos) << r.err;
    EXPECT_EQ(testing::crex_cli({"compare", ok, ok}).exit_code, 0);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace crex
