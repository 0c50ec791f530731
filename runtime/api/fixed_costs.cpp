#include "runtime/api/fixed_costs.h"

#include <fmt/format.h>

#include <algorithm>

namespace crex {

std::optional<FixedCosts> predict_fixed_costs(const StageCosts& stages, int width, int height, uint32_t spp) {
    if (!stages.known() || width <= 0 || height <= 0) return std::nullopt;
    FixedCosts c;
    // The preview's time is a fixed part (the cache's caustic map), its records, and the rest
    // per sample. A sparse preview's samples lie far apart, so each makes a record of its own,
    // up to as many as the full preview needed: with a cache, its cost per sample is not the
    // full preview's (prog_tc's coarsest preview on the corridor took 0.4-0.6 s where the
    // full preview's cost per sample predicted a tenth of that).
    const double fixed = std::clamp(stages.preview_fixed_seconds, 0.0, stages.preview_seconds);
    const double records = std::clamp(stages.preview_record_seconds, 0.0, stages.preview_seconds - fixed);
    const double per_sample = (stages.preview_seconds - fixed - records) / static_cast<double>(stages.preview_samples);
    const double per_record = stages.preview_records > 0 ? records / static_cast<double>(stages.preview_records) : 0.0;
    const uint64_t samples = preview_samples_at(width, height, spp, kCoarsestPreviewStride);
    const double sparse_records = static_cast<double>(std::min(samples, stages.preview_records));
    // Guidance, the end and a strided preview's bookkeeping go over every pixel whatever the
    // preview sampled.
    const double pixel_share = static_cast<double>(width) * static_cast<double>(height) / static_cast<double>(stages.pixels);
    c.coarsest_preview_seconds = fixed + per_sample * static_cast<double>(samples) + per_record * sparse_records +
                                 stages.strided_preview_seconds * pixel_share;
    c.guidance_seconds = stages.guidance_seconds * pixel_share;
    c.end_seconds = stages.end_seconds * pixel_share;
    c.predicted_seconds = c.coarsest_preview_seconds + c.guidance_seconds + c.end_seconds;
    c.floor_seconds = (1 + kFixedCostSpread) * c.predicted_seconds;
    return c;
}

std::string describe_fixed_costs(const FixedCosts& c) {
    return fmt::format("the preview at every {}th pixel {:.3g} s, guidance {:.3g} s and the render's end {:.3g} s (from the profile's "
                       "stage costs), and {:.0f} % of that again for how far they vary from run to run",
                       kCoarsestPreviewStride, c.coarsest_preview_seconds, c.guidance_seconds, c.end_seconds, 100 * kFixedCostSpread);
}

}  // namespace crex
