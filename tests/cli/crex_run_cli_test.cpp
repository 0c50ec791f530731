// `crex run` as a user runs it: outputs written atomically, EXR layers, exit codes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "runtime/base/memory.h"
#include "runtime/io/image_io.h"
#include "tests/support/crex_cli.h"
#include "tests/support/scratch_folder.h"

namespace crex {
namespace {

namespace fs = std::filesystem;

using testing::crex_cli;

class CrexRunCli : public testing::ScratchFolderTest {
protected:
    CrexRunCli() : ScratchFolderTest("crex_run_cli_") {}
    size_t file_count() const {
        size_t n = 0;
        for ([[maybe_unused]] const auto& e : fs::recursive_directory_iterator(dir_)) ++n;
        return n;
    }
};

TEST_F(CrexRunCli, RendersTheDefaultSceneToEveryRequestedFormat) {
    auto r = crex_cli({"run", "--size", "32x24", "--spp", "2", "-o", path("a.exr"), "-o", path("a.png"), "-o", path("a.hdr")});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("rendered builtin:cornell with (TTMRSGD)* at 32x24, 2 spp"), std::string::npos) << r.out;
    for (const char* f : {"a.exr", "a.png", "a.hdr"}) {
        int w = 0, h = 0;
        std::vector<float> rgb;
        ASSERT_EQ(read_image(path(f), w, h, rgb), "") << f;
        EXPECT_EQ(w, 32);
        EXPECT_EQ(h, 24);
        double sum = 0;
        for (float v : rgb) {
            ASSERT_TRUE(std::isfinite(v));
            sum += v;
        }
        EXPECT_GT(sum, 0) << f;
    }
    EXPECT_EQ(file_count(), 3u);  // no temporaries left behind
}

// An EXR says what made it: oiiotool --info -v, as a user would look, shows the scene, the
// crex or pipeline, spp, seed, render time and version, typed (numbers unquoted), and the
// view as OpenEXR's matrices with the primaries.
TEST_F(CrexRunCli, ExrHeadersSayWhatMadeTheImage) {
    if (std::system("oiiotool --help > /dev/null 2>&1") != 0) GTEST_SKIP() << "oiiotool (openimageio-tools) is not installed";
    auto r = crex_cli({"run", "--size", "16x16", "--spp", "3", "--seed", "7", "-e", "(TTD)*", "-o", path("m.exr")});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto oiiotool_info = [](const std::string& file) { return testing::run_command({"/bin/sh", "-c", "oiiotool --info -v '" + file + "'"}); };
    auto info = oiiotool_info(path("m.exr"));
    ASSERT_EQ(info.exit_code, 0) << info.err;
    for (const char* want : {"crex:scene: \"builtin:cornell\"", "crex:crex: \"(TTD)*\"", "crex:spp_min: 3\n", "crex:spp_max: 3\n",
                             "crex:seed: 7\n", "crex:render_seconds: ", "crex:version:", "Software: \"crex ", "worldToCamera: ",
                             "worldToNDC: ", "chromaticities: 0.64, 0.33, 0.3, 0.6, 0.15, 0.06, 0.3127, 0.329"})
        EXPECT_NE(info.out.find(want), std::string::npos) << want << "\n" << info.out;
    auto pipe = crex_cli({"run", CREX_SOURCE_DIR "/stdlib/pipelines/sel_rp.pipe", "--size", "16x16", "-o", path("p.exr"), "-q"});
    ASSERT_EQ(pipe.exit_code, 0) << pipe.err;
    auto pinfo = oiiotool_info(path("p.exr"));
    for (const char* want : {"crex:pipeline: \"sel_rp\"", "crex:pipeline_file: \"", "crex:pipeline_hash: \"", "crex:spp_max: 16\n"})
        EXPECT_NE(pinfo.out.find(want), std::string::npos) << want << "\n" << pinfo.out;
    // Read back through the library: the types survive; selective spp is a range over the pixels.
    int w = 0, h = 0;
    ImageMetadata m;
    ASSERT_EQ(read_image_metadata(path("p.exr"), w, h, m), "");
    auto find = [&](const std::string& name) -> AttributeValue {
        for (const ImageAttribute& a : m)
            if (a.name == name) return a.value;
        return std::string("(missing)");
    };
    ASSERT_TRUE(std::holds_alternative<int>(find("crex:spp_min"))) << attribute_text(m, "crex:spp_min");
    EXPECT_LT(std::get<int>(find("crex:spp_min")), 16);
    EXPECT_TRUE(std::holds_alternative<float>(find("crex:render_seconds")));
    EXPECT_TRUE(std::holds_alternative<Matrix44>(find("worldToNDC")));
    EXPECT_TRUE(std::holds_alternative<Chromaticities>(find("chromaticities")));
}

// --view FILE.vf replaces the scene's camera with RADIANCE's view options, as rpict -vf: the
// scene's own view file gives the scene's image, another view another image, and a bad
// option is said in the view file.
TEST_F(CrexRunCli, AViewFileReplacesTheCamera) {
    const std::string rad = CREX_SOURCE_DIR "/examples/scenes/cornell/scene.rad", vf = CREX_SOURCE_DIR "/examples/scenes/cornell/scene.vf";
    auto run = [&](const std::vector<std::string>& extra, const std::string& out) {
        std::vector<std::string> args = {"run", "--scene", rad, "--size", "16x16", "--spp", "2", "-q", "-o", path(out)};
        args.insert(args.end(), extra.begin(), extra.end());
        return crex_cli(args);
    };
    ASSERT_EQ(run({}, "own.exr").exit_code, 0);
    ASSERT_EQ(run({"--view", vf}, "vf.exr").exit_code, 0);
    std::ofstream(path("away.vf")) << "rview -vp 0 0 3.4 -vd 0 0 1 -vu 0 1 0 -vh 40 -vv 40\n";  // facing out of the box
    ASSERT_EQ(run({"--view", path("away.vf")}, "away.exr").exit_code, 0);
    auto image = [&](const std::string& f) {
        int w = 0, h = 0;
        std::vector<float> rgb;
        EXPECT_EQ(read_image(path(f), w, h, rgb), "");
        return rgb;
    };
    EXPECT_EQ(image("own.exr"), image("vf.exr"));
    EXPECT_NE(image("own.exr"), image("away.exr"));
    std::ofstream(path("bad.vf")) << "rview -vp 0 0 3\n-vh 200\n";
    auto bad = run({"--view", path("bad.vf")}, "bad.exr");
    EXPECT_EQ(bad.exit_code, 1);
    EXPECT_NE(bad.err.find("bad.vf:2:5: error[E303]"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(path("bad.exr")));
}

TEST_F(CrexRunCli, ComponentLayersSumToTheComposite) {
    auto r = crex_cli({"run", "--size", "16x16", "--spp", "2", "--components", "-o", path("c.exr")});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto out = crex_cli({"run", "--size", "16x16", "--spp", "2", "-o", path("plain.exr")});
    ASSERT_EQ(out.exit_code, 0);
    int w, h;
    std::vector<float> composite, plain;
    ASSERT_EQ(read_image(path("c.exr"), w, h, composite), "");
    ASSERT_EQ(read_image(path("plain.exr"), w, h, plain), "");
    EXPECT_EQ(composite, plain);  // same seed: the same picture with or without layers
}

TEST_F(CrexRunCli, JsonSummaryCountsRaysPerComponent) {
    auto r = crex_cli({"run", "--size", "8x8", "--spp", "1", "-e", "TT", "--format", "json", "-o", path("t.exr")});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["components"]["camera"]["rays"], 64);
    EXPECT_EQ(j["components"]["D"]["rays"], 0);
    EXPECT_LE(j["components"]["T"]["executions"].get<int>(), 2);
    EXPECT_EQ(j["crex"], "TT");
}

// The JSON summary lists every warning of the run, those said while the scene loaded too, each
// located in its file; stderr says them as text whatever the format.
TEST_F(CrexRunCli, TheJsonSummaryListsTheScenesWarnings) {
    { std::ofstream(path("w.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 2 2\nf 1 2 3\nusemtl nothere\nf 1 1 4\n"; }
    auto r = crex_cli({"run", "--scene", path("w.obj"), "--size", "8x8", "--spp", "1", "--format", "json", "-o", path("w.exr")});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    std::vector<std::string> codes;
    for (const auto& w : j["warnings"]) {
        codes.push_back(w["code"]);
        if (w["code"] == "W301") {
            EXPECT_EQ(w["file"], path("w.obj"));
            EXPECT_EQ(w["line"], 6);
            EXPECT_EQ(w["severity"], "warning");
        }
    }
    for (const char* code : {"W301", "W303", "W313"})  // no material, a zero-area triangle, no lights
        EXPECT_NE(std::find(codes.begin(), codes.end(), code), codes.end()) << code << " in " << j["warnings"].dump();
    EXPECT_NE(r.err.find("warning[W301]"), std::string::npos) << r.err;
    // A sequence lists them once, beside the frames.
    { std::ofstream(path("walk.json")) << R"({"keys": [{"time": 0, "position": [0.3, 0.3, 3], "look_at": [0.3, 0.3, 0]},
                                                      {"time": 1, "position": [0.4, 0.3, 3], "look_at": [0.3, 0.3, 0]}]})"; }
    auto seq = crex_cli({"run", "--scene", path("w.obj"), "--size", "8x8", "--spp", "1", "--camera-path", path("walk.json"),
                         "--frames", "0..1", "--fps", "1", "--format", "json", "-o", path("s.exr")});
    ASSERT_EQ(seq.exit_code, 0) << seq.err;
    const auto s = nlohmann::json::parse(seq.out);
    ASSERT_TRUE(s["warnings"].is_array()) << seq.out;
    size_t w301 = 0;
    for (const auto& w : s["warnings"]) w301 += w["code"] == "W301";
    EXPECT_EQ(w301, 1u) << s["warnings"].dump();
}

TEST_F(CrexRunCli, BadInputExitsOneAndWritesNothing) {
    auto bad_crex = crex_cli({"run", "-e", "{D*}", "-o", path("x.exr")});
    EXPECT_EQ(bad_crex.exit_code, 1);
    EXPECT_NE(bad_crex.err.find("<crex>:1:3: error[E004]"), std::string::npos) << bad_crex.err;
    std::ofstream(path("bad.json")) << "{\"shapes\": 3}";
    auto bad_scene = crex_cli({"run", "--scene", path("bad.json"), "-o", path("x.exr")});
    EXPECT_EQ(bad_scene.exit_code, 1);
    EXPECT_FALSE(fs::exists(path("x.exr")));
}

TEST_F(CrexRunCli, UsageAndIoFailures) {
    EXPECT_EQ(crex_cli({"run", "--size", "0x10"}).exit_code, 2);
    EXPECT_EQ(crex_cli({"run", "--size", "big"}).exit_code, 2);
    EXPECT_EQ(crex_cli({"run", "--spp", "0"}).exit_code, 2);
    EXPECT_EQ(crex_cli({"run", "--scene", "/nonexistent.json"}).exit_code, 3);
    std::ofstream(path("a_file")) << "not a directory";
    auto r = crex_cli({"run", "--size", "4x4", "-o", path("a_file/x.exr")});  // even root cannot write there
    EXPECT_EQ(r.exit_code, 3);
    auto unknown = crex_cli({"run", "--size", "4x4", "-o", path("x.unknownext")});
    EXPECT_EQ(unknown.exit_code, 3);
    EXPECT_NE(unknown.err.find("x.unknownext"), std::string::npos) << unknown.err;
    // Every output is checked before rendering: a bad second -o leaves the first unwritten.
    for (const std::string& bad : {path("y.unknownext"), path("a_file/y.png"), dir_.string()}) {
        auto two = crex_cli({"run", "--size", "4x4", "-o", path("first.exr"), "-o", bad});
        EXPECT_EQ(two.exit_code, 3) << bad;
        EXPECT_NE(two.err.find(bad), std::string::npos) << two.err;
        EXPECT_FALSE(fs::exists(path("first.exr"))) << bad;
        EXPECT_EQ(two.out.find("rendered"), std::string::npos) << bad;  // found before any ray
    }
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

// capict's summary says how many pixels each sub-sampled component ran in, out of all, and
// how many refinement rounds there were; components the scene cannot produce are not listed.
TEST_F(CrexRunCli, CapictSaysWhereEachComponentRan) {
    auto r = crex_cli({"run", CREX_SOURCE_DIR "/stdlib/pipelines/capict.pipe", "--scene", "builtin:cornell", "--size", "32x32", "-o",
                       path("capict.exr"), "--format", "json", "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.find("W204"), std::string::npos) << r.err;  // its G and S maps are pruned on this scene, not warned about
    auto j = nlohmann::json::parse(r.out);
    const auto& corners = j["component_subsampled_pixels_rendered"];
    ASSERT_TRUE(corners.contains("D") && corners.contains("R")) << corners.dump();
    EXPECT_FALSE(corners.contains("G"));
    for (const char* c : {"D", "R"}) {
        EXPECT_GT(corners[c].get<int>(), 0) << c;
        EXPECT_LT(corners[c].get<int>(), 32 * 32) << c;
    }
    EXPECT_GE(j["component_subsample_refinements"].get<int>(), 0);
}

TEST_F(CrexRunCli, APipelineWritesItsMapsAndPerPixelPictures) {
    auto r = crex_cli({"run", CREX_SOURCE_DIR "/stdlib/pipelines/sel_st.pipe", "--scene",
                       CREX_SOURCE_DIR "/examples/scenes/corridor/scene.json", "--size", "32x24", "-o", path("sel_st.exr"),
                       "--maps", path("maps"), "--format", "json", "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["pipeline"], "sel_st");
    EXPECT_EQ(j["maps"], nlohmann::json::array({"sal", "task", "imp"}));
    EXPECT_GT(j["stages"]["preview_seconds"].get<double>(), 0.0);
    EXPECT_GT(j["stages"]["selective_rays"].get<double>(), 0.0);
    double pct = j["preview_percent_of_time"].get<double>();
    EXPECT_TRUE(pct > 0 && pct <= 100) << pct;
    for (const char* f : {"preview.png", "map_sal.png", "map_task.png", "map_imp.png", "samples_per_pixel.png", "rays_per_pixel.png",
                          "rays_per_pixel.exr", "components_per_pixel.png"})
        EXPECT_TRUE(fs::exists(dir_ / "maps" / f)) << f;
    // The rays-per-pixel EXR holds the counts: their mean is what the summary says.
    int w = 0, h = 0;
    std::vector<float> rays;
    ASSERT_EQ(read_image(path("maps/rays_per_pixel.exr"), w, h, rays), "");
    double sum = 0;
    for (size_t p = 0; p < rays.size(); p += 3) sum += rays[p];
    EXPECT_NEAR(sum / (w * h), j["rays_per_pixel"]["mean"].get<double>(), 1e-6);
    // The task map is 1 on the tagged objects: the exit sign is in view.
    std::vector<float> task;
    ASSERT_EQ(read_image(path("maps/map_task.png"), w, h, task), "");
    EXPECT_NEAR(*std::max_element(task.begin(), task.end()), 1.0f, 1e-6);
}

// The demo (tools/dev.sh demo) runs the normative pipeline without its budget: every pixel
// gets the camera samples its importance asks for (vary spp 4 .. 25 by imp), so the exit sign
// and the lamps, where the map is high, get more than the walls. Under the 10 s budget on a
// slow machine the whole budget went to the preview's rays and the map was 4 everywhere.
TEST_F(CrexRunCli, TheDemoPipelineAddsSamplesWhereItsImportanceIsHigh) {
    auto r = crex_cli({"run", CREX_SOURCE_DIR "/examples/pipelines/cornell_prog.pipe", "--no-budget", "--size", "64x48", "-o",
                       path("demo.exr"), "--maps", path("maps"), "--report", path("report"), "--format", "json", "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    int w = 0, h = 0, wi = 0, hi = 0;
    std::vector<float> spp, imp;
    ASSERT_EQ(read_image(path("maps/samples_per_pixel.exr"), w, h, spp), "");
    ASSERT_EQ(read_image(path("maps/map_imp.png"), wi, hi, imp), "");
    ASSERT_EQ(w * h, wi * hi);
    const size_t pixels = static_cast<size_t>(w) * static_cast<size_t>(h);
    std::vector<std::pair<float, float>> by_importance;  // (importance, samples)
    for (size_t p = 0; p < pixels; ++p) by_importance.emplace_back(imp[3 * p], spp[3 * p]);
    std::sort(by_importance.begin(), by_importance.end());
    auto mean_samples = [&](size_t from, size_t to) {
        double sum = 0;
        for (size_t k = from; k < to; ++k) sum += by_importance[k].second;
        return sum / static_cast<double>(to - from);
    };
    const size_t tenth = pixels / 10;
    const double least = mean_samples(0, tenth), most = mean_samples(pixels - tenth, pixels);
    EXPECT_GE(by_importance.front().second, 4.0f);  // the pipeline's floor, everywhere
    EXPECT_GT(most, least + 2) << "the tenth of pixels of highest importance: " << most << " spp, of lowest: " << least;
    EXPECT_GT(std::max_element(spp.begin(), spp.end())[0], 12.0f);
    // The summary says the same (the map's values, not its 8-bit picture, rank the pixels).
    auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["samples_by_map"]["map"], "imp");
    EXPECT_NEAR(j["samples_by_map"]["highest_tenth_spp"].get<double>(), most, 1.0);
    EXPECT_NEAR(j["samples_by_map"]["lowest_tenth_spp"].get<double>(), least, 1.0);
}

// lamp_aa spends its extra camera samples on the outline of the lamp the camera sees directly
// and nowhere else, and leaves every other pixel exactly as a plain 1-spp cached render has it.
TEST_F(CrexRunCli, LampAaSamplesTheLampsOutlineAndLeavesEveryOtherPixelAsAPlainRender) {
    const std::vector<std::string> common = {"--size", "64x64", "--ad", "32", "--seed", "3", "-q"};
    auto with = [&](std::vector<std::string> args) {
        args.insert(args.end(), common.begin(), common.end());
        return args;
    };
    auto a = crex_cli(with({"run", CREX_SOURCE_DIR "/stdlib/pipelines/lamp_aa.pipe", "-o", path("lamp_aa.exr"), "--maps", path("maps")}));
    ASSERT_EQ(a.exit_code, 0) << a.err;
    auto b = crex_cli(with({"run", "--ic", "--spp", "1", "-o", path("plain.exr")}));
    ASSERT_EQ(b.exit_code, 0) << b.err;
    int w = 0, h = 0;
    std::vector<float> aa, plain, spp;
    ASSERT_EQ(read_image(path("lamp_aa.exr"), w, h, aa), "");
    ASSERT_EQ(read_image(path("plain.exr"), w, h, plain), "");
    ASSERT_EQ(read_image(path("maps/samples_per_pixel.exr"), w, h, spp), "");
    ASSERT_EQ(aa.size(), plain.size());
    auto at = [&](const std::vector<float>& img, int x, int y) {
        const size_t p = 3 * (static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x));
        return (img[p] + img[p + 1] + img[p + 2]) / 3;
    };
    // The lamp: far brighter than anything it lights (builtin:cornell's emits 15 or so), in
    // the top fifth of the image. From a quarter of the way down the mirror ball shows it too,
    // but that is not `emission` (an emitter the camera sees directly): lamp_aa leaves it be.
    auto lamp = [&](int x, int y) { return x >= 0 && y >= 0 && x < w && y < h / 5 && at(plain, x, y) > 2.0f; };
    auto near = [&](int x, int y, bool want) {
        for (int dy = -3; dy <= 3; ++dy)
            for (int dx = -3; dx <= 3; ++dx) {
                const int u = x + dx, v = y + dy;
                if (u >= 0 && v >= 0 && u < w && v < h && lamp(u, v) == want) return true;  // pixels of the image only
            }
        return false;
    };
    // The lamp's outline: a lamp pixel beside one that is not.
    auto on_outline = [&](int x, int y) { return lamp(x, y) && (!lamp(x - 1, y) || !lamp(x + 1, y) || !lamp(x, y - 1) || !lamp(x, y + 1)); };
    size_t more = 0, outline_pixels = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float samples = at(spp, x, y);
            if (on_outline(x, y)) {
                ++outline_pixels;
                EXPECT_GT(samples, 1.0f) << "pixel " << x << "," << y << " of the lamp's outline kept one sample";
            }
            if (samples == 1.0f) {
                for (int c = 0; c < 3; ++c) {
                    const size_t p = 3 * (static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) + c;
                    ASSERT_EQ(aa[p], plain[p]) << "pixel " << x << "," << y << " kept one sample but differs from the plain render";
                }
                continue;
            }
            ++more;
            EXPECT_TRUE(near(x, y, true) && near(x, y, false)) << "pixel " << x << "," << y << " got " << samples << " samples away from the lamp's outline";
        }
    EXPECT_GT(outline_pixels, 10u) << "builtin:cornell's lamp is in view";
    EXPECT_LT(more, static_cast<size_t>(w * h) / 10) << "extra samples went beyond the outline";
}

TEST_F(CrexRunCli, IcRadiusRunsTheProgressiveIrradianceCache) {
    auto r = crex_cli({"run", CREX_SOURCE_DIR "/stdlib/pipelines/prog_all.pipe", "--size", "24x24", "-o", path("p.exr"), "--ad", "64",
                       "--format", "json", "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.find("note:"), std::string::npos) << r.err;
    auto j = nlohmann::json::parse(r.out);
    const auto& ic = j["irradiance_cache"];
    EXPECT_GT(ic["preview_records"].get<int>(), 0);
    EXPECT_GT(ic["reprocessed_preview_samples"].get<int>(), 0);  // salient pixels asked for a finer radius
    EXPECT_EQ(ic["records"].get<int>(), ic["preview_records"].get<int>() + ic["selective_records"].get<int>());
}

TEST_F(CrexRunCli, ARenderThatCannotFitInMemoryIsRefusedBeforeItStarts) {
    // 16384x16384 with every component's image holds about 57 GB of film and images: before
    // this check the kernel let it start and it grew past 15 GB in 50 s on a 24 GB machine.
    // (Without --components its film is 19 GB, which a machine with that much free memory renders.)
    const auto available = memory_available_bytes();
    if (!available || *available > size_t{55} * 1000 * 1000 * 1000) GTEST_SKIP() << "this machine could hold it";
    auto r = crex_cli({"run", "--scene", "builtin:cornell", "--size", "16384x16384", "--components", "-o", path("big.exr")});
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NE(r.err.find("a 16384x16384 render holds"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("GB of memory and swap this machine has free"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("big.exr")));
}

TEST_F(CrexRunCli, ANoteEveryRoundRepeatsIsSaidOnce) {
    std::ofstream(path("zero.pipe")) << "pipeline zero {\n  preselective { spp 1 }\n  guidance { m = constant(0) }\n"
                                        "  selective { vary spp 1 .. 4 by m\n  rounds 3 }\n}\n";
    auto r = crex_cli({"run", path("zero.pipe"), "--size", "8x8", "-o", path("zero.exr"), "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string note = "note: map 'm = constant(0)' is 0 everywhere";
    const size_t at = r.err.find(note);
    ASSERT_NE(at, std::string::npos) << r.err;
    EXPECT_EQ(r.err.find(note, at + 1), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("(3 times)", at), std::string::npos) << r.err;
}

TEST_F(CrexRunCli, AMemoryLimitBelowWhatTheFilmHoldsIsSaidNotPretended) {
    // 64x64: about 97 MiB of film, images and the process baseline, over a 64 MiB limit.
    auto r = crex_cli({"run", "--scene", "builtin:cornell", "--size", "64x64", "--max-memory", "64", "-o", path("m.exr"), "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("more than --max-memory 64 MiB: its passes go one row at a time"), std::string::npos) << r.err;
    auto fits = crex_cli({"run", "--scene", "builtin:cornell", "--size", "64x64", "--max-memory", "512", "-o", path("m.exr"), "-q"});
    ASSERT_EQ(fits.exit_code, 0) << fits.err;
    EXPECT_EQ(fits.err.find("--max-memory"), std::string::npos) << fits.err;
}

TEST_F(CrexRunCli, APipelinesAdSetsTheRecordsHemisphereRaysUnlessTheCommandLineDoes) {
    std::ofstream(path("ad.pipe")) << "pipeline ad_set {\n  ad 32\n  preselective { crex \"(TTMRSGD)*\" spp 1 }\n"
                                      "  guidance { m = constant(1) }\n  selective { vary ic_radius 0.5 .. 0.3 by m }\n}\n";
    auto hemisphere_rays_per_record = [&](std::vector<std::string> extra) {
        std::vector<std::string> args = {"run", path("ad.pipe"), "--size", "16x16", "-o", path("ad.exr"), "--format", "json", "-q"};
        args.insert(args.end(), extra.begin(), extra.end());
        auto r = crex_cli(args);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        const auto j = nlohmann::json::parse(r.out)["irradiance_cache"];
        EXPECT_GT(j["records"].get<int>(), 0);
        return j["ad"].get<int>();
    };
    EXPECT_EQ(hemisphere_rays_per_record({}), 32);
    EXPECT_EQ(hemisphere_rays_per_record({"--ad", "48"}), 48);
}

TEST_F(CrexRunCli, APipelinesShadowRaysSetTheCameraHitsLightSamplesUnlessTheCommandLineDoes) {
    auto pipe = [&](const std::string& name, const std::string& setting) {
        std::ofstream(path(name)) << "pipeline sr_set {\n  preselective { crex \"(TTMRSGD)*\" spp 1" << setting << " }\n"
                                     "  guidance { m = constant(1) }\n  selective { vary ic_radius 0.5 .. 0.3 by m }\n}\n";
        return path(name);
    };
    const std::string six = pipe("sr6.pipe", " shadow_rays 6"), none = pipe("sr.pipe", "");
    auto camera_shadow_rays = [&](const std::string& file, std::vector<std::string> extra) {
        std::vector<std::string> args = {"run", file, "--size", "16x16", "-o", path("sr.exr"), "--format", "json", "-q"};
        args.insert(args.end(), extra.begin(), extra.end());
        auto r = crex_cli(args);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return nlohmann::json::parse(r.out)["components"]["camera"]["shadow_rays"].get<double>();
    };
    // Light samples a light behind the surface does not trace, so the counts are near, not
    // exactly, proportional to the rays a hit asks for.
    const double one = camera_shadow_rays(none, {}), two = camera_shadow_rays(six, {"--shadow-rays", "2"});
    EXPECT_GT(one, 0);
    EXPECT_EQ(camera_shadow_rays(none, {"--shadow-rays", "1"}), one);  // the default is one
    EXPECT_NEAR(camera_shadow_rays(six, {}) / one, 6.0, 0.3);
    EXPECT_NEAR(two / one, 2.0, 0.1);
    // Out of range: a located error before anything renders.
    std::ofstream(path("sr0.pipe")) << "pipeline sr0 {\n  preselective { crex \"(TTMRSGD)*\" spp 1 shadow_rays 0 }\n}\n";
    auto bad = crex_cli({"check", path("sr0.pipe")});
    EXPECT_EQ(bad.exit_code, 1) << bad.err;
    EXPECT_NE(bad.err.find("sr0.pipe:2:"), std::string::npos) << bad.err;
    EXPECT_NE(bad.err.find("E203"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(RunOutputsCli, AShortWriteNeverReplacesTheOldImage) {
    // A PNG written to a full disk reported "wrote" and replaced the good old file with a
    // truncated one. A file-size limit (the shell's ulimit, SIGXFSZ ignored) makes the write
    // short: the run fails with exit 3 naming the user's path, and the old file is intact.
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("crex_short_write_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string png = (dir / "a.png").string();
    auto first = testing::crex_cli({"run", "--size", "64x64", "--spp", "1", "-o", png, "-q"});
    ASSERT_EQ(first.exit_code, 0) << first.err;
    const auto before = fs::file_size(png);
    auto limited = testing::run_command({"/bin/sh", "-c", std::string("trap '' XFSZ; ulimit -f 2; exec ") + CREX_BINARY +
                                                                " run --size 64x64 --spp 2 -o " + png + " -q"});
    EXPECT_EQ(limited.exit_code, 3) << limited.err;
    EXPECT_NE(limited.err.find("cannot write '" + png + "'"), std::string::npos) << limited.err;
    EXPECT_EQ(fs::file_size(png), before);
    int w = 0, h = 0;
    std::vector<float> rgb;
    EXPECT_EQ(read_image(png, w, h, rgb), "");  // still the whole old picture
    size_t files = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
    EXPECT_EQ(files, 1u);  // no temporary left behind
    fs::remove_all(dir);
}

// Several outputs: all or none. The second image cannot be written (a file-size limit lets
// the small PNG through and stops the EXR): the first, already written, must not replace the
// old one either. Then a report into a folder that is not a crex report (its images/ is a
// file): refused before rendering, and again nothing is replaced. No staged file is left behind.
TEST(RunOutputsCli, SeveralOutputsAreWrittenAllOrNone) {
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("crex_all_or_none_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string png = (dir / "a.png").string(), exr = (dir / "a.exr").string();
    auto first = testing::crex_cli({"run", "--size", "16x16", "--spp", "1", "-o", png, "-o", exr, "-q"});
    ASSERT_EQ(first.exit_code, 0) << first.err;
    auto bytes = [](const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    const std::string old_png = bytes(png), old_exr = bytes(exr);
    ASSERT_LT(old_png.size(), 2048u) << "the test needs a PNG under the 2 KB limit";
    ASSERT_GT(old_exr.size(), 2048u) << "and an EXR over it";
    auto limited = testing::run_command({"/bin/sh", "-c", std::string("trap '' XFSZ; ulimit -f 4; exec ") + CREX_BINARY +
                                                                " run --size 16x16 --spp 1 --seed 7 -o " + png + " -o " + exr + " -q"});
    EXPECT_EQ(limited.exit_code, 3) << limited.err;
    EXPECT_NE(limited.err.find("cannot write '" + exr + "'"), std::string::npos) << limited.err;
    EXPECT_EQ(bytes(png), old_png);  // written (staged), but never moved over the old one
    EXPECT_EQ(bytes(exr), old_exr);

    fs::create_directories(dir / "report");
    { std::ofstream(dir / "report" / "images") << "in the way"; }
    auto blocked = testing::crex_cli({"run", "--size", "16x16", "--spp", "1", "--seed", "9", "-o", png, "--report",
                                      (dir / "report").string(), "--reference", exr, "-q"});
    EXPECT_EQ(blocked.exit_code, 3) << blocked.err;  // a report replaces its folder whole: a folder that is not one is refused
    EXPECT_NE(blocked.err.find("is not a crex report"), std::string::npos) << blocked.err;
    EXPECT_EQ(bytes(png), old_png);
    EXPECT_FALSE(fs::exists(dir / "report" / "index.html"));

    auto ok = testing::crex_cli({"run", "--size", "16x16", "--spp", "1", "--seed", "9", "-o", png, "--maps", (dir / "maps").string(), "-q"});
    ASSERT_EQ(ok.exit_code, 0) << ok.err;
    EXPECT_NE(bytes(png), old_png);
    EXPECT_TRUE(fs::exists(dir / "maps" / "rays_per_pixel.png"));
    for (const auto& e : fs::recursive_directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().find(".crex-staged"), std::string::npos) << e.path();
    // A file where --maps wants a directory: said before anything renders.
    auto file_maps = testing::crex_cli({"run", "--size", "16x16", "--spp", "1", "-o", png, "--maps", png, "-q"});
    EXPECT_EQ(file_maps.exit_code, 3);  // an output problem, as for -o
    EXPECT_NE(file_maps.err.find("--maps " + png + ": is a file; give a directory"), std::string::npos) << file_maps.err;
    fs::remove_all(dir);
}

// A budgeted run from a saved profile says, per component, how far the profile's cost per ray
// was from what the run measured (thesis Table 5.4), in the JSON summary and the text.
TEST(RunBudgetCli, TheProfilesErrorIsReportedPerComponent) {
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("crex_profile_error_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string profile = (dir / "p.json").string();
    auto full = testing::crex_cli({"run", "-e", "(TT[RS]GMD)*", "--size", "32x32", "--spp", "4", "-o", (dir / "f.exr").string(),
                                   "--save-profile", profile, "-q"});
    ASSERT_EQ(full.exit_code, 0) << full.err;
    auto cut = testing::crex_cli({"run", "-e", "(TT[RS]GMD)*", "--size", "32x32", "--spp", "4", "-o", (dir / "c.exr").string(),
                                  "--profile", profile, "--budget", "50%", "--policy", "queues", "--format", "json", "-q"});
    ASSERT_EQ(cut.exit_code, 0) << cut.err;
    auto j = nlohmann::json::parse(cut.out);
    EXPECT_EQ(j["policy"], "queues");
    const auto& e = j["profile_error_percent"];
    ASSERT_TRUE(e.contains("camera")) << e.dump();
    // An error for each component this run traced rays of, and for no other. Which ones those
    // are depends on the machine: a stall in the camera rays of a loaded CI machine has spent
    // the whole 50 % before the first D ray (it happened once), so D is asked for only when
    // the run reached it. Usually it reaches all of D, T, R and M.
    for (const auto& [what, c] : j["components"].items()) {
        const bool any = c["rays"].get<uint64_t>() > 0;
        EXPECT_EQ(e.contains(what), any) << what << ": " << e.dump();
    }
    for (const auto& [what, percent] : e.items()) EXPECT_TRUE(std::isfinite(percent.get<double>())) << what;
    auto text = testing::crex_cli({"run", "-e", "(TT[RS]GMD)*", "--size", "32x32", "--spp", "4", "-o", (dir / "c.exr").string(),
                                   "--profile", profile, "--budget", "50%"});
    ASSERT_EQ(text.exit_code, 0) << text.err;
    EXPECT_NE(text.out.find("profile's cost per ray against this run's: camera "), std::string::npos) << text.out;
    fs::remove_all(dir);
}

}  // namespace
}  // namespace crex
