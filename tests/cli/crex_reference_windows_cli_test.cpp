// References that scale with the frame (issue 32), as a user makes and uses them: windows of
// the frame rendered as the whole frame would be, accumulation over runs, and `crex compare`
// on the windows alone.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "runtime/io/image_io.h"
#include "runtime/reference/windowed_image.h"
#include "tests/support/crex_cli.h"
#include "tests/support/scratch_folder.h"

namespace crex {
namespace {

namespace fs = std::filesystem;
using testing::crex_cli;

constexpr int kWidth = 48, kHeight = 32;
// Two windows of different heights: the atlas has a black strip under the shorter one.
const std::vector<std::string> kWindows = {"5,4,12,10", "30,16,16,16"};

class ReferenceWindowsCli : public testing::ScratchFolderTest {
protected:
    ReferenceWindowsCli() : ScratchFolderTest("crex_reference_windows_") {}

    // `crex reference builtin:cornell` of the windows at 48x32, seed 3; `context`: with the
    // cheap cached render of the whole frame (exposure and saliency), which costs more than
    // the windows at this size.
    void windowed_reference(const std::string& out, uint32_t spp, bool context = false) {
        std::vector<std::string> args = {"reference", "builtin:cornell", "--size", "48x32", "--spp", std::to_string(spp), "--seed", "3",
                                         "--context-spp", context ? "1" : "0", "-q", "-o", path(out)};
        for (const auto& w : kWindows) args.insert(args.end(), {"--window", w});
        auto r = crex_cli(args);
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }

    static std::vector<float> read(const std::string& file, int& w, int& h) {
        std::vector<float> rgb;
        EXPECT_EQ(read_image(file, w, h, rgb), "");
        return rgb;
    }

