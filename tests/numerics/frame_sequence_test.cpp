// Frames along a camera path with the irradiance cache carried from frame to frame (issue 36):
// a carried frame is the image a cold render of that frame makes, within the cache's own
// noise, for far fewer new records.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "runtime/api/frame_flicker.h"
#include "runtime/api/frame_sequence.h"
#include "runtime/scene/load_scene.h"
#include "runtime/io/image_io.h"
#include "runtime/scene/camera_path_file.h"
#include "tests/support/scratch_folder.h"

namespace crex {
namespace {

// A walk down the corridor at 6 m/s: frames 0.2 m apart at 30 fps (the issue's spacing).
const char* kWalk = R"({"keys": [
    {"time": 0, "position": [0, 1.6, 9.5], "look_at": [0, 1.4, 0]},
    {"time": 1, "position": [0, 1.6, 3.5], "look_at": [0, 1.4, -6]}]})";

class FrameSequence : public testing::ScratchFolderTest {
protected:
    FrameSequence() : ScratchFolderTest("crex_frame_sequence_") {}

    void SetUp() override {
        ScratchFolderTest::SetUp();
        DiagnosticSink sink;
        InputSpec spec;
        spec.scene = CREX_SOURCE_DIR "/examples/scenes/corridor/scene.json";
        in_ = load_run_inputs(spec, sink);
        ASSERT_TRUE(in_.ready()) << in_.failure;
        SourceFile file("walk.json", kWalk);
        path_ = read_camera_path(file, 30, sink);
        ASSERT_TRUE(path_);
        RunOptions o;
        o.width = 32, o.height = 24, o.spp = 4;
        o.irradiance_cache = true;
        o.ab = 2, o.ad = 64;      // a small cache: CI renders it under ASan
        o.caustic_photons = 0;    // the door pane's caustics are not what this is about
        run_ = resolve_run(in_.plan, o);
    }

    std::vector<FrameRun> render(const std::string& name, FrameRange frames, bool carry, float reuse = 0, bool seed_per_frame = false,
                                 bool new_positions = false) {
        RunFiles files;
        files.images = {path(name + ".exr")};
        SequenceOptions o;
        o.path = &*path_;
        o.frames = frames;
        o.carry_cache = carry;
        o.reuse_frames = reuse;
        o.seed_per_frame = seed_per_frame;
        o.new_positions_every_frame = new_positions;
        RunObserver nobody;
        return render_frames(in_, run_, files, o, nobody);
    }

    /// The camera stands still, 3 m from the corridor's far end, for the whole path.
    void stand_still() {
        DiagnosticSink sink;
        SourceFile file("still.json", R"({"timing": "keys", "keys": [
            {"time": 0, "position": [0, 1.6, 6.5], "look_at": [0, 1.4, 0]},
            {"time": 1, "position": [0, 1.6, 6.5], "look_at": [0, 1.4, 0]}]})");
        path_ = read_camera_path(file, 30, sink);
        ASSERT_TRUE(path_);
    }

    std::vector<float> image(const std::string& name, int64_t frame) {
        int w = 0, h = 0;
        std::vector<float> rgb;
        EXPECT_EQ(read_image(frame_file_name(path(name + ".exr"), frame), w, h, rgb), "");
        EXPECT_EQ(w, 32);
        return rgb;
    }

    /// Frame `frame` of sequence `a` against the same frame of `b` (or frame `frame_b`): mean
    /// |a - b| over mean |b|, 1 where b is black.
    double relative_difference(const std::string& a, const std::string& b, int64_t frame, std::optional<int64_t> frame_b = {}) {
        const std::vector<float> x = image(a, frame), y = image(b, frame_b.value_or(frame));
        EXPECT_EQ(x.size(), y.size());
        double diff = 0, sum = 0;
        for (size_t i = 0; i < std::min(x.size(), y.size()); ++i) diff += std::abs(double(x[i]) - y[i]), sum += std::abs(double(y[i]));
        return sum > 0 ? diff / sum : 1.0;
    }

    RunInputs in_;
    std::optional<CameraPath> path_;
    ResolvedRun run_;
};

