/// \file ambient_stand_ins.h
/// What stands in for the work a render leaves undone (spec/pipeline.md §6). Rays still waiting
/// in a bin when a pass ends are dropped; their light stands in as `av` times their throughput
/// (D's rays), or, automatically, as what the executed rays of their component brought back per
/// unit throughput in this render (every component's), or the image's mean radiance where none
/// of them ran. So a pixel whose components were skipped is never black for lack of work.
/// Automatic stand-ins are known only at the end; until then each component's throughput left
/// unexecuted is kept per pixel.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "runtime/driver/process_group.h"
#include "runtime/render/executor.h"
#include "runtime/render/film.h"

namespace crex {

class AmbientStandIns {
public:
    /// `pixels` of the image; `av` the stand-in radiance unless `automatic`.
    AmbientStandIns(size_t pixels, const Vec3& av, bool automatic);

    /// Whether the stand-ins have a per-pixel buffer at all: not when nothing would stand in
    /// (`--ambient 0`, not automatic), where it would be zeros the size of the film's sums.
    static bool per_pixel(const Vec3& av, bool automatic) { return automatic || max_component(av) > 0; }

    /// Automatic stand-ins: the throughput buffers of `components` made now, before the render's
    /// clock starts, instead of when their first rays are left. Distributed rendering keeps every
    /// component, so that each process shares its rows alike (a pixel's may have been left by
    /// the process whose band held it before); a budgeted render the components its crex reads,
    /// because a buffer made at the end of its last pass is made after the budget's last
    /// decision (4 ms of page faults for three at 384x288 on this VM, a 3 to 4 % overshoot of a
    /// 0.11 s budget).
    void keep(const std::array<bool, kComponentCount>& components);

    /// The rays left in `bins` at the end of a pass: counted in `left` per bin, their stand-in
    /// (or, automatic, their throughput) kept; the bins emptied and freed.
    void flush(std::array<RayBatch, kComponentCount>& bins, std::array<size_t, kComponentCount>& left);

    /// The stand-ins if the render stopped now (an image for a checkpoint): the rays still
    /// `waiting` in the bins and `carried` to the selective stage stand in too, automatic ones
    /// with what their component's rays brought back so far.
    std::vector<double> if_stopped_now(const Film& film, const ExecutorStats& stats, const std::array<RayBatch, kComponentCount>& waiting,
                                       const std::array<RayBatch, kComponentCount>& carried) const;

    /// The end of an automatic render: each component's throughput left stands in with what its
    /// executed rays over pixels [p0, p1) found (summed over every process rendering rows of
    /// `group`), else with the mean radiance of `image_before` (the preview, or the composite
    /// so far); each said in `notes`, kept in `auto_ambient`. `group` null: one process.
    void finish_automatic(const Film& film, const ExecutorStats& stats, const std::vector<float>& image_before, size_t p0, size_t p1,
                          ProcessGroup* group, std::array<Vec3, kComponentCount>& auto_ambient, std::vector<std::string>& notes);

    /// The throughput buffers freed (after finish_automatic(), once the render's clock stopped).
    void release();
    /// As if `throughput` of every component's rays were left in every pixel (the probe that
    /// times the end of a budgeted render).
    void leave_everywhere(float throughput);

    /// Per pixel RGB, sample-summed: what the composite adds for D rays dropped (and, after
    /// finish_automatic(), every component's).
    std::vector<double>& ambient() { return ambient_; }
    const std::vector<double>& ambient() const { return ambient_; }
    /// Automatic: per component, the throughput of its rays left unexecuted (per pixel RGB).
    std::array<std::vector<float>, kComponentCount>& throughput_left() { return left_; }
    /// The bytes of the throughput buffers made so far.
    size_t kept_bytes() const {
        size_t bytes = 0;
        for (const auto& left : left_) bytes += left.size() * sizeof(float);
        return bytes;
    }
    const Vec3& av() const { return av_; }
    bool automatic() const { return automatic_; }

private:
    size_t pixels_;
    Vec3 av_;
    bool automatic_;
    std::vector<double> ambient_;
    std::array<std::vector<float>, kComponentCount> left_;
    std::array<uint64_t, kComponentCount> flushed_{};  // rays of each component flush() kept in left_
};

}  // namespace crex
