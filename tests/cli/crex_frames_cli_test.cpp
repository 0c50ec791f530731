// `crex run --camera-path FILE --frames A..B` as a user runs it (issue 36): a file per frame
// and output, a rerun that skips finished frames without touching them, --force to redo them,
// a progress line per frame, JSON per frame, and usage errors for what does not go together.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "runtime/api/frame_sequence.h"
#include "runtime/io/image_io.h"
#include "runtime/io/video_file.h"
#include "tests/support/crex_cli.h"
#include "tests/support/float_map.h"
#include "tests/support/scratch_folder.h"

namespace crex {
namespace {

using testing::crex_cli;

const char* kCorridor = CREX_SOURCE_DIR "/examples/scenes/corridor/scene.json";

class CrexFramesCli : public testing::ScratchFolderTest {
protected:
    CrexFramesCli() : ScratchFolderTest("crex_frames_cli_") {}

    std::string write(const std::string& name, const std::string& text) {
        std::ofstream(path(name)) << text;
        return path(name);
    }
    std::string walk() {
        return write("walk.json", R"({"keys": [
            {"time": 0, "position": [0, 1.6, 9.5], "look_at": [0, 1.4, 0]},
            {"time": 1, "position": [0, 1.6, 3.5], "look_at": [0, 1.4, -6]}]})");
    }
    static std::string frame_file(const std::string& name, int64_t frame) { return frame_file_name(name, frame); }
    std::vector<std::string> run_args(std::vector<std::string> more) {
        std::vector<std::string> args = {"run", "--scene", kCorridor, "--size", "24x16", "--spp", "1", "-o", path("f.png")};
        args.insert(args.end(), more.begin(), more.end());
        return args;
    }
    // The file's inode: an atomic rewrite renames a new file into place, so it changes.
    static ino_t inode(const std::string& p) {
        struct stat st {};
        return ::stat(p.c_str(), &st) == 0 ? st.st_ino : 0;
    }
    static std::string bytes(const std::string& p) {
        std::ifstream f(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), {});
    }
    // The picture without its header (which holds the render's seconds).
    static std::vector<float> pixels(const std::string& p) {
        int w = 0, h = 0;
        std::vector<float> rgb;
        EXPECT_EQ(read_image(p, w, h, rgb), "") << p;
        return rgb;
    }
};

TEST_F(CrexFramesCli, WritesEachFrameSkipsFinishedOnesAndForceRedoesThem) {
    const std::string path_file = walk();
    auto first = crex_cli(run_args({"--camera-path", path_file, "--frames", "3..5"}));
    ASSERT_EQ(first.exit_code, 0) << first.err;
    std::vector<std::string> frames = {path("f.0003.png"), path("f.0004.png"), path("f.0005.png")};
    std::vector<ino_t> inodes;
    std::vector<std::string> contents;
    std::vector<std::vector<float>> pictures;
    for (const auto& f : frames) {
        ASSERT_TRUE(std::filesystem::exists(f)) << f;
        inodes.push_back(inode(f));
        contents.push_back(bytes(f));
        pictures.push_back(pixels(f));
    }
    EXPECT_FALSE(std::filesystem::exists(path("f.png")));
    EXPECT_FALSE(std::filesystem::exists(path("f.0002.png")));
    EXPECT_TRUE(pictures[0] != pictures[2]) << "the camera moved";
    EXPECT_NE(first.err.find("frame 1/3 (0003): "), std::string::npos) << first.err;
    EXPECT_NE(first.err.find("frame 3/3 (0005): "), std::string::npos) << first.err;
    EXPECT_NE(first.out.find("3 frames: 3 rendered, 0 skipped"), std::string::npos) << first.out;

    // Again: every frame's file exists, so nothing is rendered and nothing touched.
    auto again = crex_cli(run_args({"--camera-path", path_file, "--frames", "3..5", "--format", "json"}));
    ASSERT_EQ(again.exit_code, 0) << again.err;
    auto j = nlohmann::json::parse(again.out);
    ASSERT_EQ(j["frames"].size(), 3u);
    for (size_t i = 0; i < 3; ++i) {
        EXPECT_TRUE(j["frames"][i]["skipped"].get<bool>());
        EXPECT_EQ(inode(frames[i]), inodes[i]) << frames[i];
        EXPECT_TRUE(bytes(frames[i]) == contents[i]) << frames[i];
    }
    EXPECT_EQ(j["skipped"], 3);

    // A frame lost: only it is rendered, to the same picture (frames do not depend on each
    // other without a cache).
    std::filesystem::remove(frames[1]);
    auto refill = crex_cli(run_args({"--camera-path", path_file, "--frames", "3..5"}));
    ASSERT_EQ(refill.exit_code, 0) << refill.err;
    EXPECT_NE(refill.err.find("frame 1/3 (0003): skipped"), std::string::npos) << refill.err;
    EXPECT_NE(refill.out.find("3 frames: 1 rendered, 2 skipped"), std::string::npos) << refill.out;
    EXPECT_TRUE(pixels(frames[1]) == pictures[1]);
    EXPECT_EQ(inode(frames[0]), inodes[0]);

    // --force renders them all again: new files in place, the same pictures.
    auto forced = crex_cli(run_args({"--camera-path", path_file, "--frames", "3..5", "--force", "--format", "json"}));
    ASSERT_EQ(forced.exit_code, 0) << forced.err;
    auto fj = nlohmann::json::parse(forced.out);
    for (size_t i = 0; i < 3; ++i) {
        const auto& f = fj["frames"][i];
        EXPECT_FALSE(f["skipped"].get<bool>());
        EXPECT_EQ(f["frame"], 3 + int(i));
        EXPECT_GT(f["rays"].get<double>(), 0);
        EXPECT_GT(f["seconds"].get<double>(), 0);
        EXPECT_EQ(f["records_made"], 0);  // no cache in this run
        if (i != 1) {
            EXPECT_NE(inode(frames[i]), inodes[i]) << frames[i];
        }
        EXPECT_TRUE(pixels(frames[i]) == pictures[i]) << frames[i];
    }
}

