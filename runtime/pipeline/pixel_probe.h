/// \file pixel_probe.h
/// What the camera sees through each pixel centre, for the guidance operators that reason
/// about objects (task map, on-screen distractors) and media (X-map): one ray per pixel,
/// traced as one batch, never part of the image.
#pragma once

#include <cstdint>
#include <vector>

#include "runtime/base/vec3.h"
#include "runtime/render/render_scene.h"

namespace crex {

struct PixelProbe {
    int width = 0, height = 0;
    std::vector<int32_t> shape;     ///< shape index hit by the centre ray, -1 for none
    std::vector<int32_t> detected;  ///< shape seen by the pixel's detectable ray: the camera ray,
                                    ///< continued through mirrors (the OSDM's specular rays)
    std::vector<float> distance;    ///< to the first hit; +inf for none
    std::vector<Vec3> normal;       ///< geometric normal at the first hit, facing the camera; 0 for none
};

/// `mirror_bounces`: how many mirror reflections a detectable ray follows.
PixelProbe probe_pixels(const RenderScene& scene, int width, int height, int mirror_bounces = 4);
/// The same through the centres of a `width` x `height` frame's pixels in columns `xs` and rows
/// `ys` only (a strided preview's grid, guidance_grid.h): a probe of xs.size() x ys.size() pixels.
PixelProbe probe_pixels(const RenderScene& scene, int width, int height, const std::vector<int>& xs, const std::vector<int>& ys,
                        int mirror_bounces = 4);

}  // namespace crex
