/// \file preview_levels.h
/// A pipeline's preview at the corners of a grid (issue 34): every k-th pixel of every k-th
/// row, and the last row and column (runtime/pipeline/subsample.h's squares of k pixels); the
/// other pixels are interpolated for guidance and rendered by the selective stage. Under a
/// budget the preview goes coarse to fine, from kCoarsestPreviewStride down to every pixel,
/// while it stays within kPreviewShare of the budget.
#pragma once

#include <cstdint>

namespace crex {

/// The share of a budget the preview may take (the thesis's 8.3 preview was 5 % of its render).
inline constexpr double kPreviewShare = 0.15;
/// The coarsest preview: every 8th pixel of every 8th row.
inline constexpr uint32_t kCoarsestPreviewStride = 8;

/// The camera samples of a preview at every `stride`-th pixel (and the last row and column).
/// The corners of a stride are among those of half of it.
uint64_t preview_samples_at(int width, int height, uint32_t spp, uint32_t stride);

}  // namespace crex