// A RADIANCE view per line: without --frames, every line is a frame.
TEST_F(CrexFramesCli, ViewFileLinesAreFrames) {
    const std::string views = write("walk.vf", "rview -vp 0 1.6 9 -vd 0 0 -1 -vu 0 1 0 -vh 60 -vv 45\n"
                                               "-vp 0 1.6 8 -vd 0 0 -1 -vu 0 1 0 -vh 60 -vv 45\n");
    auto r = crex_cli(run_args({"--camera-path", views, "-o", path("f.exr")}));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const char* f : {"f.0000.png", "f.0001.png", "f.0000.exr", "f.0001.exr"}) EXPECT_TRUE(std::filesystem::exists(path(f))) << f;
    EXPECT_FALSE(std::filesystem::exists(path("f.0002.png")));
}

// Case II (thesis 4.5): frames tagged high quality render with every selective variable at its
// maximum, the others selectively; by range, or by whether a tagged distractor is on screen.
// The pipeline's selective stage takes 1 spp where its map is 0 and 4 at its maximum, so a
// high-quality frame traces about four times the rays of the same frame rendered selectively.
TEST_F(CrexFramesCli, FramesTaggedHighQualityRenderAtTheMaximum) {
    const std::string pipe = write("t.pipe", "pipeline t {\n  preselective { spp 1 }\n  guidance { m = constant(0) }\n"
                                             "  selective { vary spp 1 .. 4 by m }\n}\n");
    const std::string walk_file = CREX_SOURCE_DIR "/examples/paths/corridor_walk.json";
    auto frames_of = [&](std::vector<std::string> more) {
        std::vector<std::string> args = {"run", pipe, "--scene", kCorridor, "--size", "24x16", "--camera-path", walk_file,
                                         "--force", "--format", "json", "-o", path("f.png")};
        args.insert(args.end(), more.begin(), more.end());
        auto r = crex_cli(args);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return nlohmann::json::parse(r.out.empty() ? "{}" : r.out).value("frames", nlohmann::json::array());
    };
    const auto plain = frames_of({"--frames", "0..54:54"});
    const auto ranged = frames_of({"--frames", "0..54:54", "--high-quality-frames", "1..5,54"});
    ASSERT_EQ(plain.size(), 2u);
    ASSERT_EQ(ranged.size(), 2u);
    EXPECT_EQ(ranged[0]["quality"], "selective");
    EXPECT_EQ(ranged[1]["quality"], "high");
    EXPECT_EQ(ranged[0]["rays"], plain[0]["rays"]) << "an untagged frame is the plain one";
    EXPECT_GT(ranged[1]["rays"].get<double>(), 3 * plain[1]["rays"].get<double>());
    // Frame 0 looks down the corridor at the poster (tagged a distractor); frame 54 has passed it.
    const auto by_distractor = frames_of({"--frames", "0..54:54", "--high-quality-without-distractors"});
    ASSERT_EQ(by_distractor.size(), 2u);
    EXPECT_EQ(by_distractor[0]["distractor_on_screen"], true);
    EXPECT_EQ(by_distractor[0]["quality"], "selective");
    EXPECT_EQ(by_distractor[1]["distractor_on_screen"], false);
    EXPECT_EQ(by_distractor[1]["quality"], "high");
    EXPECT_EQ(by_distractor[1]["rays"], ranged[1]["rays"]);
}

