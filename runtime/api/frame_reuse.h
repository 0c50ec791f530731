/// \file frame_reuse.h
/// A sequence's `--reuse-frames N` (issue 36): each frame inherits the one before's light
/// (pixel_history.h) at the pixels that see the same surface point (frame_geometry.h's
/// warp), up to N frames' worth of the pixel's own samples, and so takes fewer of its own.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "runtime/api/frame_geometry.h"
#include "runtime/driver/pixel_history.h"
#include "runtime/scene/scene.h"

namespace crex {

/// Per shape, whether what the camera sees of it may be inherited: its light does not change
/// much as the eye moves a frame's step. A surface with an ideal specular lobe (a mirror's
/// image, a polished reflection), glass and dielectrics (what is seen through them) and
/// spotlights seen directly may not; diffuse and glossy surfaces and plain emitters may.
std::vector<char> shapes_that_inherit(const Scene& scene);

/// `previous` (the frame before's history: its image and its pixels' sample counts) moved
/// onto this frame's pixels: pixel p takes the bilinear blend of its taps (frame_geometry.h)
/// that had samples, their counts blended alike, where its shape may inherit; else nothing.
/// The counts are capped later, at `frames` times the samples the pixel takes of its own
/// (PixelHistory::frames).
PixelHistory inherited_history(const PixelHistory& previous, const std::vector<PixelTaps>& from, const std::vector<int32_t>& shape,
                               const std::vector<char>& inherits, float frames);

/// The share of pixels that inherit anything, and their mean inherited count as it counts
/// beside the fewest own samples that carry it on (what a frame says it inherited: 8 at
/// `--reuse-frames 8` for a pixel that takes one sample a frame, 16 for one that takes two).
std::pair<double, double> inherited_share(const PixelHistory& history);

}  // namespace crex
