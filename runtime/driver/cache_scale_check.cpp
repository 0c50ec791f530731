#include "runtime/driver/cache_scale_check.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "runtime/pipeline/pixel_probe.h"
#include "runtime/render/render_scene.h"

namespace crex {

std::optional<Diagnostic> coarse_cache_warning(const RenderScene& scene, const IcFileSettings& cache, int width, int height) {
    constexpr int kGrid = 24;  // 576 camera rays: nothing beside a render
    if (width <= 0 || height <= 0 || !(cache.min_radius > 0)) return std::nullopt;
    std::vector<int> xs, ys;
    for (int i = 0; i < kGrid; ++i) {
        xs.push_back(std::min(width - 1, (2 * i + 1) * width / (2 * kGrid)));
        ys.push_back(std::min(height - 1, (2 * i + 1) * height / (2 * kGrid)));
    }
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
    ys.erase(std::unique(ys.begin(), ys.end()), ys.end());
    const PixelProbe probe = probe_pixels(scene, width, height, xs, ys, 0);
    std::vector<float> seen;
    for (float d : probe.distance)
        if (std::isfinite(d) && d > 0) seen.push_back(d);
    if (seen.size() < 16) return std::nullopt;
    const auto ninth = seen.begin() + static_cast<std::ptrdiff_t>(seen.size() * 9 / 10);
    std::nth_element(seen.begin(), ninth, seen.end());
    const double near = *ninth;
    if (!(cache.min_radius > 0.05 * near)) return std::nullopt;
    // The --ar that makes the smallest record 1 % of that distance, within the option's range.
    const double wanted = std::ceil(cache.extent / (0.01 * near));
    const std::string fix = wanted <= 1e6 ? fmt::format("raise --ar to {:g}, or render without --ic", wanted)
                                          : std::string("no --ar up to 1e6 makes them fine enough: render without --ic, or leave out the shapes far from the view");
    return run_diagnostic("W407", "crex run",
                          fmt::format("the irradiance cache's records are at least {:.3g} wide (the scene's extent {:.3g} over {:g}, "
                                      "which --ar sets), where nine in ten of the surfaces in view lie within {:.3g}: their indirect "
                                      "light will come out in blotches; {}",
                                      cache.min_radius, cache.extent, std::round(cache.extent / cache.min_radius), near, fix));
}

}  // namespace crex
