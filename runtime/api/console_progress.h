/// \file console_progress.h
/// What `crex run` and `crex reference` watch a render by (`--progress`):
///   bar    one line on stderr redrawn at most ten times a second (stage, pass, percent, ETA,
///          ray rate): the default on a terminal;
///   plain  a line per update, at most one every 10 s and only once the render has run 5 s
///          (short renders say nothing): the default when stderr is a pipe or a log;
///   none   nothing (`-q` too).
/// It also carries a report's checkpoints, and asks the render to stop after Ctrl-C
/// (interrupt.h).
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

#include <fmt/format.h>

#include "runtime/api/interrupt.h"
#include "runtime/driver/run_observer.h"

namespace crex {

enum class ProgressMode { kNone, kBar, kPlain };

/// `--progress auto|bar|plain|none` as a mode: auto is a bar on a terminal, else plain lines;
/// `quiet` is none.
inline ProgressMode progress_mode(const std::string& flag, bool quiet) {
    if (quiet || flag == "none") return ProgressMode::kNone;
    if (flag == "bar") return ProgressMode::kBar;
    if (flag == "plain") return ProgressMode::kPlain;
    return ::isatty(STDERR_FILENO) ? ProgressMode::kBar : ProgressMode::kPlain;
}

class ConsoleProgress final : public RunObserver {
public:
    /// `recorder`: where a report's checkpoints go (null: none); `stop_on_interrupt`: Ctrl-C
    /// ends the render early with the image so far (one process).
    explicit ConsoleProgress(ProgressMode mode, CheckpointRecorder* recorder = nullptr, bool stop_on_interrupt = false)
        : mode_(mode), recorder_(recorder), stop_on_interrupt_(stop_on_interrupt) {}
    ~ConsoleProgress() override { finish(); }

    void progress(const RunProgress& p) override { update(p); }
    CheckpointRecorder* checkpoints() override { return recorder_; }
    bool stop_requested() override { return stop_on_interrupt_ && interrupted(); }

    /// "  selective  pass 3/12   41%  ETA 12 s   5.20 M rays/s  D at <crex>:1:7"
    void update(const RunProgress& p) {
        if (mode_ == ProgressMode::kNone) return;
        auto now = std::chrono::steady_clock::now();
        const double s = std::chrono::duration<double>(now - start_).count();
        if (mode_ == ProgressMode::kBar) {
            if (now - last_ < std::chrono::milliseconds(100)) return;
        } else if (s < 5 || (printed_ && now - last_ < std::chrono::seconds(10))) {
            return;
        }
        last_ = now;
        std::string eta = "";
        if (p.fraction > 0 && p.fraction < 1)
            eta = "ETA " + std::to_string(static_cast<long>(p.stage_seconds / p.fraction * (1 - p.fraction) + 0.5)) + " s";
        std::string pass = p.passes > 1 ? "pass " + std::to_string(p.pass) + "/" + std::to_string(p.passes) : "";
        // The ray rate when the renderer counts its rays (a reference's path tracer does not).
        const std::string rate = p.rays > 0 && s > 0 ? fmt::format("{:.2f} M rays/s", static_cast<double>(p.rays) / 1e6 / s) : "";
        if (mode_ == ProgressMode::kBar) {
            std::fprintf(stderr, "\r\033[K  %-13s %-11s %3.0f%%  %-10s %14s  %s", p.stage.c_str(), pass.c_str(), 100 * p.fraction, eta.c_str(),
                         rate.c_str(), p.step.c_str());
            drawn_ = true;
        } else {
            // The step too: a stage without passes (the cache's records made again) says its work there.
            std::fprintf(stderr, "crex: %.0f s: %s%s%s %.0f%%%s%s%s%s%s%s\n", s, p.stage.c_str(), pass.empty() ? "" : " ", pass.c_str(),
                         100 * p.fraction, eta.empty() ? "" : ", ", eta.c_str(), rate.empty() ? "" : ", ", rate.c_str(),
                         p.step.empty() ? "" : "; ", p.step.c_str());
            std::fflush(stderr);
            printed_ = true;
        }
    }
    void finish() {
        if (drawn_) std::fprintf(stderr, "\r\033[K");
        drawn_ = false;
    }

private:
    ProgressMode mode_;
    CheckpointRecorder* recorder_;
    bool stop_on_interrupt_;
    bool drawn_ = false, printed_ = false;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    std::chrono::steady_clock::time_point last_{};
};

}  // namespace crex
