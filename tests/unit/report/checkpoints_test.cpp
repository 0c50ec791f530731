// A report's checkpoints: scored against the reference when taken, their images freed (a report
// held up to 512 MiB of them beside the passes --max-memory sizes), the same curve as scoring the
// images after the render, and as many points as before.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "runtime/report/checkpoints.h"
#include "runtime/report/error_curve.h"

namespace crex {
namespace {

metrics::Image gradient(int w, int h, float scale) {
    metrics::Image im{w, h, std::vector<float>(static_cast<size_t>(w) * h * 3)};
    for (size_t i = 0; i < im.rgb.size(); ++i) im.rgb[i] = scale * (0.05f + 0.9f * static_cast<float>(i % 97) / 97.0f);
    return im;
}

TEST(Checkpoints, ScoredWhenTakenTheImageIsFreedAndTheCurveIsTheSame) {
    const metrics::Image reference = gradient(24, 16, 1.0f);
    const metrics::DisplayView view{true, 1.3};
    CheckpointRecorder scored(0.0, scorer_against(reference, view));
    CheckpointRecorder kept(0.0, {}, size_t{1} << 30);  // no scorer: nothing kept but the times
    std::vector<Checkpoint> with_images;
    for (int k = 0; k < 5; ++k) {
        const metrics::Image im = gradient(24, 16, 1.0f + 0.3f / static_cast<float>(k + 1));
        auto snapshot = [&] { return im.rgb; };
        scored.event("step", true, static_cast<uint64_t>(k), snapshot, true);
        kept.event("step", true, static_cast<uint64_t>(k), snapshot, true);
        with_images.push_back({0.0, "selective", "step", static_cast<uint64_t>(k), im.rgb, std::nullopt});
    }
    ASSERT_EQ(scored.checkpoints().size(), 5u);
    for (const Checkpoint& c : scored.checkpoints()) {
        EXPECT_TRUE(c.image.empty());
        ASSERT_TRUE(c.score.has_value());
    }
    for (const Checkpoint& c : kept.checkpoints()) {
        EXPECT_TRUE(c.image.empty());
        EXPECT_FALSE(c.score.has_value());
    }
    const std::vector<CurvePoint> now = error_curve(scored.checkpoints(), reference, view);
    const std::vector<CurvePoint> after = error_curve(with_images, reference, view);
    ASSERT_EQ(now.size(), after.size());
    for (size_t i = 0; i < now.size(); ++i) {
        EXPECT_EQ(now[i].rmse, after[i].rmse);
        EXPECT_EQ(now[i].relmse, after[i].relmse);
        EXPECT_EQ(now[i].flip, after[i].flip);
        EXPECT_EQ(now[i].perr, after[i].perr);
        EXPECT_EQ(now[i].ssim, after[i].ssim);
    }
    // The error falls as the images approach the reference.
    EXPECT_GT(now.front().rmse, now.back().rmse);
    EXPECT_GT(now.front().flip, now.back().flip);
}

TEST(Checkpoints, ThinOutAsIfTheImagesWereKept) {
    // Room for 4 images of 24x16: the fifth thins the points to every other one (and the last).
    const metrics::Image reference = gradient(24, 16, 1.0f);
    const size_t image_bytes = reference.rgb.size() * sizeof(float);
    CheckpointRecorder rec(0.0, scorer_against(reference, {true, 1.0}), 4 * image_bytes);
    for (int k = 0; k < 5; ++k) rec.event("step " + std::to_string(k), true, 0, [&] { return reference.rgb; }, true);
    ASSERT_EQ(rec.checkpoints().size(), 3u);
    EXPECT_EQ(rec.checkpoints()[0].event, "step 0");
    EXPECT_EQ(rec.checkpoints()[1].event, "step 2");
    EXPECT_EQ(rec.checkpoints()[2].event, "step 4");
    EXPECT_EQ(rec.checkpoints()[2].score->rmse, 0.0);
}

TEST(Checkpoints, WithoutAReferenceNoImageIsCopiedButTheThinningCountsThem) {
    // The same room for 4 images of 24x16 as above, no scorer: the snapshot is never taken, and
    // the fifth checkpoint still thins the points as if its image had been kept.
    const size_t floats = size_t{24} * 16 * 3;
    CheckpointRecorder rec(0.0, {}, 4 * floats * sizeof(float));
    rec.start(floats);
    int copies = 0;
    for (int k = 0; k < 5; ++k)
        rec.event("step " + std::to_string(k), true, 0, [&] { ++copies; return std::vector<float>(floats, 1.0f); }, true);
    EXPECT_EQ(copies, 0);
    ASSERT_EQ(rec.checkpoints().size(), 3u);
    EXPECT_EQ(rec.checkpoints()[1].event, "step 2");
    EXPECT_FALSE(rec.checkpoints()[2].score.has_value());
}

// Checkpoints never cost much more than the render: a score dearer than the interval (4 ms
// against 0.5 ms, events every 1 ms of render) spaces them by what one costs. Without that, all
// 40 events were scored: 160 ms of scoring for 40 ms of render.
TEST(Checkpoints, AreNeverCloserThanTheyCostToScore) {
    using namespace std::chrono_literals;
    const CheckpointScorer slow = [](const std::vector<float>&) {
        std::this_thread::sleep_for(4ms);
        return CheckpointScore{};
    };
    CheckpointRecorder rec(0.0005, slow);
    rec.start(3);
    for (int k = 0; k < 40; ++k) {
        std::this_thread::sleep_for(1ms);  // the render's work between two events
        rec.event("step", false, 0, [] { return std::vector<float>(3, 1.0f); });
    }
    const double render = rec.now(), scoring = rec.paused_seconds();
    EXPECT_GE(rec.checkpoints().size(), 2u);
    EXPECT_LT(rec.checkpoints().size(), 20u);
    EXPECT_LT(scoring, 1.5 * render + 0.01) << rec.checkpoints().size() << " checkpoints";
}

}  // namespace
}  // namespace crex
