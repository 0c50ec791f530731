/// \file run_observer.h
/// What a caller sees of a render while it runs: progress (a terminal line, a notebook's bar,
/// a Python callback) and the checkpoints of a report. The driver calls it from the thread
/// that called run_plan(), between steps and batches of rays, never from a worker thread: an
/// observer may throw (RunCancelled, say) to stop the render there, and nothing of it is kept.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>

#include "runtime/report/checkpoints.h"

namespace crex {

/// What the driver is doing, for a progress line.
struct RunProgress {
    std::string stage;            ///< "setup" (the caustic map), "render", "pre-selective", "guidance", "selective"
    size_t pass = 0, passes = 0;  ///< 1-based pass within the stage
    double fraction = 0;          ///< of the stage's camera samples traced so far
    double stage_seconds = 0;     ///< since the stage began
    uint64_t rays = 0;            ///< rays executed since the first camera ray
    std::string step;             ///< the crex step running
};

/// Thrown by an observer that stops the render (Ctrl-C in Python); the render is abandoned.
struct RunCancelled : std::runtime_error {
    using std::runtime_error::runtime_error;
};

class RunObserver {
public:
    virtual ~RunObserver() = default;
    /// Called often (every batch of rays): keep it cheap, or throttle it.
    virtual void progress(const RunProgress& p) { (void)p; }
    /// Where image snapshots go during the render, for an error curve; null: none are taken.
    virtual CheckpointRecorder* checkpoints() { return nullptr; }
    /// Asked before each pass: true ends the render early as a spent budget does (the pass in
    /// flight finishes, no later stage starts) and the result is the image so far, marked
    /// `stopped` (Ctrl-C in `crex run`). One process only: a distributed render ignores it.
    virtual bool stop_requested() { return false; }
};

/// Progress to a function (none: nobody watching), no checkpoints.
class ProgressFunction final : public RunObserver {
public:
    explicit ProgressFunction(std::function<void(const RunProgress&)> f) : f_(std::move(f)) {}
    void progress(const RunProgress& p) override {
        if (f_) f_(p);
    }

private:
    std::function<void(const RunProgress&)> f_;
};

/// Long work while a scene is made ready (a texture's tiled copy: a 30000x30000 PNG's took 53 s)
/// as progress of the stage "setup" in `line`, told to `observer`: each step (an image) its own
/// share and ETA. Both outlive the function.
inline std::function<void(const std::string& step, double fraction)> setup_progress(RunObserver& observer, RunProgress& line) {
    using Clock = std::chrono::steady_clock;
    return [&observer, &line, phase = std::string(), start = Clock::now()](const std::string& step, double done) mutable {
        if (phase != step) phase = step, start = Clock::now();
        line.stage = "setup";
        line.fraction = done;
        line.stage_seconds = std::chrono::duration<double>(Clock::now() - start).count();
        line.step = step;
        observer.progress(line);
    };
}

}  // namespace crex
