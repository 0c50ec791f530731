/// \file frame_geometry.h
/// What each pixel centre of a frame sees, and which pixel of the frame before saw the same
/// surface point (issue 36): the warp under a frame's flicker (frame_flicker.h) and the
/// samples a frame inherits from the one before (frame_reuse.h).
#pragma once

#include <array>
#include <cstdint>
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

/// For each pixel of `current`, the pixel of `previous` that saw the same surface point, or
/// -1: its point projects into the previous frame onto a pixel that saw the same shape within
/// two pixel footprints (at least 1 %) of the point's distance from the previous camera.
/// Nothing matches across a change of size or a projection without a matrix (the fisheyes).
std::vector<int32_t> previous_pixels(const FrameGeometry& previous, const FrameGeometry& current, const Vec3& origin_offset);

/// The four pixels of the frame before around where a pixel's point falls, with bilinear
/// weights (those above 0; pixel -1: no tap), where every one of them saw the point's shape
/// inside it (its 3x3 neighbourhood all that shape, as is the pixel's own) at about the
/// point's distance; else no tap at all.
struct PixelTaps {
    std::array<int32_t, 4> pixel{-1, -1, -1, -1};
    std::array<float, 4> weight{};
};
std::vector<PixelTaps> previous_taps(const FrameGeometry& previous, const FrameGeometry& current, const Vec3& origin_offset);

}  // namespace crex