// Frame 2 after frame 0 (records carried) against frame 2 alone. Both trace the same camera
// samples (keyed by pixel and sample index); only D differs, interpolated from other records
// of the same accuracy. Ward's criterion (aa = 0.15) bounds the interpolation's estimated
// error wherever a record is reused, and each record's own estimate has the noise of its 64
// hemisphere rays (about 12 %), averaged over the several records a pixel blends: the carried
// image measured 0.6 % from the cold one (mean |a - b| over mean b), for 609 new records
// against 3,081. 2 % leaves room for the records' noise under other rounding (a sanitizer
// build, another compiler) and is still far below a wrong camera: frame 0's image is 80 %
// from frame 2's.
TEST_F(FrameSequence, CarriedCacheGivesTheColdImageWithFewerRecords) {
    const auto carried = render("carried", {0, 2, 2}, true);
    const auto cold = render("cold", {2, 2, 1}, false);
    ASSERT_EQ(carried.size(), 2u);
    ASSERT_EQ(cold.size(), 1u);
    EXPECT_EQ(carried[1].records_reused, carried[0].records_made);
    EXPECT_EQ(cold[0].records_reused, 0u);
    EXPECT_GT(cold[0].records_made, 0u);
    EXPECT_LT(carried[1].records_made * 2, cold[0].records_made) << "carried " << carried[1].records_made << ", cold "
                                                                  << cold[0].records_made;
    EXPECT_LT(relative_difference("carried", "cold", 2), 0.02) << "carried against cold";
    EXPECT_GT(relative_difference("carried", "cold", 0, 2), 0.2) << "frame 0 is another view";
}

// Flicker (frame_flicker.h) is noise that changes between frames: path traced (no cache, so
// every pixel's noise is its own), frames at 16 spp flicker less than at 2 spp. Noise alone
// would give sqrt(8) = 2.8; sub-pixel shifts at edges add a floor the same at any spp (at
// 32x24 a large share): measured 0.036 against 0.019 (1.9x), so the bound is 1.5. (At 160x120,
// 4, 16 and 64 spp gave 0.038, 0.019 and 0.010: 2x for every 4x, as noise should.)
TEST_F(FrameSequence, FlickerFallsWithSamplesAndTheFirstFrameHasNone) {
    run_.settings.irradiance_cache.reset();
    auto flicker_at = [&](uint32_t spp) {
        run_.settings.spp = spp;
        const auto frames = render("spp" + std::to_string(spp), {0, 2, 1}, true);
        EXPECT_FALSE(frames[0].flicker.has_value()) << "nothing before the first frame";
        double sum = 0;
        for (size_t i = 1; i < frames.size(); ++i) {
            EXPECT_TRUE(frames[i].flicker.has_value());
            EXPECT_GT(frames[i].flicker_matched, 0.5);  // frames 0.2 m apart see mostly the same points
            sum += frames[i].flicker.value_or(0);
        }
        return sum / 2;
    };
    const double few = flicker_at(2), many = flicker_at(16);
    EXPECT_GT(few, 0);
    EXPECT_GT(few / many, 1.5) << "2 spp: " << few << ", 16 spp: " << many;
}

