/// \file metrics.h
/// Image error metrics (issue 8; spec/pipeline.md §7 "Metrics"). Images are RGB, 3 floats per
/// pixel, row-major, the same size. Linear metrics (RMSE, relMSE) read linear radiance;
/// perceptual ones (SSIM, FLIP, perr) read display values in [0, 1] (display_view()).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace crex::metrics {

struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb;
};

/// Root mean squared error over every channel of every pixel.
double rmse(const Image& test, const Image& reference);

/// Relative MSE: mean of (t - r)^2 / (r^2 + eps) over channels (eps = 0.01, as usual in
/// rendering papers, so black reference pixels do not dominate).
double relmse(const Image& test, const Image& reference, double eps = 1e-2);

/// Mean SSIM (Wang et al. 2004) of the luminance, with the 11x11 Gaussian window (sigma 1.5)
/// over every position where it fits, C1 = (0.01)^2, C2 = (0.03)^2 for values in [0, 1].
/// nullopt if the image is smaller than the window.
std::optional<double> ssim(const Image& test_display, const Image& reference_display);

/// The per-pixel LDR-FLIP error map (Andersson et al. 2020, "FLIP: A Difference Evaluator for
/// Alternating Images"), values in [0, 1], for display-referred sRGB inputs viewed at
/// `pixels_per_degree` (default: 0.7 m from a 0.7 m wide 3840-pixel monitor, 67.02).
std::vector<float> flip_map(const Image& test_display, const Image& reference_display, double pixels_per_degree = 67.0206);

/// Fireflies: pixels whose luminance is over 10 times the median of their 3x3 neighbourhood
/// (edges clamped) and over a hundredth of the image's mean luminance (so that noise in black
/// regions is not counted). A count; per megapixel it compares images of any size.
size_t firefly_count(const Image& linear);

inline constexpr double kDefaultPerrThreshold = 0.1;
/// perr: the percentage of pixels whose FLIP value is at least `threshold` (not Daly's VDP).
double perr(const std::vector<float>& flip, double threshold = kDefaultPerrThreshold);
double mean(const std::vector<float>& values);

/// Attention-weighted mean: sum(w_i v_i) / sum(w_i), so errors count where a viewer looks
/// (weights: a saliency or task map in [0, 1]). Negative and non-finite weights count as 0;
/// nullopt when every weight is 0 or the sizes differ.
std::optional<double> weighted_mean(const std::vector<float>& values, const std::vector<float>& weights);
/// The two sums of weighted_mean(), sum(w_i v_i) and sum(w_i) (both 0 when the sizes differ),
/// so that means over several images (windows) combine.
struct WeightedSum {
    double sum = 0, weight = 0;
};
WeightedSum weighted_sum(const std::vector<float>& values, const std::vector<float>& weights);

/// How an image is shown to the perceptual metrics: LDR inputs as they are (sRGB), HDR inputs
/// through the tone map of spec §7 with the *reference's* exposure, so both images of a pair
/// are seen the same way.
struct DisplayView {
    bool hdr = false;
    double exposure = 1;
    std::string describe() const;
};
Image display_view(const Image& linear, const DisplayView& view);

}  // namespace crex::metrics
