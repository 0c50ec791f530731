/// \file checkpoints.h
/// Checkpoints of a render for its error-against-time curve (issue 8, spec §7 "Metrics"): a
/// copy of the image at every stage boundary, at step boundaries, and at least every
/// `interval` seconds. With a reference, each copy is scored against it when taken and then
/// freed, so a report holds one image copy at a time whatever the frame size (it held up to
/// 512 MiB of them beside the passes --max-memory sizes); the clock the budget sees pauses
/// during the copy and the scoring. Without a reference no image is copied at all.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace crex {

/// A checkpoint's error against the reference (error_curve.h says how it is measured).
struct CheckpointScore {
    double rmse = 0, relmse = 0, flip = 0, perr = 0;
    std::optional<double> ssim;
};

/// Scores a linear RGB image against the run's reference (error_curve.h makes one).
using CheckpointScorer = std::function<CheckpointScore(const std::vector<float>& image)>;

struct Checkpoint {
    double seconds = 0;       ///< render time (the paused clock) when the image was copied
    std::string stage;        ///< "preselective", "guidance", "selective", "end"
    std::string event;        ///< what had just run: "camera rays", "D at <crex>:1:7", ...
    uint64_t rays = 0;        ///< rays executed so far
    std::vector<float> image; ///< linear RGB; empty once scored, or when there is no reference
    std::optional<CheckpointScore> score;  ///< against the reference (none without one)
};

class CheckpointRecorder {
public:
    /// `interval`: seconds between checkpoints within long steps; `scorer`: the reference's (none:
    /// checkpoints keep the time, stage and rays only); `max_bytes`: once the snapshots taken
    /// would fill it, the checkpoints thin themselves out (every other mid-step checkpoint is
    /// dropped and the interval doubles). No snapshot is kept, but the points a report shows (and
    /// the scoring it pays for) are as many as that many bytes of images would hold.
    explicit CheckpointRecorder(double interval, CheckpointScorer scorer = {}, size_t max_bytes = size_t{512} << 20);

    /// Starts the clock (at the first camera ray) for images of `image_floats` floats: without a
    /// scorer no image is copied, and the thinning counts that many per checkpoint.
    void start(size_t image_floats = 0);
    /// Seconds since start(), without the time spent copying snapshots.
    double now() const;
    double paused_seconds() const { return paused_; }

    void set_stage(const std::string& stage) { stage_ = stage; }
    /// Runs `work` (report bookkeeping) with the clock paused.
    void paused(const std::function<void()>& work);
    /// Records a checkpoint if due: always when `force` (stage ends), at step boundaries when
    /// at least a tenth of the interval has passed, otherwise when the interval has; and never
    /// sooner after the last one than a checkpoint takes to copy and score, on average.
    void event(const std::string& what, bool boundary, uint64_t rays, const std::function<std::vector<float>()>& snapshot,
               bool force = false);

    /// A checkpoint made elsewhere (distributed runs: the image of every rank's rows at the
    /// end, which no single process's film holds before then).
    void add(Checkpoint c);

    const std::vector<Checkpoint>& checkpoints() const { return checkpoints_; }
    /// Whether checkpoints are scored against a reference (else their images are never read).
    bool scores() const { return static_cast<bool>(scorer_); }

private:
    /// Scores `c` (with a reference), frees its image and keeps it, thinning the kept ones out
    /// once their images would have filled max_bytes_.
    void keep(Checkpoint c);
    size_t image_floats_ = 0;

    using Clock = std::chrono::steady_clock;
    double interval_;
    CheckpointScorer scorer_;
    size_t max_bytes_, bytes_ = 0;
    Clock::time_point start_ = Clock::now();
    double paused_ = 0, last_ = -1e30;
    double copy_seconds_ = 0;  ///< spent copying and scoring checkpoints, over copies_ of them
    size_t copies_ = 0;
    std::string stage_ = "preselective";
    std::vector<Checkpoint> checkpoints_;
};

}  // namespace crex
