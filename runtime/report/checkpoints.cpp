#include "runtime/report/checkpoints.h"

#include <algorithm>

namespace crex {

CheckpointRecorder::CheckpointRecorder(double interval, CheckpointScorer scorer, size_t max_bytes)
    : interval_(interval > 0 ? interval : 0.1), scorer_(std::move(scorer)), max_bytes_(max_bytes) {}

void CheckpointRecorder::start(size_t image_floats) {
    image_floats_ = image_floats;
    start_ = Clock::now();
    paused_ = copy_seconds_ = 0;
    copies_ = 0;
    last_ = -1e30;
}

double CheckpointRecorder::now() const { return std::chrono::duration<double>(Clock::now() - start_).count() - paused_; }

void CheckpointRecorder::paused(const std::function<void()>& work) {
    auto start = Clock::now();
    work();
    paused_ += std::chrono::duration<double>(Clock::now() - start).count();
}

void CheckpointRecorder::event(const std::string& what, bool boundary, uint64_t rays, const std::function<std::vector<float>()>& snapshot,
                               bool force) {
    double t = now();
    // Checkpoints are never closer, in render time, than one of them costs to copy and score:
    // so they never take much longer than the render itself. Scoring a 1920x1080 image against
    // its reference takes longer than the default interval, and a run under a sanitizer renders
    // ten times slower with each score ten times dearer.
    const double cost = copies_ ? copy_seconds_ / double(copies_) : 0.0;
    bool due = force || t - last_ >= std::max(boundary ? interval_ / 10 : interval_, cost);
    if (!due) return;
    auto copy_start = Clock::now();
    // Without a reference the image would be read by nothing: only its size is counted.
    keep(Checkpoint{t, stage_, what, rays, scorer_ || image_floats_ == 0 ? snapshot() : std::vector<float>{}, std::nullopt});
    last_ = t;
    const double took = std::chrono::duration<double>(Clock::now() - copy_start).count();
    paused_ += took;
    copy_seconds_ += took, ++copies_;
}

void CheckpointRecorder::add(Checkpoint c) { keep(std::move(c)); }

void CheckpointRecorder::keep(Checkpoint c) {
    bytes_ += (c.image.empty() ? image_floats_ : c.image.size()) * sizeof(float);
    if (scorer_ && !c.image.empty()) c.score = scorer_(c.image);
    std::vector<float>().swap(c.image);  // the score is all the curve needs
    checkpoints_.push_back(std::move(c));
    if (bytes_ <= max_bytes_) return;
    // Thin out: keep stage ends and every other checkpoint; what is kept counts as the images it
    // was made from.
    std::vector<Checkpoint> kept;
    size_t image_bytes = bytes_ / checkpoints_.size();
    bytes_ = 0;
    for (size_t i = 0; i < checkpoints_.size(); ++i)
        if (i % 2 == 0 || i + 1 == checkpoints_.size() || checkpoints_[i].event.rfind("end of ", 0) == 0) {
            bytes_ += image_bytes;
            kept.push_back(std::move(checkpoints_[i]));
        }
    checkpoints_ = std::move(kept);
    interval_ *= 2;
}

}  // namespace crex
