#include "runtime/driver/pass_sizing.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "runtime/base/memory.h"
#include "runtime/driver/ambient_stand_ins.h"
#include "runtime/driver/film_layout.h"
#include "runtime/driver/run_result.h"
#include "runtime/driver/run_settings.h"
#include "runtime/render/film.h"
#include "runtime/render/render_scene.h"
#include "runtime/texture/surface_textures.h"

namespace crex {
namespace {

// Memory model of a pass (kBytesPerSample): before passes, 512x512 at 16 spp of (TTMRSGD)* on
// builtin:cornell peaked at 1.51 GB for 4.2 M samples (~360 bytes each); 512 leaves room for
// the allocator's slack (at 400, 64 spp peaked at 1.10 GB under a 1 GiB limit; at 512, 0.87 GB).
// What a ray waiting in a bin costs with the step that made it (the bin it was taken from,
// shading buffers) and the allocator's slack, from max RSS over the peak rays held: Cornell
// 256x256 64 spp ~275 bytes (1.2 rays held a sample), the room ~345 (4.1 rays: trans and glass
// split lobes). A scene that holds more than the model's 512 bytes a sample has its later
// passes sized by this (the room at 128 spp went to 2.06 GB under a 1 GiB limit).
constexpr size_t kBytesPerHeldRay = 400;
// The process without any rays: code, Embree's and TBB's arenas, the images being written.
constexpr size_t kBaselineBytes = size_t{96} << 20;
// Beside the film (Film::bytes_per_pixel): the ambient stand-ins, RGB in double.
constexpr size_t kAmbientBytesPerPixel = 3 * 8;
// The images made after the render (composite, layers, tone-mapped copies).
constexpr size_t kOutputBytesPerPixel = 3 * 12;
// A triangle: its vertices and normal here, Embree's copy and BVH nodes.
constexpr size_t kBytesPerTriangle = 256;
// Guidance: the preview, nine linear buffers, maps and their intermediates.
constexpr size_t kGuidanceBytesPerPixel = 12 * 12 + 16 * 4;
// Held through a pipeline's passes: the preview image, the maps, the per-pixel settings.
constexpr size_t kSelectiveBytesPerPixel = 64;

}  // namespace

uint8_t subsampled_components(const PipelinePlan& plan) {
    uint8_t branches = 0;
    for (const PlanVariable& v : plan.variables)
        if (v.variable == pipeline::SelectiveVariable::kSubsample && v.component)
            branches = static_cast<uint8_t>(branches | (1u << static_cast<unsigned>(*v.component)));
    return branches;
}

size_t resident_bytes(size_t pixels, const FilmLayout& layout, uint8_t tracked_branches, bool ambient, bool staged) {
    const size_t per_pixel = Film::bytes_per_pixel(layout, tracked_branches) + (ambient ? kAmbientBytesPerPixel : 0) +
                             (staged ? kSelectiveBytesPerPixel : 0);
    return kBaselineBytes + pixels * per_pixel;
}

size_t fixed_bytes(size_t pixels, const FilmLayout& layout, uint8_t tracked_branches, bool staged, bool ambient) {
    // Guidance and the output images come between passes and after them, not beside them.
    return resident_bytes(pixels, layout, tracked_branches, ambient, staged) +
           pixels * std::max(kOutputBytesPerPixel, staged ? kGuidanceBytesPerPixel : 0);
}

bool keeps_ambient(const RunSettings& s) { return AmbientStandIns::per_pixel(s.ambient, s.ambient_auto); }

namespace {

// What a run of `plan` holds whatever its passes, before anything is made.
size_t fixed_bytes_of(const PipelinePlan& plan, const RunSettings& s) {
    const size_t pixels = static_cast<size_t>(s.width) * static_cast<size_t>(s.height);
    return fixed_bytes(pixels, film_layout(plan, s), subsampled_components(plan), plan.staged, keeps_ambient(s));
}

}  // namespace

// Refused before anything is allocated: otherwise the kernel's overcommit lets it start, and
// the out-of-memory killer ends it (or another process) minutes later. A 16384x16384 Cornell
// box went past 15 GB on a 24 GB machine before it was stopped.
void refuse_what_cannot_fit(const PipelinePlan& plan, const RunSettings& s) {
    const std::optional<size_t> available = memory_available_bytes();
    if (!available) return;
    const size_t pixels = static_cast<size_t>(s.width) * static_cast<size_t>(s.height);
    const size_t needed = fixed_bytes_of(plan, s);
    if (needed <= *available) return;
    constexpr double kGB = 1e9;
    throw std::runtime_error(fmt::format(
        "a {}x{} render holds {:.1f} GB whatever its passes ({} bytes a pixel: the film's sums in double, {}{}the "
        "output images), more than the {:.1f} GB of memory and swap this machine has "
        "free; render it smaller (--size)",
        s.width, s.height, static_cast<double>(needed) / kGB, (needed - kBaselineBytes) / std::max<size_t>(pixels, 1),
        keeps_ambient(s) ? "the ambient stand-ins, " : "", plan.staged ? "guidance's buffers, " : "", static_cast<double>(*available) / kGB));
}

std::string memory_over_limit_note(const PipelinePlan& plan, const RunSettings& s) {
    const size_t fixed = fixed_bytes_of(plan, s);
    if (fixed <= s.max_memory) return {};
    // Said, rather than let the limit look kept, with the limit that would be: the film and
    // its buffers, and room for passes of 64 rows.
    const size_t rows = std::min<size_t>(64, static_cast<size_t>(s.height));
    const size_t enough = fixed + rows * static_cast<size_t>(s.width) * kBytesPerSample;
    return fmt::format("the render's film, buffers and images alone hold {:.0f} MiB, more than --max-memory {:.0f} MiB: its passes "
                       "go one row at a time, and the process holds more than that limit (--max-memory {:.0f} would keep it)",
                       static_cast<double>(fixed) / (1 << 20), static_cast<double>(s.max_memory) / (1 << 20),
                       std::ceil(static_cast<double>(enough) / (1 << 20)));
}

size_t pass_bytes(size_t fixed, size_t held, const RenderScene& scene, int width, size_t max_memory) {
    size_t used = fixed + held;
    for (const auto& g : scene.embree->geometries()) used += g.indices.size() * kBytesPerTriangle;
    if (scene.textures) used += texture_cache_bytes(max_memory);
    // At least one row of samples, whatever the limit says: a pass cannot be smaller.
    const size_t row = static_cast<size_t>(width) * kBytesPerSample;
    return max_memory > used + row ? max_memory - used : row;
}

uint32_t progressive_pass_samples(const SampleRanges& frame) {
    // Sized on where the samples end, which every process of a group knows alike (the targets
    // guidance set from the whole image), not on where they start: a process's film holds the
    // samples of its own rows only, and a size it alone saw would split its passes differently
    // from one process's and change the order of a pixel's sums.
    uint32_t deepest = frame.end_of.empty() ? frame.end : 0;
    for (uint32_t stop : frame.end_of) deepest = std::max(deepest, stop);
    return deepest > 1 ? (deepest + kProgressivePasses - 1) / kProgressivePasses : 0;
}

StagePasses::StagePasses(int width, int height, const SampleRanges& ranges, PassLimits limits, bool budgeted, uint32_t pass_samples,
                         uint32_t progressive)
    : width_(width), height_(height), ranges_(ranges), limits_(limits), full_bytes_(limits.bytes), replan_(!budgeted && !pass_samples) {
    limits_.bytes_per_sample = kBytesPerSample;
    limits_.max_samples = pass_samples ? pass_samples : progressive;
    // Under a budget, camera samples are scheduled work (issue 15): one sample index a pass,
    // each admitted on the cost per sample measured so far (budget_admission.h).
    if (budgeted) limits_.max_samples = 1;
    // The model's bytes per sample hold for scenes like the Cornell box; where lobe splitting
    // keeps many more rays in flight the first pass is an eighth of the room, and the rest is
    // planned again on the rays it actually held.
    if (replan_) limits_.bytes = std::max<size_t>(limits_.bytes / 8, limits_.bytes_per_sample);
    passes_ = plan_sample_passes(width, height, ranges_, limits_);
}

size_t StagePasses::replan_after_first(uint64_t peak_rays_held, size_t pixels) {
    if (!replan_ || passes_.size() <= 1) return 0;
    // Plan the rest on what the first pass held: its samples' rays in flight.
    const size_t measured = peak_rays_held * kBytesPerHeldRay / std::max<uint64_t>(1, passes_[0].samples);
    limits_.bytes_per_sample = std::max(limits_.bytes_per_sample, measured);
    limits_.bytes = full_bytes_;
    if (passes_[0].row_begin != 0 || passes_[0].row_end != height_) {
        merge_later_passes();
        return limits_.bytes_per_sample;
    }
    SampleRanges rest = ranges_;
    if (rest.start_of.empty() && rest.end_of.empty()) {
        rest.first = std::max(rest.first, passes_[0].end);
    } else {
        rest.start_of.resize(pixels);
        rest.end_of.resize(pixels);
        for (size_t p = 0; p < rest.start_of.size(); ++p) {
            rest.start_of[p] = std::max(ranges_.start(p), passes_[0].end);
            rest.end_of[p] = ranges_.stop(p);
        }
    }
    std::vector<SamplePass> later = plan_sample_passes(width_, height_, rest, limits_);
    passes_.resize(1);
    passes_.insert(passes_.end(), later.begin(), later.end());
    return limits_.bytes_per_sample;
}

void StagePasses::merge_later_passes() {
    // The first pass held some rows only (a frame too large for one sample of every pixel in an
    // eighth of the room), so the later ones, planned at an eighth too, are merged where they
    // take the same samples of rows that follow on, up to what the room holds at the measured
    // cost. Each pixel still takes its samples in the same order. (At 3840x2160, 64 spp under
    // the default limit, the eighths made 5,568 passes and the process held 385 MB of 1 GiB.)
    const uint64_t most = std::max<uint64_t>(1, limits_.bytes / std::max<size_t>(1, limits_.bytes_per_sample));
    std::vector<SamplePass> merged{passes_[0]};
    for (size_t i = 1; i < passes_.size(); ++i) {
        const SamplePass& p = passes_[i];
        SamplePass& last = merged.back();
        if (merged.size() > 1 && p.first == last.first && p.end == last.end && p.row_begin == last.row_end && last.samples + p.samples <= most) {
            last.row_end = p.row_end;
            last.samples += p.samples;
        } else {
            merged.push_back(p);
        }
    }
    passes_ = std::move(merged);
}

}  // namespace crex