// --reuse-frames 8 (frame_reuse.h): path traced at 8 spp, frames after the first inherit up to
// 8 samples where they see inside the surfaces the frame before saw, so they trace fewer rays,
// flicker less (their noise is partly the frame before's), and stay as close to a converged
// frame as frames rendered alone (mean |a - b| over mean b against 128 spp). The frames alone
// have a seed per frame, as frames that inherit do: with one seed for all, their noise is
// partly the same pattern every frame, which flickers less than new noise. At 32x24 (what CI
// runs) half the pixels are at an edge, which inherits nothing: measured rays 0.56 of alone,
// flicker 0.81, error 0.100 with reuse against 0.108 alone. (At 160x120: 89 % of pixels
// inherit, flicker 0.0107 against 0.0198.) The bounds leave room for other rounding while
// failing a blend that weighed the wrong way or inherited across edges (before edges were
// left out: error 0.30, 2.6 times the frames alone).
TEST_F(FrameSequence, InheritedFramesTraceFewerRaysFlickerLessAndStayAsClose) {
    run_.settings.irradiance_cache.reset();
    run_.settings.spp = 128;
    render("converged", {2, 2, 1}, false);
    run_.settings.spp = 8;
    const auto alone = render("alone", {0, 2, 1}, true, 0, true);  // the seeds the reused frames have
    const auto reused = render("reused", {0, 2, 1}, true, 8);
    ASSERT_EQ(alone.size(), 3u);
    ASSERT_EQ(reused.size(), 3u);
    EXPECT_EQ(reused[0].rays, alone[0].rays) << "the first frame inherits nothing";
    EXPECT_EQ(reused[0].inherited_pixels, 0.0);
    EXPECT_GT(reused[2].inherited_pixels, 0.3);
    EXPECT_GT(reused[2].inherited_samples, 7.0);
    const double rays = double(reused[1].rays + reused[2].rays) / double(alone[1].rays + alone[2].rays);
    EXPECT_LT(rays, 0.7);
    const double flicker = (reused[1].flicker.value_or(1) + reused[2].flicker.value_or(1)) / (alone[1].flicker.value_or(0) + alone[2].flicker.value_or(0));
    EXPECT_LT(flicker, 0.95);
    const double with = relative_difference("reused", "converged", 2), without = relative_difference("alone", "converged", 2);
    EXPECT_LT(with, 1.25 * without) << "rays " << rays << ", flicker " << flicker;
}

// The same for a pipeline whose preview takes 8 samples a pixel: a later frame's preview takes
// one sample of its own where the pixel inherits, all 8 where it does not (a pixel new to the
// frame). Its preview took all 8 in every pixel of every frame before: rays 1.00 of alone,
// where a plain crex's were 0.56. Now: rays 0.56, error against 128 spp 0.100 (alone 0.108).
TEST_F(FrameSequence, APipelinesPreviewTakesOnlyWhatItsPixelsDoNotInherit) {
    {
        std::ofstream f(path("p.pipe"));
        f << R"(pipeline p {
  preselective { crex "(TTMRSGD)*"  spp 8 }
  guidance { sal = saliency(preview) }
  selective { vary shadow_rays 1 .. 1 by sal }
})";
    }
    DiagnosticSink sink;
    InputSpec spec;
    spec.file = path("p.pipe");
    spec.scene = CREX_SOURCE_DIR "/examples/scenes/corridor/scene.json";
    in_ = load_run_inputs(spec, sink);
    ASSERT_TRUE(in_.ready()) << in_.failure;
    RunOptions o;
    o.width = 32, o.height = 24;
    run_ = resolve_run(in_.plan, o);
    run_.settings.irradiance_cache.reset();
    run_.settings.spp = 128;
    render("converged", {2, 2, 1}, false);
    run_ = resolve_run(in_.plan, o);
    run_.settings.irradiance_cache.reset();
    const auto alone = render("alone", {0, 2, 1}, true, 0, true);
    const auto reused = render("reused", {0, 2, 1}, true, 8);
    ASSERT_EQ(reused.size(), 3u);
    EXPECT_EQ(reused[0].rays, alone[0].rays) << "the first frame inherits nothing";
    EXPECT_GT(reused[2].inherited_pixels, 0.3);
    const double rays = double(reused[1].rays + reused[2].rays) / double(alone[1].rays + alone[2].rays);
    EXPECT_LT(rays, 0.7);
    const double with = relative_difference("reused", "converged", 2), without = relative_difference("alone", "converged", 2);
    EXPECT_LT(with, 1.25 * without) << "rays " << rays;
}

