#include "runtime/api/frame_writer.h"

#include <fmt/format.h>

#include <chrono>

#include "runtime/api/frame_sequence.h"
#include "runtime/io/image_io.h"

namespace crex {

FrameWriter::FrameWriter(const std::vector<std::string>& paths) {
    // A failure to load is not this frame's to report: the first write meets it and says so.
    plugin_ = preload_image_plugin(paths);
}

FrameWriter::~FrameWriter() {
    if (pending_.valid()) pending_.wait();
}

void FrameWriter::write(int64_t frame, RunImages images) {
    finish();
    frame_ = frame;
    pending_ = std::async(std::launch::async, [images = std::move(images)] { return write_run_images(images); });
}

double FrameWriter::finish() {
    if (!pending_.valid()) return 0;
    const auto start = std::chrono::steady_clock::now();
    const std::string error = pending_.get();
    const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!error.empty()) throw FrameWriteError(fmt::format("frame {}: {}", frame_, error));
    return waited;
}

}  // namespace crex
