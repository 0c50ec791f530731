/// \file progress.h
/// What `crex run` and `crex reference` watch a render by: a one-line progress display on
/// stderr (stage, pass, percent, ETA, ray rate), only when stderr is a terminal (quiet in pipes
/// and CI logs), redrawn at most ten times a second; and the checkpoints of a report.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "runtime/driver/run_observer.h"

namespace crex::app {

class Progress final : public RunObserver {
public:
    /// `recorder`: where a report's checkpoints go (null: none).
    explicit Progress(bool enabled, CheckpointRecorder* recorder = nullptr)
        : enabled_(enabled && ::isatty(STDERR_FILENO)), recorder_(recorder) {}
    ~Progress() override { finish(); }

    void progress(const RunProgress& p) override { update(p); }
    CheckpointRecorder* checkpoints() override { return recorder_; }

    /// "  selective  pass 3/12   41%  ETA 12 s   5.20 M rays/s  D at <crex>:1:7"
    void update(const RunProgress& p) {
        if (!enabled_) return;
        auto now = std::chrono::steady_clock::now();
        if (now - last_ < std::chrono::milliseconds(100)) return;
        last_ = now;
        double s = std::chrono::duration<double>(now - start_).count();
        std::string eta = "";
        if (p.fraction > 0.02 && p.fraction < 1)
            eta = "ETA " + std::to_string(static_cast<long>(p.stage_seconds / p.fraction * (1 - p.fraction) + 0.5)) + " s";
        std::string pass = p.passes > 1 ? "pass " + std::to_string(p.pass) + "/" + std::to_string(p.passes) : "";
        std::fprintf(stderr, "\r\033[K  %-13s %-11s %3.0f%%  %-10s %6.2f M rays/s  %s", p.stage.c_str(), pass.c_str(), 100 * p.fraction,
                     eta.c_str(), s > 0 ? p.rays / 1e6 / s : 0.0, p.step.c_str());
        drawn_ = true;
    }
    void finish() {
        if (drawn_) std::fprintf(stderr, "\r\033[K");
        drawn_ = false;
    }

private:
    bool enabled_;
    CheckpointRecorder* recorder_;
    bool drawn_ = false;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    std::chrono::steady_clock::time_point last_{};
};

}  // namespace crex::app