// A camera that stands still, path traced at 4 spp with --reuse-frames 64: every frame after
// the first takes one sample of its own and inherits the rest, so frame 6 holds 10 samples
// where they see inside a surface, and comes closer to a converged frame than frame 0 did -
// but only if each frame draws new samples. With the seed of frame 0 in every frame (the bug
// this guards), a pixel's own sample repeated the first of the samples it inherited, the
// camera's motion dragged that fixed pattern into streaks, and a still camera gained nothing:
// measured error frame 6 / frame 0 1.12 with it (0.300 / 0.267), 0.70 with a seed per frame.
// The pixels that inherit nothing (a third here) keep frame 0's positions since
// (APixelThatInheritsNothingKeepsItsSamplePositions), so their error is frame 0's in every
// frame, where a new draw was as likely better as worse (a few bright outline pixels hold half
// of it): 0.89 at this seed, 0.87 to 0.90 at seeds 7 to 9; the bound still fails 1.12.
TEST_F(FrameSequence, InheritingFramesDrawNewSamplesEveryFrame) {
    ASSERT_NO_FATAL_FAILURE(stand_still());
    run_.settings.irradiance_cache.reset();
    run_.settings.spp = 256;
    render("still_converged", {0, 0, 1}, false);
    run_.settings.spp = 4;
    const auto frames = render("still", {0, 6, 1}, true, 64);
    ASSERT_EQ(frames.size(), 7u);
    EXPECT_GT(frames[6].inherited_pixels, 0.3);
    const double first = relative_difference("still", "still_converged", 0), last = relative_difference("still", "still_converged", 6, 0);
    EXPECT_LT(last, 0.95 * first) << "frame 0: " << first << ", frame 6: " << last;
}

// The same still camera, --reuse-frames 2, path traced: a pixel asking for 6 samples takes 2 of
// its own a frame beside 4 inherited (own_samples: at least a third of what it asks for), so
// its own samples weigh a third of it, as one sample beside 2 does at 3 spp, and their mean is
// half as noisy: it flickers about 1/sqrt(2) as much (stationary blend: the frame-to-frame
// difference's variance is a^2 v 2 / (2 - a), own weight a, own mean's variance v). With the
// cap at 2 samples it took 4 beside 2 and weighed two thirds: 1.12 times the flicker where it
// inherits. Measured, frames 3-5 (a third of the pixels at 32x24 are outlines, which inherit
// nothing and take all 6 afresh either way): 0.69 of 3 spp's flicker for 2.0 times its rays;
// with the old cap 0.85 for 2.8 times the rays. The bound fails the old cap.
TEST_F(FrameSequence, APixelAskingForMoreSamplesTakesMoreEveryFrameAndFlickersLess) {
    ASSERT_NO_FATAL_FAILURE(stand_still());
    run_.settings.irradiance_cache.reset();
    auto walk = [&](uint32_t spp) {
        run_.settings.spp = spp;
        const auto frames = render("still_" + std::to_string(spp), {0, 5, 1}, true, 2);
        EXPECT_EQ(frames.size(), 6u);
        double flicker = 0, rays = 0;
        for (size_t f = 3; f < frames.size(); ++f) flicker += frames[f].flicker.value_or(0), rays += double(frames[f].rays);
        return std::pair{flicker, rays};
    };
    const auto [one, one_rays] = walk(3);
    const auto [two, two_rays] = walk(6);
    EXPECT_GT(two_rays, 1.5 * one_rays) << "two samples a frame where the pixel inherits";
    EXPECT_GT(one, 0);
    EXPECT_LT(two, 0.78 * one) << "3 spp: " << one << ", 6 spp: " << two;
}

