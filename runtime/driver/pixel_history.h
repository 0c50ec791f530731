/// \file pixel_history.h
/// Samples a frame inherits from the frame before (issue 36, `--reuse-frames`): the previous
/// frame's final value at the surface point each pixel sees, counted as some of the pixel's
/// samples. A pixel that inherits h of them takes h fewer of its own (at least one), and its
/// image is its own samples' mean and the inherited value, weighted by their counts: the
/// temporal accumulation of real-time renderers, with the count capped at N frames' worth of
/// the pixel's own samples (`--reuse-frames N`) so that what a frame inherits fades, by
/// N / (N + 1) a frame whatever the pixel's own count. Inherited light is the light of a
/// point seen from where the camera was a frame ago: right for light that does not depend on
/// the view, so frame_reuse.h lets only surfaces without an ideal specular lobe inherit.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "runtime/render/film.h"

namespace crex {

struct PixelHistory {
    std::vector<float> rgb;     ///< per pixel RGB radiance (linear)
    std::vector<float> weight;  ///< per pixel, the samples the value carries (0: none), before the cap
    /// The cap: beside n samples of its own a pixel's inherited value counts as at most
    /// `frames` x n samples (`--reuse-frames`; 0: no cap).
    float frames = 0;
    float samples(size_t pixel) const { return pixel < weight.size() ? weight[pixel] : 0.0f; }
    /// What pixel `pixel`'s inherited value counts as beside `own` samples of its own.
    double counted(size_t pixel, double own) const {
        const double h = std::max(0.0f, samples(pixel));
        return frames > 0 ? std::min(h, static_cast<double>(frames) * own) : h;
    }
};

/// Of `spp` samples a pixel asks for, those it takes itself when it carries `inherited` from
/// the frame before, capped at `frames` times its own (PixelHistory::frames): the rest, and
/// at least spp / (frames + 1), and at least one (new light at every pixel every frame). The
/// second keeps the weight of a frame's own samples at 1 / (frames + 1) however many a pixel
/// asks for: with the rest alone, a pixel asking for 16 beside 8 inherited took 8, weighed
/// half its image and flickered more than one asking for 9, which took 1 at a ninth.
inline uint32_t own_samples(double spp, float inherited, float frames) {
    if (!(spp > 0)) return 0;
    const double rest = std::ceil(spp - static_cast<double>(std::max(0.0f, inherited)) - 1e-9);
    const double share = frames > 0 ? std::ceil(spp / (static_cast<double>(frames) + 1) - 1e-9) : 0.0;
    return static_cast<uint32_t>(std::clamp(std::max(rest, share), 1.0, std::ceil(spp - 1e-9)));
}

/// How far an inherited value may lie from the mean of its pixel's neighbourhood in this
/// frame, in the neighbourhood's standard deviations (blend_history).
inline constexpr double kHistoryClip = 1.5;

/// Folds `history` into the composite `rgb` of `film` (per pixel mean radiance): each pixel
/// with its own samples n and an inherited weight h becomes (n rgb + h value) / (n + h), the
/// value first clipped to its 3x3 neighbourhood's mean +- kHistoryClip standard deviations of
/// this frame's own pixels (the variance clipping of temporal anti-aliasing). Pixels without
/// samples of their own are left to whatever fills them.
void blend_history(std::vector<float>& rgb, const Film& film, const PixelHistory& history);

/// The samples each pixel of `image` (the frame's final image, history blended in) counts as
/// for the frame after: its own and what it inherited; 0 where it has none of its own.
PixelHistory history_of(const std::vector<float>& image, const Film& film, const PixelHistory* inherited);

}  // namespace crex
