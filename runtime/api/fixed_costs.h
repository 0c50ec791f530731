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
    /// Its coarsest preview, guidance and end as the profile predicts them. The preview is
    /// predicted from the profile's: its fixed part, a record per sample (up to the full
    /// preview's records) with a cache, and the rest per sample.
    double predicted_seconds = 0;
    /// The smallest budget the pipeline can meet: the prediction and kFixedCostSpread of it
    /// again, for how far these costs move from one run to the next.
    double floor_seconds = 0;
};

/// What the fixed costs may take beyond their prediction, as a share of it. The shortest runs
/// the stdlib's time-constrained pipelines can make came out at 0.62-1.57 of the prediction on
/// the three stock scenes (384x288 and 512x384, three runs each; docs/runtime.md): a budget
/// within that of the prediction has nothing left to cut when they run long, and was missed by
/// up to +43 %.
inline constexpr double kFixedCostSpread = 0.5;

/// The fixed costs of a `width` x `height` render at `spp` preview samples, from `stages`
/// (nullopt: the profile does not hold them).
std::optional<FixedCosts> predict_fixed_costs(const StageCosts& stages, int width, int height, uint32_t spp);

/// "the preview at every 8th pixel 0.021 s, guidance 0.05 s and the render's end 0.003 s (from
/// the profile's stage costs), and half of that again for how far they vary from run to run".
std::string describe_fixed_costs(const FixedCosts& costs);

}  // namespace crex
