#include "runtime/metrics/image_comparison.h"

#include <cmath>

namespace crex::metrics {

ImageComparison compare_images(const Image& test, const Image& reference, const DisplayView& view, const MetricChoice& choice,
                               const std::vector<float>* weights) {
    ImageComparison c;
    c.pixels = static_cast<size_t>(reference.width) * static_cast<size_t>(reference.height);
    if (choice.rmse) c.rmse = rmse(test, reference);
    if (choice.relmse) c.relmse = relmse(test, reference);
    if (choice.fireflies) c.test_fireflies = firefly_count(test), c.reference_fireflies = firefly_count(reference);
    const bool perceptual = choice.ssim || choice.flip || choice.perr;
    if (!perceptual && !choice.flip_map && !weights) return c;
    const Image td = display_view(test, view), rd = display_view(reference, view);
    c.flip_map = flip_map(td, rd, choice.pixels_per_degree);
    if (choice.ssim) c.ssim_asked = true, c.ssim = ssim(td, rd);
    if (choice.flip) c.flip = mean(c.flip_map);
    if (choice.perr) c.perr = perr(c.flip_map, choice.perr_threshold);
    if (weights) {
        const WeightedSum s = weighted_sum(c.flip_map, *weights);
        c.weighted_flip = s.sum, c.weight = s.weight;
        if (c.weight > 0) c.aflip = c.weighted_flip / c.weight;
    }
    return c;
}

ImageComparison combine(const std::vector<ImageComparison>& parts) {
    ImageComparison all;
    double sq = 0, rel = 0, flip = 0, perr_sum = 0, ssim_sum = 0;
    size_t ssim_pixels = 0;
    for (const ImageComparison& p : parts) {
        const double n = static_cast<double>(p.pixels);
        all.pixels += p.pixels;
        if (p.rmse) sq += n * *p.rmse * *p.rmse;
        if (p.relmse) rel += n * *p.relmse;
        if (p.flip) flip += n * *p.flip;
        if (p.perr) perr_sum += n * *p.perr;
        if (p.ssim) ssim_sum += n * *p.ssim, ssim_pixels += p.pixels;
        all.ssim_asked |= p.ssim_asked;
        all.weight += p.weight, all.weighted_flip += p.weighted_flip;
        if (p.test_fireflies) all.test_fireflies = all.test_fireflies.value_or(0) + *p.test_fireflies;
        if (p.reference_fireflies) all.reference_fireflies = all.reference_fireflies.value_or(0) + *p.reference_fireflies;
    }
    if (parts.empty() || all.pixels == 0) return all;
    const double n = static_cast<double>(all.pixels);
    const ImageComparison& first = parts.front();
    if (first.rmse) all.rmse = std::sqrt(sq / n);
    if (first.relmse) all.relmse = rel / n;
    if (first.flip) all.flip = flip / n;
    if (first.perr) all.perr = perr_sum / n;
    if (ssim_pixels) all.ssim = ssim_sum / static_cast<double>(ssim_pixels);
    if (all.weight > 0) all.aflip = all.weighted_flip / all.weight;
    return all;
}

}  // namespace crex::metrics
