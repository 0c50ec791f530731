/// \file sequence_report.h
/// `crex run --camera-path PATH --report DIR` (issue 36): a sequence's report as one
/// self-contained page, beside its data. Per frame: its time (the whole frame, its render, its
/// budget), the cache records it made, its flicker against the frame before it and, where a
/// reference sequence has the frame, its error against it; every frame in a table and as
/// frames.csv / frames.json; a strip of frames as a viewer sees them (through the first
/// frame's exposure, so a change of brightness shows); the video when one was made.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace crex {

struct SequenceFrameRow {
    int64_t frame = 0;
    double time = 0;  ///< on the path, seconds
    bool skipped = false;
    bool high_quality = false;
    double seconds = 0, render_seconds = 0, budget_seconds = 0;  ///< budget 0: none
    size_t records_made = 0, records_reused = 0;
    uint64_t rays = 0;
    double inherited_pixels = 0;         ///< share of pixels that inherited samples (--reuse-frames)
    std::optional<double> flicker;       ///< display difference from the frame before it
    std::optional<double> flip, relmse;  ///< against the reference's frame, where it has one
    std::string image;                   ///< the frame's first image file ("": none)
};

struct SequenceReport {
    std::string dir, title;
    std::vector<std::pair<std::string, std::string>> summary;  ///< rows first in the summary table
    std::vector<SequenceFrameRow> frames;
    std::string reference;  ///< the reference sequence's name, for the page ("": none)
    std::string video;      ///< a video of the frames, embedded in the page ("": none)
    std::string plan_dot;   ///< the plan the frames ran ("": none)
    size_t strip = 12;      ///< at most this many frames in the strip, evenly spaced
};

/// Writes `report.dir` (made; a folder that report_folder_refusal() allowed); returns "" or
/// what failed. index.html is written last, so a page that is there is whole.
std::string write_sequence_report(const SequenceReport& report);

/// The frames of `count` (at most `most`) shown in a strip: evenly spaced, the first and the
/// last included, each once.
std::vector<size_t> strip_frames(size_t count, size_t most);

}  // namespace crex
