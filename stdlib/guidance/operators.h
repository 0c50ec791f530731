/// \file operators.h
/// The guidance operators of spec/pipeline.md §1: each turns rasters (the preview, component
/// buffers, other maps) and what the camera sees (object ids) into a map in [0, 1] at image
/// resolution. They are a library: the runtime binds each to its registry entry
/// (compiler/pipeline/registry.h) in runtime/pipeline/guidance_graph.cpp, and nothing in the
/// compiler knows how they work.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "stdlib/guidance/raster.h"

namespace crex::guidance {

/// Itti-Koch saliency of an RGB image in display values (0..1): intensity, red/green and
/// blue/yellow opponency and four orientations, centre-surround differences over a Gaussian
/// pyramid, the N() normalisation, conspicuity maps combined with equal weights.
Raster saliency(const Raster& display_rgb);

/// Sobel gradient magnitude of the luminance, scaled so the strongest edge is 1.
Raster edges(const Raster& display);

/// Largest luminance difference between a pixel and its four neighbours, scaled to max 1:
/// where neighbouring samples disagree, a sub-sampled grid must refine (thesis ch. 7).
Raster radiance_difference(const Raster& display);

/// What the camera sees at each pixel (object = index of a scene shape, -1 for nothing) and
/// the geometry of the viewer, for the task and distractor maps.
struct ViewGeometry {
    int width = 0, height = 0;
    double view_distance = 1;  ///< viewer to display, in display widths
    /// Visual angle (radians) between pixel centres `d` pixels apart, at the display centre.
    double visual_angle(double d_pixels) const;
};

/// Task map (thesis 4.8): `value[i]` (0..1) on the pixels of object set i (`covered[i]`,
/// row-major), falling linearly with visual angle to `base` at `fovea` radians; the maximum
/// over the sets.
Raster task_map(const std::vector<std::vector<bool>>& covered, const std::vector<double>& value, const ViewGeometry& view,
                double fovea, double base = 0);

/// The q-buffer of the on-screen distractor map (thesis 4.5): the highest quality requested of
/// each pixel so far. A request returns only the quality still missing, so overlapping
/// gradients never shoot a pixel twice.
class QBuffer {
public:
    explicit QBuffer(size_t pixels) : q_(pixels, 0.0f) {}
    /// Requests `quality` (0..1) for `pixel`; returns the extra quality granted (>= 0).
    float request(size_t pixel, float quality);
    const std::vector<float>& qualities() const { return q_; }

private:
    std::vector<float> q_;
};

/// On-screen distractor map: every pixel whose detectable ray (camera ray, or the specular
/// ray it continues as) sees a distractor requests quality 1 there, falling linearly to 0 at
/// `fovea` radians, through a q-buffer. `granted` (optional) receives the total granted per
/// pixel, which never exceeds its highest request.
Raster distractor_map(const std::vector<bool>& detectable, const ViewGeometry& view, double fovea,
                      std::vector<float>* granted = nullptr);

/// IM(w, op) of weighted maps (thesis 4.8): op "+" sums w_i m_i, "max" takes the largest
/// w_i m_i, "*" multiplies them; clamped to [0, 1]. In a sum, maps that are 0 everywhere hand
/// their weight to the others (the weights of the rest are scaled to the same total).
Raster importance(const std::vector<const Raster*>& maps, const std::vector<double>& weights, const std::string& op);

/// Where the image is still noisy, as a viewer would see it: from the displayed (tone-mapped)
/// image at its pixels' mean plus and minus their standard error (the film's two half-buffers),
/// the luminance difference, blurred by one pixel and scaled so the 98th percentile is 1.
Raster noise_map(const Raster& display_high, const Raster& display_low);

Raster constant_map(int width, int height, double value);
Raster threshold(const Raster& map, double at);

}  // namespace crex::guidance