// The same still camera: a pixel that inherits nothing (where two surfaces meet in its 3x3
// neighbourhood, a third of the pixels at 32x24) draws all its samples every frame. At new
// positions in its pixel each frame, its blend of the two surfaces jumped from frame to frame;
// at the same positions (RunSettings::position_seed) only its light is new. Measured, frames
// 1-4 through the cache with 16 shadow rays a hit (as walks render): flicker 0.00136 at the
// same positions against 0.00543 at new ones (0.25). The bound fails positions drawn afresh
// and leaves room for other rounding.
TEST_F(FrameSequence, APixelThatInheritsNothingKeepsItsSamplePositions) {
    ASSERT_NO_FATAL_FAILURE(stand_still());
    RunOptions o;  // the fixture's cache, direct light quiet (16 shadow rays), as walks render
    o.width = 32, o.height = 24, o.spp = 4, o.shadow_rays = 16;
    o.irradiance_cache = true;
    o.ab = 2, o.ad = 64;
    o.caustic_photons = 0;
    run_ = resolve_run(in_.plan, o);
    auto flicker = [](const std::vector<FrameRun>& frames) {
        double sum = 0;
        for (size_t k = 1; k < frames.size(); ++k) sum += frames[k].flicker.value_or(1);
        return sum / static_cast<double>(frames.size() - 1);
    };
    const auto kept = render("kept", {0, 4, 1}, true, 8);
    const auto moved = render("moved", {0, 4, 1}, true, 8, false, true);
    ASSERT_EQ(kept.size(), 5u);
    ASSERT_EQ(moved.size(), 5u);
    EXPECT_EQ(kept[0].rays, moved[0].rays) << "frame 0: every pixel at frame 0's positions";
    EXPECT_LT(kept[4].inherited_pixels, 0.9) << "some pixels inherit nothing";
    EXPECT_LT(flicker(kept), 0.5 * flicker(moved)) << "kept " << flicker(kept) << ", moved " << flicker(moved);
}

// A walk with --reuse-frames stopped after frame 1 and run again: frame 2 inherits from frame
// 1's file (every pixel counted at the cap, as it was: frame 1's pixels had 8 or 9 samples),
// so it is the frame the walk would have made. Measured: identical (the EXR holds 32-bit
// floats), where a frame 2 that inherited nothing is 2.2 % away (another 8 samples' noise).
TEST_F(FrameSequence, ARestartedWalkInheritsFromTheFinishedFrameBefore) {
    run_.settings.irradiance_cache.reset();
    run_.settings.spp = 8;
    render("whole", {0, 2, 1}, true, 8);
    render("restarted", {0, 1, 1}, true, 8);
    const auto again = render("restarted", {0, 2, 1}, true, 8);
    ASSERT_EQ(again.size(), 3u);
    EXPECT_TRUE(again[0].skipped);
    EXPECT_TRUE(again[1].skipped);
    EXPECT_GT(again[2].inherited_pixels, 0.3);
    render("fresh", {2, 2, 1}, true, 8);
    const double restarted = relative_difference("restarted", "whole", 2), fresh = relative_difference("fresh", "whole", 2);
    EXPECT_LT(restarted, 0.001) << "fresh: " << fresh;
    EXPECT_GT(fresh, 0.01);
}