// --reuse-frames: frames after the first say what share of their pixels inherited how many
// samples, and trace fewer rays than they would alone; the first inherits nothing, and with
// --seed-per-frame (which --reuse-frames implies) traces the very rays of a frame alone.
TEST_F(CrexFramesCli, ReusedFramesSayWhatTheyInherited) {
    auto frames_of = [&](std::vector<std::string> more) {
        std::vector<std::string> args = {"run", "--scene", kCorridor, "--size", "48x32", "--spp", "8", "-o", path("r.png"), "--camera-path",
                                         walk(), "--frames", "0..1", "--force", "--format", "json"};
        args.insert(args.end(), more.begin(), more.end());
        auto r = crex_cli(args);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return nlohmann::json::parse(r.out.empty() ? "{}" : r.out).value("frames", nlohmann::json::array());
    };
    const auto alone = frames_of({"--seed-per-frame"}), reused = frames_of({"--reuse-frames", "8"});
    ASSERT_EQ(reused.size(), 2u);
    ASSERT_EQ(alone.size(), 2u);
    EXPECT_FALSE(reused[0].contains("inherited"));
    EXPECT_EQ(reused[0]["rays"], alone[0]["rays"]);
    ASSERT_TRUE(reused[1].contains("inherited"));
    EXPECT_GT(reused[1]["inherited"]["pixels"].get<double>(), 0.1);
    EXPECT_LE(reused[1]["inherited"]["samples"].get<double>(), 8.0);
    EXPECT_LT(reused[1]["rays"].get<double>(), alone[1]["rays"].get<double>());
    EXPECT_TRUE(reused[1]["stages"].contains("selective_seconds"));
}

// --sequence-budget: each frame's render budget is what is left over the frames left (its
// arithmetic: FrameBudget in tests/numerics); the first frame gets an even share.
TEST_F(CrexFramesCli, ASequenceBudgetGivesEachFrameItsShareOfWhatIsLeft) {
    auto r = crex_cli(run_args({"--camera-path", walk(), "--frames", "0..3", "--sequence-budget", "4s", "--format", "json"}));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["frames"].size(), 4u);
    // An even share, less the moments before the first frame (a loaded CI machine can stall
    // for tens of milliseconds there: the bound is loose, a wrong share is not within it).
    EXPECT_LE(j["frames"][0]["budget_seconds"].get<double>(), 1.0);
    EXPECT_GT(j["frames"][0]["budget_seconds"].get<double>(), 0.75);
    double spent = 0;
    for (size_t i = 0; i < 4; ++i) {
        const auto& f = j["frames"][i];
        ASSERT_TRUE(f.contains("budget_seconds")) << f;
        EXPECT_GT(f["budget_seconds"].get<double>(), 0) << f;
        // Never more than an even share of what was left when the frame began.
        EXPECT_LE(f["budget_seconds"].get<double>(), (4 - spent) / double(4 - i) + 1e-9) << f;
        spent += f["seconds"].get<double>();
    }
    EXPECT_DOUBLE_EQ(j["sequence_budget"]["seconds"].get<double>(), 4.0);
    EXPECT_GE(j["sequence_budget"]["took"].get<double>(), spent);
}

