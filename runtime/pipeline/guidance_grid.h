/// \file guidance_grid.h
/// The grid of a strided preview (issue 34): a preview at stride k has samples at every k-th
/// pixel of every k-th row and in the last row and column, and every other pixel is
/// interpolated from its square's corners. Guidance traces the pixel probe through the grid's
/// pixels alone after such a preview, and makes the maps of what each pixel sees (task maps,
/// distractors, X-map) on the grid, spread over the frame as the preview is: k^2 fewer probe
/// rays and map pixels. Maps of the image (saliency, edges, noise) stay at the frame's size:
/// saliency made on the grid agreed far less with a converged image's (docs/runtime.md).
#pragma once

#include <cstdint>
#include <vector>

#include "runtime/pipeline/subsample.h"
#include "stdlib/guidance/raster.h"

namespace crex {

class GuidanceGrid {
public:
    /// The grid of a `width` x `height` frame at `stride` (>= 1).
    GuidanceGrid(int width, int height, uint32_t stride);
    int width() const { return static_cast<int>(xs_.size()); }
    int height() const { return static_cast<int>(ys_.size()); }
    /// The frame's columns and rows the grid holds, in order.
    const std::vector<int>& columns() const { return xs_; }
    const std::vector<int>& rows() const { return ys_; }
    /// A grid-sized map spread over the frame: each pixel bilinear between its square's corners,
    /// as the preview's own pixels are (SubsampleGrid::fill_unsampled).
    guidance::Raster spread(const guidance::Raster& map) const;

private:
    SubsampleGrid preview_;  // the preview's grid at this stride: its corners are this grid
    std::vector<int> xs_, ys_;
    std::vector<uint8_t> corners_;  // per frame pixel: 1 on the grid
};

}  // namespace crex
