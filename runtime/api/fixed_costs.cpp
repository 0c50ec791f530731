#include "runtime/api/fixed_costs.h"

#include <fmt/format.h>

namespace crex {

std::optional<FixedCosts> predict_fixed_costs(const StageCosts& stages, int width, int height, uint32_t spp) {
    if (!stages.known() || width <= 0 || height <= 0) return std::nullopt;
    FixedCosts c;
    const double per_sample = stages.preview_seconds / static_cast<double>(stages.preview_samples);
    c.coarsest_preview_seconds = per_sample * static_cast<double>(preview_samples_at(width, height, spp, kCoarsestPreviewStride));
    c.guidance_seconds = stages.guidance_seconds / static_cast<double>(stages.pixels) * static_cast<double>(width) * static_cast<double>(height);
    c.floor_seconds = c.coarsest_preview_seconds + c.guidance_seconds;
    return c;
}

std::string describe_fixed_costs(const FixedCosts& c) {
    return fmt::format("the preview at every {}th pixel {:.3g} s and guidance {:.3g} s (from the profile's stage costs)",
                       kCoarsestPreviewStride, c.coarsest_preview_seconds, c.guidance_seconds);
}

}  // namespace crex
