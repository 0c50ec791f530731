/// \file frame_writer.h
/// A sequence's frame files written on a thread of their own while the next frame renders
/// (issue 36). Encoding a frame's EXR and PNG took 30 to 50 ms of a 0.3 s later frame of the
/// corridor walk at 320x240, time the render's threads need not wait for.
///
/// At most one frame is in flight: write() first waits for the frame before, so memory holds
/// one frame's images beyond the render's own, and a frame's failure stops the sequence at the
/// next frame at the latest. Each frame's files are still all or none (write_run_images), so
/// a sequence stopped anywhere, by an error or an interrupt, leaves finished frames whole and
/// the one in flight either whole or absent, and a restart skips exactly the finished ones.
#pragma once

#include <cstdint>
#include <future>
#include <string>

#include "runtime/api/run_outputs.h"

namespace crex {

class FrameWriter {
public:
    /// Starts loading the image plugin (0.2 to 0.35 s, once a process) on the writer's thread
    /// where any of `paths` needs it (needs_image_plugin), so the first frame renders beside
    /// it instead of the second frame waiting for it.
    explicit FrameWriter(const std::vector<std::string>& paths);
    FrameWriter(const FrameWriter&) = delete;
    FrameWriter& operator=(const FrameWriter&) = delete;
    /// Waits for the frame in flight (its files land or are not made); its error is not
    /// thrown from here: a destructor runs while something else is already failing.
    ~FrameWriter();

    /// Waits for the frame before (throws FrameWriteError naming it if it failed), then starts
    /// writing `images` of `frame`.
    void write(int64_t frame, RunImages images);
    /// Waits for the frame in flight; throws FrameWriteError if it failed. Returns the seconds
    /// spent waiting.
    double finish();

private:
    std::future<void> plugin_;  // declared first: destroyed last, after the frame in flight
    std::future<std::string> pending_;
    int64_t frame_ = -1;
};

}  // namespace crex