// `crex compare --frames`: two sequences frame by frame, a reference with some frames only;
// --flicker traced from the frames' headers is the flicker crex run measured as it rendered.
TEST_F(CrexFramesCli, CompareScoresSequencesAndTheirFlickerFromTheFiles) {
    const std::string walk_file = walk();
    auto test = crex_cli({"run", "--scene", kCorridor, "--size", "24x16", "--spp", "2", "--camera-path", walk_file, "--frames", "0..3",
                          "-o", path("t.exr"), "--format", "json"});
    ASSERT_EQ(test.exit_code, 0) << test.err;
    auto ref = crex_cli({"run", "--scene", kCorridor, "--size", "24x16", "--spp", "16", "--camera-path", walk_file, "--frames", "0..2:2",
                         "-o", path("r.exr"), "-q"});
    ASSERT_EQ(ref.exit_code, 0) << ref.err;
    auto c = crex_cli({"compare", path("t.exr"), path("r.exr"), "--frames", "0..3", "--metric", "rmse,flip", "--flicker", "--format", "json"});
    ASSERT_EQ(c.exit_code, 0) << c.err;
    const auto j = nlohmann::json::parse(c.out);
    const auto rendered = nlohmann::json::parse(test.out);
    ASSERT_EQ(j["frames"].size(), 4u);
    EXPECT_EQ(j["scored"].get<size_t>(), 2u);
    double flip = 0;
    for (int f = 0; f < 4; ++f) {
        const auto& one = j["frames"][f];
        EXPECT_EQ(one.contains("flip"), f % 2 == 0) << one;  // the reference has frames 0 and 2
        if (one.contains("flip")) {
            // The same figure as comparing the two files alone.
            auto alone = crex_cli({"compare", frame_file(path("t.exr"), f), frame_file(path("r.exr"), f), "--metric", "flip", "--format", "json"});
            EXPECT_DOUBLE_EQ(one["flip"].get<double>(), nlohmann::json::parse(alone.out)["flip"].get<double>());
            flip += one["flip"].get<double>() / 2;
        }
        const auto& run_frame = rendered["frames"][f];
        EXPECT_EQ(one.contains("flicker"), run_frame.contains("flicker")) << one;
        if (one.contains("flicker")) {
            EXPECT_NEAR(one["flicker"]["display_difference"].get<double>(), run_frame["flicker"]["display_difference"].get<double>(),
                        1e-3 * run_frame["flicker"]["display_difference"].get<double>() + 1e-6);
        }
    }
    EXPECT_DOUBLE_EQ(j["mean"]["flip"].get<double>(), flip);
    EXPECT_FALSE(j["flicker"].contains("reference"));  // frames 0 and 2 do not follow each other
    // A test frame missing is named; --flicker without --frames is a usage error.
    auto missing = crex_cli({"compare", path("t.exr"), path("r.exr"), "--frames", "0..4"});
    EXPECT_EQ(missing.exit_code, 3);
    EXPECT_NE(missing.err.find("t.0004.exr"), std::string::npos) << missing.err;
    auto alone = crex_cli({"compare", frame_file(path("t.exr"), 0), frame_file(path("r.exr"), 0), "--flicker"});
    EXPECT_EQ(alone.exit_code, 2) << alone.err;
    // A header whose view puts the camera beyond float rays' reach is said, not traced (Embree
    // aborted, exit 134).
    for (int f = 0; f < 2; ++f) {
        int w = 0, h = 0;
        ImageMetadata metadata;
        ASSERT_EQ(read_image_metadata(frame_file(path("t.exr"), f), w, h, metadata), "");
        for (ImageAttribute& a : metadata)
            if (f == 1 && a.name == "crex:view") a.value = std::string("-vp 0 1e300 0 -vd 0 0 -1 -vu 0 1 0");
        ImageLayer layer;
        layer.rgb = pixels(frame_file(path("t.exr"), f));
        ASSERT_EQ(write_image(frame_file(path("far.exr"), f), w, h, {layer}, metadata), "");
    }
    auto far = crex_cli({"compare", path("far.exr"), path("t.exr"), "--frames", "0..1", "--flicker"});
    EXPECT_NE(far.exit_code, 0);
    EXPECT_NE(far.exit_code, 134);
    EXPECT_NE(far.err.find("far.0001.exr: its view (crex:view) puts the camera farther from the scene"), std::string::npos) << far.err;
}

