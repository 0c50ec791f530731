/// \file image_comparison.h
/// One comparison of a test image with a reference by the metrics `crex compare` reports, in
/// one place, so that a whole image and each window of a windowed reference (issue 32) are
/// measured by the same code.
#pragma once

#include <optional>
#include <vector>

#include "runtime/metrics/metrics.h"

namespace crex::metrics {

/// Which metrics to compute, and their parameters.
struct MetricChoice {
    bool rmse = false, relmse = false, ssim = false, flip = false, perr = false, fireflies = false;
    double perr_threshold = kDefaultPerrThreshold;
    double pixels_per_degree = 67.0206;
    /// The FLIP map is computed anyway when a perceptual metric, weights or the map is asked for.
    bool flip_map = false;
};

struct ImageComparison {
    size_t pixels = 0;
    std::optional<double> rmse, relmse, flip, perr;
    bool ssim_asked = false;
    std::optional<double> ssim;      ///< nullopt (when asked) if the image is smaller than SSIM's window
    /// With weights: the attention-weighted FLIP and the sums it is made of, so that several
    /// comparisons (windows) combine into one: aflip = weighted_flip / weight.
    std::optional<double> aflip;
    double weight = 0, weighted_flip = 0;
    std::vector<float> flip_map;     ///< per pixel, when computed
    /// firefly_count() of the test image and of the reference, when asked.
    std::optional<size_t> test_fireflies, reference_fireflies;
};

/// `test` against `reference` (same size, linear values as read) seen through `view`;
/// `weights` (one per pixel, or null) give the attention-weighted FLIP.
ImageComparison compare_images(const Image& test, const Image& reference, const DisplayView& view, const MetricChoice& choice,
                               const std::vector<float>* weights = nullptr);

/// Several comparisons as one over all their pixels: means weighted by pixel count (RMSE as
/// the root of the mean square), SSIM over the parts it fits, aflip as the ratio of the sums.
ImageComparison combine(const std::vector<ImageComparison>& parts);

}  // namespace crex::metrics
