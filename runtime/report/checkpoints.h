/// \file checkpoints.h
/// Checkpoints of a render for its error-against-time curve (issue 8, spec §7 "Metrics"): a
/// copy of the image at every stage boundary, at step boundaries, and at least every
/// `interval` seconds. Metrics are computed after the render, so a checkpoint costs the render
/// one image copy; the clock the budget sees pauses during the copy.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace crex {

struct Checkpoint {
    double seconds = 0;       ///< render time (the paused clock) when the image was copied
    std::string stage;        ///< "preselective", "guidance", "selective", "end"
    std::string event;        ///< what had just run: "camera rays", "D at <crex>:1:7", ...
    uint64_t rays = 0;        ///< rays executed so far
    std::vector<float> image; ///< linear RGB
};

class CheckpointRecorder {
public:
    /// `interval`: seconds between checkpoints within long steps; `max_bytes`: snapshots beyond
    /// it thin themselves out (every other mid-step checkpoint is dropped and the interval doubles).
    explicit CheckpointRecorder(double interval, size_t max_bytes = size_t{512} << 20);

    /// Starts the clock (at the first camera ray).
    void start();
    /// Seconds since start(), without the time spent copying snapshots.
    double now() const;
    double paused_seconds() const { return paused_; }

    void set_stage(const std::string& stage) { stage_ = stage; }
    /// Runs `work` (report bookkeeping) with the clock paused.
    void paused(const std::function<void()>& work);
    /// Records a checkpoint if due: always when `force` (stage ends), at step boundaries when
    /// at least a tenth of the interval has passed, otherwise when the interval has.
    void event(const std::string& what, bool boundary, uint64_t rays, const std::function<std::vector<float>()>& snapshot,
               bool force = false);

    /// A checkpoint made elsewhere (distributed runs: the image of every rank's rows at the
    /// end, which no single process's film holds before then).
    void add(Checkpoint c) {
        bytes_ += c.image.size() * sizeof(float);
        checkpoints_.push_back(std::move(c));
    }

    const std::vector<Checkpoint>& checkpoints() const { return checkpoints_; }

private:
    using Clock = std::chrono::steady_clock;
    double interval_;
    size_t max_bytes_, bytes_ = 0;
    Clock::time_point start_ = Clock::now();
    double paused_ = 0, last_ = -1e30;
    std::string stage_ = "preselective";
    std::vector<Checkpoint> checkpoints_;
};

}  // namespace crex
