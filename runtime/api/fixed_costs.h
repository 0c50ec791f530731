/// \file fixed_costs.h
/// Under a budget, a pipeline's preview and guidance are work the budget schedules (issue 34):
/// the preview goes coarse to fine within kPreviewShare of the budget (preview_levels.h), and a
/// budget below the pipeline's floor, its coarsest preview and guidance as the stage costs of a
/// saved profile predict them, is refused before rendering.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "runtime/driver/preview_levels.h"
#include "runtime/render/profile.h"

namespace crex {

struct FixedCosts {
    double coarsest_preview_seconds = 0;  ///< the preview at every kCoarsestPreviewStride-th pixel
    double guidance_seconds = 0;
    double end_seconds = 0;  ///< the render's end after its last stage (RunSettings::end_seconds)
    /// The smallest budget the pipeline can meet: its coarsest preview, guidance and end. The
    /// preview is predicted from the profile's: its fixed part, a record per sample (up to the
    /// full preview's records) with a cache, and the rest per sample.
    double floor_seconds = 0;
};

/// The fixed costs of a `width` x `height` render at `spp` preview samples, from `stages`
/// (nullopt: the profile does not hold them).
std::optional<FixedCosts> predict_fixed_costs(const StageCosts& stages, int width, int height, uint32_t spp);

/// "the preview at every 8th pixel 0.021 s, guidance 0.05 s and the render's end 0.003 s (from the profile's stage costs)".
std::string describe_fixed_costs(const FixedCosts& costs);

}  // namespace crex
