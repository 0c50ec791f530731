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

#include "runtime/base/vec3.h"
#include "runtime/render/render_scene.h"

namespace crex {

/// What the camera (the scene's, as it is now) sees through each pixel centre: the point, in
/// the render scene's local coordinates, and its shape (-1: nothing).
struct FrameGeometry {
    int width = 0, height = 0;
    Camera camera;
    std::vector<Vec3> point;
    std::vector<int32_t> shape;
};
FrameGeometry frame_geometry(const RenderScene& scene, int width, int height);

struct FrameFlicker {
    double difference = 0;  ///< mean over matched pixels and channels of |a - b|, display values in [0, 1]
    double matched = 0;     ///< fraction of the current frame's pixels matched
};

/// `image` against `previous_image` warped onto it, both display values (to_display() with
/// one exposure: an exposure that changes would count as flicker); nullopt when no pixel matches
/// (or a projection without a matrix: the fisheyes). A pixel matches where its point projects
/// into the previous frame onto a pixel that saw the same shape within two pixel footprints
/// (at least 1 %) of the point's distance from the previous camera.
std::optional<FrameFlicker> frame_flicker(const FrameGeometry& previous, const std::vector<float>& previous_image,
                                          const FrameGeometry& current, const std::vector<float>& image, const Vec3& origin_offset);

}  // namespace crex
