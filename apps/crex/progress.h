/// \file progress.h
/// A one-line progress display on stderr, only when stderr is a terminal (quiet in pipes and
/// CI logs), redrawn at most ten times a second.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

namespace crex::app {

class Progress {
public:
    explicit Progress(bool enabled) : enabled_(enabled && ::isatty(STDERR_FILENO)) {}
    ~Progress() { finish(); }

    void update(const std::string& what, uint64_t rays) {
        if (!enabled_) return;
        auto now = std::chrono::steady_clock::now();
        if (now - last_ < std::chrono::milliseconds(100)) return;
        last_ = now;
        double s = std::chrono::duration<double>(now - start_).count();
        std::fprintf(stderr, "\r\033[K  rendering: %-12s %8.2f M rays  %6.1f s  %6.2f M rays/s", what.c_str(), rays / 1e6, s,
                     s > 0 ? rays / 1e6 / s : 0.0);
        drawn_ = true;
    }
    void finish() {
        if (drawn_) std::fprintf(stderr, "\r\033[K");
        drawn_ = false;
    }

private:
    bool enabled_;
    bool drawn_ = false;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    std::chrono::steady_clock::time_point last_{};
};

}  // namespace crex::app
