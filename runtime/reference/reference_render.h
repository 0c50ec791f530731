/// \file reference_render.h
/// Rendering references (issue 32): the pixels of some windows of the full frame, exactly as a
/// render of the whole frame would give them (same camera, filter, sample pattern, seed), and
/// more samples for an existing reference, continuing its sample indices so that they are
/// independent of the ones it has; and the cheap look at the whole frame a windowed reference
/// keeps for what its windows cannot tell (the frame's exposure and where the eye goes).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "compiler/sched/program.h"
#include "runtime/driver/run_plan.h"
#include "runtime/reference/windowed_image.h"
#include "runtime/scene/scene.h"

namespace crex {

struct ReferencePixels {
    int width = 128, height = 128;     ///< the full frame
    std::vector<PixelWindow> windows;  ///< empty: the whole frame
    uint32_t first_sample = 0, spp = 1024;  ///< samples [first_sample, first_sample + spp) of every pixel
    uint64_t seed = 0;
    double lw = 1e-3;
    uint32_t max_depth = 256;
    std::function<void(const RunProgress&)> progress;
    /// Asked between sample passes (Ctrl-C): true stops the render after the pass in flight.
    std::function<bool()> stop;
};

struct RenderedPixels {
    std::vector<float> rgb;  ///< the windows as an atlas (windowed_image.h), or the whole frame
    double seconds = 0;
    bool stopped = false;  ///< ReferencePixels::stop asked it to stop
    /// The samples every rendered pixel holds: the settings' spp, or fewer when stopped; 0 when
    /// stopped before a pass ended or with pixels of different counts (not a reference then).
    uint32_t spp = 0;
};

/// Path traces the reference's pixels with `program` (no cache).
RenderedPixels render_reference_pixels(const Scene& scene, const sched::Program& program, const ReferencePixels& settings);

/// `more` samples of the pixels of the reference `header` describes (its frame, windows and
/// seed), continuing its sample indices: samples [spp, spp + more) of each pixel.
ReferencePixels more_samples_of(const ReferenceHeader& header, uint32_t more);

/// `more` (rendered from more_samples_of(ref.header, ...); stopped or not, its spp) added to
/// `ref`: the mean of all the samples, their total and runs in the header, the render time, and
/// the estimate of its own error (own_rmse_estimate).
void add_samples(ReferenceImage& ref, const RenderedPixels& more);

/// The whole frame seen cheaply: a render through the irradiance cache (smooth at few samples,
/// unlike path tracing), its exposure and its saliency as displayed.
struct FrameContext {
    int width = 0, height = 0;
    std::vector<float> rgb;       ///< linear RGB
    double exposure = 1;          ///< display_exposure(rgb)
    std::vector<float> saliency;  ///< one a pixel, in [0, 1]
    double seconds = 0;
    std::string how;              ///< what it was, for the reference's header
};

FrameContext render_frame_context(const Scene& scene, const sched::Program& program, int width, int height, uint32_t spp, uint64_t seed,
                                  const std::function<void(const RunProgress&)>& progress = {});

/// A new reference of `pixels`, rendered as `s` says (its windows, or the whole frame) from the
/// scene given as `scene` (`scene_hash`: scene_content_hash()) with `crex`: the image (the
/// windows side by side) and its header, with the samples every pixel holds (pixels.spp:
/// fewer than asked when stopped); with the frame's `context`, its exposure and attention.
ReferenceImage reference_image_of(const ReferencePixels& s, RenderedPixels pixels, const std::string& scene, const std::string& scene_hash,
                                  const std::string& crex, const FrameContext* context = nullptr);

}  // namespace crex