// Two frames from one camera match every pixel that sees something, each with itself: the
// flicker is then the plain mean display difference of the two images.
// A frame's files are written while the next frame renders (frame_writer.h). When one cannot
// be written, the sequence stops naming that frame, the frames before it are whole on disk and
// nothing after it is: a restart renders from the failed frame on.
TEST_F(FrameSequence, AFrameThatCannotBeWrittenStopsTheSequenceWithTheFramesBeforeKept) {
    RunFiles files;
    files.images = {path("walk.exr"), path("walk.png")};
    std::filesystem::create_directories(frame_file_name(path("walk.png"), 1));  // frame 1's PNG cannot be made
    SequenceOptions o;
    o.path = &*path_;
    o.frames = FrameRange{0, 3, 1};
    o.flicker = false;
    RunObserver nobody;
    try {
        render_frames(in_, run_, files, o, nobody);
        ADD_FAILURE() << "the sequence went on past a frame it could not write";
    } catch (const FrameWriteError& e) {
        EXPECT_NE(std::string(e.what()).find("frame 1:"), std::string::npos) << e.what();
    }
    for (const char* ext : {".exr", ".png"}) {
        EXPECT_TRUE(std::filesystem::is_regular_file(frame_file_name(path(std::string("walk") + ext), 0))) << ext;
        EXPECT_FALSE(std::filesystem::exists(frame_file_name(path(std::string("walk") + ext), 2))) << ext;
        EXPECT_FALSE(std::filesystem::exists(frame_file_name(path(std::string("walk") + ext), 3))) << ext;
    }
    EXPECT_FALSE(std::filesystem::exists(frame_file_name(path("walk.exr"), 1)));  // all or none
    (void)image("walk", 0);  // frame 0 reads back whole
}

// A walk builds its scene once, before the first frame; a texture larger than the texture
// cache is then read through a tiled copy, whose making took a minute for a 30000x30000 PNG.
// It is said as the first frame's "setup" progress, as a single render says it (a walk used
// to make it without a word).
TEST_F(FrameSequence, TheFirstFramesTiledCopyIsSaidAsSetupProgress) {
    const std::string cache = path("cache");
    ::setenv("CREX_CACHE", cache.c_str(), 1);
    ImageLayer layer;
    layer.rgb.assign(size_t{1200} * 1200 * 3, 0.5f);  // 23 MB with its MIP levels: over 16 MiB
    ASSERT_EQ(write_image(path("big.exr"), 1200, 1200, {layer}), "");
    std::ofstream(path("textured.json")) << R"({
      "materials": [{"name": "t", "type": "plastic", "color": {"file": "big.exr"}}],
      "shapes": [{"type": "mesh", "material": "t", "vertices": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]],
                  "triangles": [[0, 1, 2], [0, 2, 3]], "uvs": [[0, 1], [1, 1], [1, 0], [0, 0]]}],
      "background": [1, 1, 1]})";
    DiagnosticSink sink;
    InputSpec spec;
    spec.scene = path("textured.json");
    in_ = load_run_inputs(spec, sink);
    ASSERT_TRUE(in_.ready()) << in_.failure;
    RunOptions ro;
    ro.width = 16, ro.height = 12, ro.spp = 1;
    ro.max_memory = size_t{128} << 20;  // the texture cache's least: 16 MiB
    run_ = resolve_run(in_.plan, ro);
    RunFiles files;
    files.images = {path("t.exr")};
    SequenceOptions o;
    o.path = &*path_;
    o.frames = FrameRange{0, 1, 1};
    o.flicker = false;
    std::vector<RunProgress> setup;
    ProgressFunction watch([&](const RunProgress& p) {
        if (p.stage == "setup") setup.push_back(p);
    });
    const auto frames = render_frames(in_, run_, files, o, watch);
    ::unsetenv("CREX_CACHE");
    ASSERT_EQ(frames.size(), 2u);
    ASSERT_FALSE(setup.empty());
    EXPECT_NE(setup.front().step.find("tiled copy of big.exr (1200x1200)"), std::string::npos) << setup.front().step;
    EXPECT_DOUBLE_EQ(setup.back().fraction, 1.0);
    EXPECT_TRUE(std::filesystem::is_directory(std::filesystem::path(cache) / "textures"));
}

