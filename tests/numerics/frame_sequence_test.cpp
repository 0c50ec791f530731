// Frames along a camera path with the irradiance cache carried from frame to frame (issue 36):
// a carried frame is the image a cold render of that frame makes, within the cache's own
// noise, for far fewer new records.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "runtime/api/frame_sequence.h"
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

    std::vector<FrameRun> render(const std::string& name, FrameRange frames, bool carry) {
        RunFiles files;
        files.images = {path(name + ".exr")};
        SequenceOptions o;
        o.path = &*path_;
        o.frames = frames;
        o.carry_cache = carry;
        RunObserver nobody;
        return render_frames(in_, run_, files, o, nobody);
    }

    std::vector<float> image(const std::string& name, int64_t frame) {
        int w = 0, h = 0;
        std::vector<float> rgb;
        EXPECT_EQ(read_image(frame_file_name(path(name + ".exr"), frame), w, h, rgb), "");
        EXPECT_EQ(w, 32);
        return rgb;
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
    auto mean_relative = [](const std::vector<float>& a, const std::vector<float>& b) {
        double diff = 0, sum = 0;
        for (size_t i = 0; i < a.size(); ++i) diff += std::abs(double(a[i]) - b[i]), sum += std::abs(double(b[i]));
        return sum > 0 ? diff / sum : 1.0;
    };
    const std::vector<float> warm = image("carried", 2), fresh = image("cold", 2);
    ASSERT_EQ(warm.size(), fresh.size());
    const double d = mean_relative(warm, fresh);
    EXPECT_LT(d, 0.02) << "carried against cold";
    EXPECT_GT(mean_relative(image("carried", 0), fresh), 0.2) << "frame 0 is another view";
}

}  // namespace
}  // namespace crex
