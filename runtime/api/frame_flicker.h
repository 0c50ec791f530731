/// \file frame_flicker.h
/// Flicker between consecutive frames of a camera path (issue 36): the previous frame warped
/// onto the current one through what each pixel centre sees, and the mean absolute difference
/// of their display values (the PNG tone map, one exposure for the whole sequence) over the
/// pixels that see the same surface point in both. Noise that changes from frame to frame is
/// what a viewer sees as flicker; a converged sequence of a static, diffuse scene scores about
/// 0 (view-dependent shading and sub-pixel shifts at edges are what remains). Display values,
/// not relative MSE of radiance: that was dominated by a few lamp pixels and fireflies (frames
/// of one walk scored 0.09 to 0.46 at 16 spp).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "runtime/api/frame_geometry.h"

namespace crex {

struct FrameFlicker {
    double difference = 0;  ///< mean over matched pixels and channels of |a - b|, display values in [0, 1]
    double matched = 0;     ///< fraction of the current frame's pixels matched
};

/// `image` against `previous_image` warped onto it, both display values (to_display() with
/// one exposure: an exposure that changes would count as flicker); nullopt when no pixel matches
/// (or a projection without a matrix: the fisheyes). Pixels match as previous_pixels() says.
std::optional<FrameFlicker> frame_flicker(const FrameGeometry& previous, const std::vector<float>& previous_image,
                                          const FrameGeometry& current, const std::vector<float>& image, const Vec3& origin_offset);

}  // namespace crex