TEST(FrameFlicker, OneCameraTwiceIsThePixelwiseDifference) {
    const Scene scene = *builtin_scene("cornell");
    const RenderScene rs(scene);
    const int w = 16, h = 12;
    const FrameGeometry g = frame_geometry(rs, w, h);
    std::vector<float> a(3 * w * h), b(3 * w * h);
    double expected = 0;
    size_t seen = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        a[i] = static_cast<float>((i * 37 % 101) / 100.0), b[i] = static_cast<float>((i * 53 % 97) / 96.0);
        if (g.shape[i / 3] >= 0) expected += std::abs(double(a[i]) - b[i]), seen += i % 3 == 0;
    }
    ASSERT_GT(seen, size_t(w * h / 2));
    const auto f = frame_flicker(g, b, g, a, rs.embree->origin_offset());
    ASSERT_TRUE(f.has_value());
    EXPECT_NEAR(f->difference, expected / (3.0 * double(seen)), 1e-9);
    EXPECT_DOUBLE_EQ(f->matched, double(seen) / (w * h));
    EXPECT_EQ(frame_flicker(g, a, g, a, rs.embree->origin_offset())->difference, 0.0);
}

// A point within half a pixel of the previous frame's border has taps off that frame. Its
// first tap off the top row read the pixel array at index -1 (a crash about one walk in 60
// on the room turn at 320x240, where the turn brings points in over the border; under the
// sanitizers, a read before the array). It gets no taps; every other pixel keeps its own.
TEST(FrameReuse, APointAtThePreviousFramesBorderHasNoTapsAndReadsNothingOffIt) {
    const Scene scene = *builtin_scene("cornell");
    const RenderScene rs(scene);
    const int w = 16, h = 12;
    const FrameGeometry previous = frame_geometry(rs, w, h);
    const CameraRays rays(previous.camera, w, h, rs.embree->origin_offset());
    const size_t centre = static_cast<size_t>(h / 2) * w + w / 2;
    ASSERT_GE(previous.shape[centre], 0);
    for (int dy = -1; dy <= 1; ++dy)  // inside its shape, so its taps are looked for
        for (int dx = -1; dx <= 1; ++dx) ASSERT_EQ(previous.shape[centre + static_cast<size_t>(dy * w + dx)], previous.shape[centre]);
    // Points on the previous camera's rays through a quarter pixel inside each corner: every
    // one of them has a tap off the frame (x or y one pixel beyond it).
    for (auto [fx, fy] : {std::pair{w - 0.25, 0.25}, std::pair{0.25, 0.25}, std::pair{0.25, h - 0.25}, std::pair{w - 0.25, h - 0.25}}) {
        FrameGeometry current = previous;
        Vec3 origin, dir;
        ASSERT_TRUE(rays.generate(fx, fy, origin, dir));
        current.point[centre] = origin + normalize_or_zero(dir) * 1.0;
        const std::vector<PixelTaps> taps = previous_taps(previous, current, rs.embree->origin_offset());
        ASSERT_EQ(taps.size(), previous.point.size());
        for (size_t i = 0; i < 4; ++i) EXPECT_EQ(taps[centre].pixel[i], -1) << fx << "," << fy;
        // The same camera twice: each other pixel inside a shape takes itself, whole.
        size_t own = 0;
        for (size_t p = 0; p < taps.size(); ++p)
            if (p != centre && taps[p].pixel[0] >= 0) {
                EXPECT_EQ(taps[p].pixel[0], static_cast<int32_t>(p));
                EXPECT_FLOAT_EQ(taps[p].weight[0], 1.0f);
                ++own;
            }
        EXPECT_GT(own, static_cast<size_t>(w * h / 4));
    }
}

// Under mpirun each process renders a run of consecutive frames: every frame once, in order,
// shares of nearly equal length (tests/mpi: the frames equal one process's).
TEST(FrameShare, EveryFrameOnceInRunsOfNearlyEqualLength) {
    for (size_t frames : {0, 1, 5, 7, 90})
        for (int processes : {1, 2, 3, 8}) {
            size_t next = 0, shortest = frames, longest = 0;
            for (int p = 0; p < processes; ++p) {
                const auto [first, end] = frame_share(frames, processes, p);
                EXPECT_EQ(first, next) << frames << " frames, process " << p << " of " << processes;
                ASSERT_LE(first, end);
                shortest = std::min(shortest, end - first), longest = std::max(longest, end - first);
                next = end;
            }
            EXPECT_EQ(next, frames) << frames << " frames on " << processes;
            EXPECT_LE(longest - shortest, 1u) << frames << " frames on " << processes;
        }
}

