#include "runtime/driver/run_result.h"

#include <cmath>

namespace crex {

std::vector<float> RunResult::image() const {
    std::vector<double> stand_in = ambient;
    component_subsample.add_stand_ins(film, stand_in);
    std::vector<float> rgb = film.composite(&stand_in);
    if (history) blend_history(rgb, film, *history);
    fill_unsampled_preview(rgb);
    if (subsample) subsample->fill(rgb);
    return rgb;
}

std::vector<float> RunResult::aov_image(size_t aov) const {
    std::vector<float> rgb = film.aov_image(aov);
    if (rgb.empty()) return rgb;  // the film kept no sum for it (RunSettings::component_images)
    // capict: a component's image takes its branch's interpolation (the whole branch, also what
    // it found through other components' rays below the first bounce), so the images still add
    // up to the final image.
    if (aov != kCameraAov && component_subsample.grid(static_cast<Component>(aov - 1))) {
        std::vector<double> delta = component_subsample.stand_ins(film, static_cast<Component>(aov - 1));
        for (uint32_t p = 0; p < film.pixel_count(); ++p)
            if (const double n = film.samples(p); n > 0)
                for (size_t k = 0; k < 3; ++k) {
                    const float v = static_cast<float>(rgb[3 * p + k] + delta[3 * p + k] / n);
                    rgb[3 * p + k] = std::isfinite(v) ? v : 0.0f;
                }
    }
    fill_unsampled_preview(rgb);
    if (subsample) subsample->fill(rgb);
    return rgb;
}

std::vector<uint8_t> RunResult::sampled_pixels() const {
    std::vector<uint8_t> sampled(film.pixel_count());
    for (uint32_t p = 0; p < sampled.size(); ++p) sampled[p] = film.samples(p) > 0;
    return sampled;
}

void RunResult::fill_unsampled_preview(std::vector<float>& values, const SubsampleGrid::Fill* fill) const {
    if (!preview_grid) return;
    if (fill) SubsampleGrid::apply(*fill, values);
    else preview_grid->fill_unsampled(values, sampled_pixels());
}

}  // namespace crex