// --reference with a path names a sequence: each frame it has is scored as `crex compare`
// scores the two files, the others not; --report draws time, flicker and error per frame.
TEST_F(CrexFramesCli, AReferenceSequenceScoresTheFramesItHasAndTheReportShowsThem) {
    const std::string walk_file = walk();
    auto ref = crex_cli({"run", "--scene", kCorridor, "--size", "24x16", "--spp", "16", "--camera-path", walk_file, "--frames", "0..2:2",
                         "-o", path("r.exr"), "-q"});
    ASSERT_EQ(ref.exit_code, 0) << ref.err;
    auto r = crex_cli({"run", "--scene", kCorridor, "--size", "24x16", "--spp", "2", "--camera-path", walk_file, "--frames", "0..3", "-o",
                       path("t.exr"), "--reference", path("r.exr"), "--report", path("rep"), "--format", "json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["frames"].size(), 4u);
    for (int f = 0; f < 4; ++f) {
        const auto& one = j["frames"][f];
        ASSERT_EQ(one.contains("error"), f % 2 == 0) << one;  // the reference has frames 0 and 2
        if (!one.contains("error")) continue;
        EXPECT_EQ(one["error"]["reference"].get<std::string>(), frame_file(path("r.exr"), f));
        auto alone = crex_cli({"compare", frame_file(path("t.exr"), f), frame_file(path("r.exr"), f), "--metric", "flip,relmse", "--format", "json"});
        ASSERT_EQ(alone.exit_code, 0) << alone.err;
        const auto c = nlohmann::json::parse(alone.out);
        EXPECT_DOUBLE_EQ(one["error"]["flip"].get<double>(), c["flip"].get<double>());
        EXPECT_DOUBLE_EQ(one["error"]["relmse"].get<double>(), c["relmse"].get<double>());
        EXPECT_GT(one["error"]["flip"].get<double>(), 0);  // 2 spp against 16: not the same picture
    }
    // The report: a row per frame in its data, a picture per frame in its strip, the page last.
    std::ifstream csv(path("rep/frames.csv"));
    size_t lines = 0;
    for (std::string line; std::getline(csv, line);) ++lines;
    EXPECT_EQ(lines, 5u);
    for (int f = 0; f < 4; ++f) EXPECT_TRUE(std::filesystem::exists(path(fmt::format("rep/frames/frame_{:04d}.png", f)))) << f;
    const std::string page = bytes(path("rep/index.html"));
    EXPECT_NE(page.find("id=\"time-plot\""), std::string::npos);
    EXPECT_NE(page.find("data-series=\"FLIP vs reference\""), std::string::npos);
    // A reference of another size is refused before anything renders.
    auto other = crex_cli({"run", "--scene", kCorridor, "--size", "32x16", "--spp", "1", "--camera-path", walk_file, "--frames", "0..3",
                           "-o", path("u.exr"), "--reference", path("r.exr")});
    EXPECT_EQ(other.exit_code, 3);
    EXPECT_NE(other.err.find("is 24x16, the frames 32x16"), std::string::npos) << other.err;
    EXPECT_FALSE(std::filesystem::exists(frame_file(path("u.exr"), 0)));
    // So is a reference frame holding a NaN (exit 1, as a single frame's --reference): its FLIP
    // would be NaN, which the report and the JSON can only show as missing. (A float map written
    // by hand, which OpenImageIO reads whatever its name says: crex's writer keeps images finite.)
    std::vector<float> nan(24 * 16 * 3, 0.5f);
    nan[7] = std::nanf("");
    testing::write_pfm(frame_file(path("n.exr"), 2), 24, 16, nan);
    auto with_nan = crex_cli({"run", "--scene", kCorridor, "--size", "24x16", "--spp", "1", "--camera-path", walk_file, "--frames", "0..3",
                              "-o", path("v.exr"), "--reference", path("n.exr")});
    EXPECT_EQ(with_nan.exit_code, 1);
    EXPECT_NE(with_nan.err.find("holds 1 non-finite value (NaN or Inf)"), std::string::npos) << with_nan.err;
    EXPECT_FALSE(std::filesystem::exists(frame_file(path("v.exr"), 0)));
}

// --video: the frames as H.264 through ffmpeg (a package CI installs; optional for users),
// one video frame per frame of the sequence, skipped ones included, nothing left on failure.
TEST_F(CrexFramesCli, VideoHoldsEveryFrame) {
    if (find_video_encoder().empty()) GTEST_SKIP() << "ffmpeg is not installed (tools/debian-packages.txt lists it)";
    const std::string walk_file = walk();
    auto first = crex_cli(run_args({"--camera-path", walk_file, "--frames", "0..1", "-q"}));
    ASSERT_EQ(first.exit_code, 0) << first.err;
    auto r = crex_cli(run_args({"--camera-path", walk_file, "--frames", "0..4", "--video", path("walk.mp4")}));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("wrote " + path("walk.mp4") + " (5 frames at 30 fps)"), std::string::npos) << r.out;
    auto probe = testing::run_command({"/usr/bin/ffprobe", "-v", "error", "-count_frames", "-show_entries", "stream=nb_read_frames,width,height",
                                       "-of", "csv=p=0", path("walk.mp4")});
    EXPECT_EQ(probe.out, "24,16,5\n") << probe.err;
    // A container it does not write, and a folder that does not exist, are refused before rendering.
    auto avi = crex_cli(run_args({"--camera-path", walk_file, "--frames", "0", "--force", "--video", path("walk.avi")}));
    EXPECT_EQ(avi.exit_code, 2);
    EXPECT_NE(avi.err.find(".mp4, .mov or .mkv"), std::string::npos) << avi.err;
    auto nowhere = crex_cli(run_args({"--camera-path", walk_file, "--frames", "0", "--force", "--video", path("no/such/walk.mp4")}));
    EXPECT_EQ(nowhere.exit_code, 2) << nowhere.err;
    EXPECT_FALSE(std::filesystem::exists(path("walk.avi")));
}

// --budget N% and no profile: the first frame renders whole and its profile sizes the rest
// (thesis 5.4), each later frame's budget N % of the first frame's render.
TEST_F(CrexFramesCli, ABudgetInPercentIsOfTheFirstFramesFullRender) {
    const std::string pipe = CREX_SOURCE_DIR "/stdlib/pipelines/prog_tc.pipe";
    auto r = crex_cli({"run", pipe, "--scene", kCorridor, "--size", "24x16", "--camera-path", walk(), "--frames", "0..2", "--budget",
                       "50%", "-o", path("p.exr"), "--format", "json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["frames"].size(), 3u);
    EXPECT_FALSE(j["frames"][0].contains("budget_seconds")) << j["frames"][0];
    const double full = j["frames"][0]["render_seconds"].get<double>();
    for (int f = 1; f < 3; ++f) EXPECT_DOUBLE_EQ(j["frames"][f]["budget_seconds"].get<double>(), 0.5 * full) << j["frames"][f];
    // With a profile given, every frame's budget is of that profile, the first's too.
    auto save = crex_cli({"run", pipe, "--scene", kCorridor, "--size", "24x16", "--save-profile", path("prof.json"), "--no-budget", "-o", path("one.exr"), "-q"});
    ASSERT_EQ(save.exit_code, 0) << save.err;
    auto given = crex_cli({"run", pipe, "--scene", kCorridor, "--size", "24x16", "--camera-path", walk(), "--frames", "0..1", "--budget",
                           "50%", "--profile", path("prof.json"), "--budget-floor", "ok", "--force", "-o", path("p.exr"), "--format", "json"});
    ASSERT_EQ(given.exit_code, 0) << given.err;
    const auto g = nlohmann::json::parse(given.out);
    EXPECT_FALSE(g["frames"][0].contains("budget_seconds"));  // a --budget of every frame is not a sequence's: its JSON has none
}

TEST_F(CrexFramesCli, RefusesWhatDoesNotGoTogether) {
    const std::string path_file = walk();
    struct Case {
        std::vector<std::string> args;
        int exit;
        const char* says;
    };
    const std::vector<Case> cases = {
        {{"--frames", "0..2"}, 2, "--frames needs --camera-path"},
        {{"--force"}, 2, "--force is for frames along a camera path"},
        {{"--camera-path", path_file, "--frames", "5..2"}, 2, "the last frame 2 is before the first 5"},
        {{"--camera-path", path_file, "--frames", "0..2:0"}, 2, "STEP from 1"},
        {{"--camera-path", path_file, "--frames", "a..b"}, 2, "expected FIRST..LAST"},
        {{"--camera-path", path_file, "--frames", "25..31"}, 2, "it has frames 0..30 (0 s to 1 s)"},
        {{"--camera-path", write("brief.json", "{\"keys\": [{\"time\": 0.01, \"position\": [0, 1, 3], \"look_at\": [0, 1, 0]},"
                                               " {\"time\": 0.02, \"position\": [0, 1, 2], \"look_at\": [0, 1, 0]}]}")},
         2, "holds no whole frame at 30 fps"},
        {{"--camera-path", path_file, "--view", path_file}, 2, "--view does not go with --camera-path"},
        {{"--camera-path", path("missing.json")}, 3, "--camera-path"},
        {{"--high-quality-frames", "1"}, 2, "--high-quality-frames is for frames along a camera path"},
        {{"--camera-path", path_file, "--high-quality-frames", "0..2,x"}, 2, "'x': expected"},
        {{"--camera-path", path_file, "--frames", "0", "--high-quality-frames", "0"}, 2, "need a pipeline"},
        {{"--camera-path", write("bad.json", "{\"keys\": [\n  {\"time\": 0, \"position\": [0, 1], \"look_at\": [0, 0, 0]}]}")}, 1,
         "bad.json:2:27: error[E302]"},
        {{"--sequence-budget", "2s"}, 2, "--sequence-budget is for frames along a camera path"},
        {{"--video", path("v.mp4")}, 2, "--video is for frames along a camera path"},
        {{"--reuse-frames", "8"}, 2, "--reuse-frames is for frames along a camera path"},
        {{"--camera-path", path_file, "--reuse-frames", "-1"}, 2, "--reuse-frames"},
        {{"--seed-per-frame"}, 2, "--seed-per-frame is for frames along a camera path"},
        {{"--camera-path", path_file, "--sequence-budget", "10%"}, 2, "give the sequence's time in seconds"},
        {{"--camera-path", path_file, "--sequence-budget", "2s", "--budget", "1s"}, 2, "--sequence-budget does not go with --budget"},
        {{"--camera-path", path_file, "--sequence-budget", "soon"}, 2, "--sequence-budget soon"},
        {{"--camera-path", path_file, "--reference", "auto"}, 2, "give the reference sequence's name"},
        {{"--camera-path", path_file, "--frames", "0..2", "--reference", path("none.exr")}, 3, "no frame of 0 .. 2 exists"},
        // Cameras float rays cannot trace from: Embree aborted (exit 134) on each (camera_path_fuzzer).
        {{"--camera-path", write("far.json", "{\"keys\": [{\"time\": 0, \"position\": [0, 1e17, 3], \"look_at\": [0, 1e17, 0]},"
                                             " {\"time\": 1, \"position\": [0, 1, 3], \"look_at\": [0, 1, 0]}]}")},
         1, "--camera-path: frame 0: the camera is 1e+17 units from the scene, more than float rays can represent"},
        {{"--camera-path", write("huge.vf", "-vp 0 1.5e308 3 -vd 0 0 -1 -vu 0 1 0\n-vp 0 1.5 2.9 -vd 0.1 0 -1 -vu 0 1 0\n")}, 1,
         "huge.vf:1:1: error[E303]: the views' positions are too far apart"},
        {{"--camera-path", write("huge.json", "{\"keys\": [{\"time\": 0, \"position\": [0, 1e300, 3], \"look_at\": [0, 0, 0]},"
                                              " {\"time\": 1, \"position\": [0, 1, 3], \"look_at\": [0, 0, 0]}]}")},
         1, "huge.json:1:10: error[E303]: keys: the positions are too far apart"},
        // No "up": the scene camera's, which the path's last direction is parallel to.
        {{"--camera-path", write("up.json", "{\"keys\": [{\"time\": 0, \"position\": [0, 1, 3], \"direction\": [0, 0, -1]},"
                                            " {\"time\": 1, \"position\": [0, 1, 2], \"direction\": [0, 1, 0]}]}")},
         1, "--camera-path: frame 30: the camera is looking along its up vector"},
        {{"--view", write("far.vf", "-vp 0 2e18 3 -vd 0 0 -1 -vu 0 1 0\n")}, 1, "far.vf:1:1: error[E303]: view: the camera is 2e+18 units"},
    };
    for (const Case& c : cases) {
        auto r = crex_cli(run_args(c.args));
        EXPECT_EQ(r.exit_code, c.exit) << c.args.back() << ": " << r.err;
        EXPECT_NE(r.err.find(c.says), std::string::npos) << c.args.back() << ": " << r.err;
    }
    EXPECT_FALSE(std::filesystem::exists(path("f.0000.png")));
}

}  // namespace
}  // namespace crex