// A sequence budget: an even share at first; a frame after slow ones gets less, after fast
// ones more; set-up and writing come off each frame's render budget; never nothing.
TEST(FrameBudget, WhatIsLeftOverTheFramesLeft) {
    EXPECT_DOUBLE_EQ(frame_budget(10, 0, 0, 10, 10), 1.0);
    EXPECT_DOUBLE_EQ(frame_budget(10, 4, 0, 8, 10), 0.75);   // two frames took 2 s each
    EXPECT_DOUBLE_EQ(frame_budget(10, 1, 0, 8, 10), 1.125);  // two took 0.5 s each
    EXPECT_DOUBLE_EQ(frame_budget(10, 1, 0.125, 8, 10), 1.0);
    EXPECT_DOUBLE_EQ(frame_budget(10, 12, 0, 3, 10), 1e-3);  // over already: a thousandth of a share
    EXPECT_DOUBLE_EQ(frame_budget(10, 0, 0, 0, 10), 1e-3);
    EXPECT_TRUE(std::isfinite(frame_budget(10, std::nan(""), 0, 3, 10)));
}

// What a process tells the lead of a frame is the frame, warnings and notes included.
TEST(FrameShare, AFrameToldToTheLeadIsTheFrame) {
    FrameRun f;
    f.frame = 12, f.time = 0.4, f.seconds = 1.5, f.render_seconds = 1.25, f.records_made = 321, f.records_reused = 4000;
    f.budget_seconds = 0.75;
    f.rays = 123456789012, f.flicker = 0.0123, f.flicker_matched = 0.96, f.high_quality = true, f.distractor_on_screen = false;
    f.files = {"out/a.0012.exr", "out/a.0012.png"};
    f.notes = {"a note"};
    f.warnings.push_back(run_diagnostic("W401", "walk.pipe:3:5", "a step leaves D without rays"));
    const nlohmann::json told = frame_to_json(f, 7);
    EXPECT_EQ(told["index"].get<size_t>(), 7u);
    const FrameRun back = frame_from_json(nlohmann::json::parse(told.dump()));
    EXPECT_EQ(back.frame, f.frame);
    EXPECT_EQ(back.time, f.time);
    EXPECT_EQ(back.seconds, f.seconds);
    EXPECT_EQ(back.render_seconds, f.render_seconds);
    EXPECT_EQ(back.records_made, f.records_made);
    EXPECT_EQ(back.records_reused, f.records_reused);
    EXPECT_EQ(back.rays, f.rays);
    EXPECT_EQ(back.flicker, f.flicker);
    EXPECT_EQ(back.flicker_matched, f.flicker_matched);
    EXPECT_EQ(back.high_quality, f.high_quality);
    EXPECT_EQ(back.distractor_on_screen, f.distractor_on_screen);
    EXPECT_EQ(back.files, f.files);
    EXPECT_EQ(back.budget_seconds, f.budget_seconds);
    EXPECT_EQ(back.notes, f.notes);
    ASSERT_EQ(back.warnings.size(), 1u);
    EXPECT_EQ(back.warnings[0].code, "W401");
    EXPECT_EQ(back.warnings[0].where, "walk.pipe:3:5");
    EXPECT_EQ(back.warnings[0].message, f.warnings[0].message);
    EXPECT_EQ(back.warnings[0].severity, f.warnings[0].severity);
    FrameRun skipped;
    skipped.frame = 3, skipped.skipped = true, skipped.files = {"x.0003.exr"};
    const FrameRun skipped_back = frame_from_json(frame_to_json(skipped, 0));
    EXPECT_TRUE(skipped_back.skipped);
    EXPECT_EQ(skipped_back.files, skipped.files);
}

}  // namespace
}  // namespace crex