    static std::map<std::string, std::string> header(const std::string& file) {
        int w = 0, h = 0;
        ImageMetadata m;
        EXPECT_EQ(read_image_metadata(file, w, h, m), "");
        std::map<std::string, std::string> text;
        for (const ImageAttribute& a : m) text[a.name] = a.text();
        return text;
    }

};

std::vector<PixelWindow> windows() {
    std::vector<PixelWindow> out;
    for (const auto& w : kWindows) out.push_back(*parse_window(w));
    return out;
}

// The pixels of a windowed reference are the same pixels of a reference of the whole frame at
// the same seed and samples, bit for bit (both fit in one sample pass here, so each pixel's
// samples are summed in the same order).
TEST_F(ReferenceWindowsCli, WindowsEqualTheSamePixelsOfAFullReferenceBitForBit) {
    windowed_reference("win.exr", 8);
    auto full = crex_cli({"reference", "builtin:cornell", "--size", "48x32", "--spp", "8", "--seed", "3", "-q", "-o", path("full.exr")});
    ASSERT_EQ(full.exit_code, 0) << full.err;
    int fw = 0, fh = 0, aw = 0, ah = 0;
    const std::vector<float> frame = read(path("full.exr"), fw, fh), atlas = read(path("win.exr"), aw, ah);
    ASSERT_EQ(fw, kWidth);
    const WindowAtlas layout(windows());
    ASSERT_EQ(aw, 12 + 16);
    ASSERT_EQ(ah, 16);
    size_t lit = 0;
    for (size_t i = 0; i < layout.windows.size(); ++i) {
        const std::vector<float> want = crop(frame, fw, layout.windows[i]), got = layout.window(atlas, i);
        ASSERT_EQ(got.size(), want.size());
        for (size_t k = 0; k < want.size(); ++k) {
            ASSERT_EQ(got[k], want[k]) << "window " << i << " value " << k;  // bit for bit
            lit += want[k] > 0;
        }
    }
    EXPECT_GT(lit, 3 * (12 * 10 + 16 * 16) / 2);  // a real image, not two black ones
    for (int y = 10; y < 16; ++y)  // below the shorter window: black
        for (int x = 0; x < 12; ++x) EXPECT_EQ(atlas[3 * static_cast<size_t>(y * aw + x)], 0.0f);
    auto h = header(path("win.exr"));
    EXPECT_EQ(h["crex:frame"], "48x32");
    EXPECT_EQ(h["crex:windows"], "5,4,12,10;30,16,16,16");
    EXPECT_EQ(h["crex:spp"], "8");
    EXPECT_EQ(h["crex:seed"], "3");
    EXPECT_EQ(h["crex:scene_hash"].size(), 16u);
    EXPECT_EQ(h["crex:scene_hash"], header(path("full.exr"))["crex:scene_hash"]);
    EXPECT_EQ(h.count("crex:exposure"), 0u);  // --context-spp 0: none recorded
    EXPECT_NE(h["crex:commands"].find("--window 5,4,12,10 --window 30,16,16,16"), std::string::npos) << h["crex:commands"];
}

// Accumulation continues the sample indices: 8 samples, then 8 more, is one run of 16 up to
// the rounding of the two stored means; the header counts them all and names both runs.
TEST_F(ReferenceWindowsCli, TwoAccumulatedHalvesEqualOneRunOfTheSum) {
    windowed_reference("halves.exr", 8);
    windowed_reference("once.exr", 16);
    auto more = crex_cli({"reference", "--accumulate", path("halves.exr"), "--spp", "8", "-q"});
    ASSERT_EQ(more.exit_code, 0) << more.err;
    int w = 0, h = 0;
    const std::vector<float> halves = read(path("halves.exr"), w, h), once = read(path("once.exr"), w, h);
    ASSERT_EQ(halves.size(), once.size());
    for (size_t k = 0; k < once.size(); ++k) {
        ASSERT_NEAR(halves[k], once[k], 4e-7 * std::fabs(once[k]) + 1e-9) << "value " << k;
    }
    auto hd = header(path("halves.exr"));
    EXPECT_EQ(hd["crex:spp"], "16");
    EXPECT_EQ(hd["crex:runs"], "8+8");
    EXPECT_NE(hd["crex:commands"].find("\ncrex reference builtin:cornell --accumulate"), std::string::npos) << hd["crex:commands"];
    // Half of the samples are not the same image: the comparison above could fail.
    windowed_reference("eight.exr", 8);
    const std::vector<float> eight = read(path("eight.exr"), w, h);
    size_t differ = 0;
    for (size_t k = 0; k < once.size(); ++k) differ += std::fabs(eight[k] - once[k]) > 1e-3 * std::fabs(once[k]);
    EXPECT_GT(differ, once.size() / 4);
}

// The header's estimate of a reference's own error, from the two runs it was accumulated from,
// is near its actual error against a render of many more samples (another seed; 512 spp, 16
// times the tested 32: its own noise raises the measured error by 3 %, against 1 % at 2048 spp,
// which took four times as long; measured estimate over actual 0.90 and 0.93).
TEST_F(ReferenceWindowsCli, AnAccumulatedReferenceEstimatesItsOwnError) {
    windowed_reference("grown.exr", 16);
    auto more = crex_cli({"reference", "--accumulate", path("grown.exr"), "--spp", "16"});
    ASSERT_EQ(more.exit_code, 0) << more.err;
    EXPECT_NE(more.err.find("its own RMSE is about"), std::string::npos) << more.err;
    std::vector<std::string> args = {"reference", "builtin:cornell", "--size", "48x32", "--spp", "512", "--seed", "9",
                                     "--context-spp", "0", "-q", "-o", path("gold.exr")};
    for (const auto& w : kWindows) args.insert(args.end(), {"--window", w});
    ASSERT_EQ(crex_cli(args).exit_code, 0);
    int w = 0, h = 0;
    const std::vector<float> grown = read(path("grown.exr"), w, h), gold = read(path("gold.exr"), w, h);
    ASSERT_EQ(grown.size(), gold.size());
    double sum = 0;
    for (size_t k = 0; k < gold.size(); ++k) sum += (double(grown[k]) - gold[k]) * (double(grown[k]) - gold[k]);
    const double actual = std::sqrt(sum / static_cast<double>(gold.size()));
    const double estimate = std::stod(header(path("grown.exr"))["crex:own_rmse"]);
    EXPECT_GT(estimate, 0.6 * actual);
    EXPECT_LT(estimate, 1.6 * actual);
    // crex compare says it beside the test's error.
    auto compared = crex_cli({"compare", path("grown.exr"), path("gold.exr"), "--format", "json"});
    ASSERT_EQ(compared.exit_code, 0) << compared.err;
    EXPECT_EQ(nlohmann::json::parse(compared.out).count("reference_own_rmse"), 0u);  // the gold has one run
    auto reversed = crex_cli({"compare", path("gold.exr"), path("grown.exr"), "--format", "json"});
    ASSERT_EQ(reversed.exit_code, 0) << reversed.err;
    EXPECT_NEAR(nlohmann::json::parse(reversed.out)["reference_own_rmse"].get<double>(), estimate, 1e-6 * estimate);
}

// Accumulation refuses what would not add up: another scene, and options the file decides.
TEST_F(ReferenceWindowsCli, AccumulationRefusesAnotherSceneAndOptionsTheFileDecides) {
    windowed_reference("ref.exr", 2);
    auto other = crex_cli({"reference", "builtin:cornell_diffuse", "--accumulate", path("ref.exr"), "--spp", "2", "-q"});
    EXPECT_EQ(other.exit_code, 1);
    EXPECT_NE(other.err.find("the scene has changed"), std::string::npos) << other.err;
    auto size = crex_cli({"reference", "--accumulate", path("ref.exr"), "--spp", "2", "--size", "48x32", "-q"});
    EXPECT_EQ(size.exit_code, 2);
    EXPECT_EQ(header(path("ref.exr"))["crex:spp"], "2");  // untouched
    ASSERT_EQ(write_image(path("plain.exr"), 4, 4, {{"", std::vector<float>(48, 0.5f)}}), "");
    auto plain = crex_cli({"reference", "--accumulate", path("plain.exr"), "--spp", "2", "-q"});
    EXPECT_EQ(plain.exit_code, 1);
    EXPECT_NE(plain.err.find("no reference header"), std::string::npos) << plain.err;
    // Windows outside the frame or overlapping are usage errors, and so is a window without -o.
    for (const auto& bad : std::vector<std::vector<std::string>>{{"--window", "40,0,16,16", "-o", path("x.exr")},
                                                                 {"--window", "0,0,8,8", "--window", "4,4,8,8", "-o", path("x.exr")},
                                                                 {"--window", "0,0,8", "-o", path("x.exr")},
                                                                 {"--window", "0,0,8,8"}}) {
        std::vector<std::string> args = {"reference", "--size", "48x32", "--spp", "1", "-q"};
        args.insert(args.end(), bad.begin(), bad.end());
        auto r = crex_cli(args);
        EXPECT_EQ(r.exit_code, 2) << r.err;
        EXPECT_FALSE(fs::exists(path("x.exr")));
    }
}

// `crex compare` against a windowed reference scores the windows alone, each as `crex compare`
// of the crops (with the frame's exposure the reference recorded) scores it, and the whole as
// those combined over all their pixels.
TEST_F(ReferenceWindowsCli, CompareOnWindowsEqualsCompareOfCrops) {
    windowed_reference("win.exr", 16, true);
    auto run = crex_cli({"run", "--size", "48x32", "--spp", "2", "--seed", "5", "-o", path("test.exr"), "-q"});
    ASSERT_EQ(run.exit_code, 0) << run.err;
    std::vector<float> map(3 * kWidth * kHeight);
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            for (int c = 0; c < 3; ++c) map[3 * static_cast<size_t>(y * kWidth + x) + static_cast<size_t>(c)] = 0.1f + static_cast<float>(x) / kWidth;
    ASSERT_EQ(write_image(path("map.exr"), kWidth, kHeight, {{"", map}}), "");
    auto on_windows = crex_cli({"compare", path("test.exr"), path("win.exr"), "--format", "json", "--metric", "rmse,relmse,ssim,flip,perr",
                                "--attention", path("map.exr")});
    ASSERT_EQ(on_windows.exit_code, 0) << on_windows.err;
    const auto j = nlohmann::json::parse(on_windows.out);
    ASSERT_EQ(j["windows"].size(), 2u);
    EXPECT_EQ(j["pixels"], 12 * 10 + 16 * 16);
    const std::string exposure = header(path("win.exr"))["crex:exposure"];  // of the cached render of the whole frame
    ASSERT_GT(std::atof(exposure.c_str()), 0.0);
    int tw = 0, th = 0, aw = 0, ah = 0;
    const std::vector<float> test = read(path("test.exr"), tw, th), atlas = read(path("win.exr"), aw, ah);
    const WindowAtlas layout(windows());
    double n = 0, flip = 0, perr = 0, sq = 0, wsum = 0, wflip = 0;
    for (size_t i = 0; i < layout.windows.size(); ++i) {
        const PixelWindow& w = layout.windows[i];
        const std::string t = path("t" + std::to_string(i) + ".exr"), r = path("r" + std::to_string(i) + ".exr"),
                          m = path("m" + std::to_string(i) + ".exr");
        ASSERT_EQ(write_image(t, w.width, w.height, {{"", crop(test, tw, w)}}), "");
        ASSERT_EQ(write_image(r, w.width, w.height, {{"", layout.window(atlas, i)}}), "");
        ASSERT_EQ(write_image(m, w.width, w.height, {{"", crop(map, kWidth, w)}}), "");
        auto c = crex_cli({"compare", t, r, "--format", "json", "--metric", "rmse,relmse,ssim,flip,perr", "--exposure", exposure,
                           "--attention", m});
        ASSERT_EQ(c.exit_code, 0) << c.err;
        const auto cj = nlohmann::json::parse(c.out), wj = j["windows"][i];
        EXPECT_EQ(wj["window"], nlohmann::json({w.x, w.y, w.width, w.height}));
        for (const char* key : {"rmse", "relmse", "flip", "perr", "aflip"}) EXPECT_DOUBLE_EQ(wj[key].get<double>(), cj[key].get<double>()) << key;
        EXPECT_EQ(wj["ssim"], cj["ssim"]);  // 10 rows: n/a for the first, a value for the second
        const double pixels = w.width * w.height;
        n += pixels, flip += pixels * cj["flip"].get<double>(), perr += pixels * cj["perr"].get<double>();
        sq += pixels * std::pow(cj["rmse"].get<double>(), 2);
        double weight = 0;
        for (int y = 0; y < w.height; ++y)
            for (int x = 0; x < w.width; ++x) weight += map[3 * static_cast<size_t>((w.y + y) * kWidth + w.x + x)];
        wsum += weight, wflip += weight * cj["aflip"].get<double>();
    }
    EXPECT_NEAR(j["flip"].get<double>(), flip / n, 1e-12);
    EXPECT_NEAR(j["perr"].get<double>(), perr / n, 1e-12);
    EXPECT_NEAR(j["rmse"].get<double>(), std::sqrt(sq / n), 1e-12);
    EXPECT_NEAR(j["aflip"].get<double>(), wflip / wsum, 1e-6);
    EXPECT_GT(j["flip"].get<double>(), 0.0);
    // The reference's own saliency of the frame weighs too; an image of another size is refused.
    auto sal = crex_cli({"compare", path("test.exr"), path("win.exr"), "--format", "json", "--attention", "saliency"});
    ASSERT_EQ(sal.exit_code, 0) << sal.err;
    EXPECT_NE(nlohmann::json::parse(sal.out)["aflip"].get<double>(), j["flip"].get<double>());
    auto small = crex_cli({"run", "--size", "24x16", "--spp", "1", "-o", path("small.exr"), "-q"});
    ASSERT_EQ(small.exit_code, 0) << small.err;
    auto refused = crex_cli({"compare", path("small.exr"), path("win.exr")});
    EXPECT_EQ(refused.exit_code, 1);
    EXPECT_NE(refused.err.find("48x32 frame"), std::string::npos) << refused.err;
}

}  // namespace
}  // namespace crex
