// Edge maps: where the image changes, a sub-sampled grid or a cached value is least trusted.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "stdlib/guidance/filters.h"
#include "stdlib/guidance/operators.h"

namespace crex::guidance {

Raster edges(const Raster& display) {
    // Smooth first (as Canny does): a preview of a few samples per pixel is noisy, and the
    // noise of single pixels should not read as edges. Scale by the 99th percentile, so that a
    // handful of fireflies cannot squash every real edge towards 0.
    Raster y = gaussian_blur(luminance(display), 1.0), gx, gy;
    sobel(y, gx, gy);
    Raster m(y.width, y.height, 1);
    for (size_t i = 0; i < m.v.size(); ++i) m.v[i] = std::hypot(gx.v[i], gy.v[i]);
    std::vector<float> sorted = m.v;
    size_t k = sorted.empty() ? 0 : (sorted.size() - 1) * 99 / 100;
    if (!sorted.empty()) std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
    float scale = sorted.empty() ? 0.0f : sorted[k];
    if (!(scale > 0)) {
        normalise_max(m);
        return m;
    }
    for (float& x : m.v) x /= scale;
    clamp01(m);
    return m;
}

Raster radiance_difference(const Raster& display) {
    Raster y = luminance(display);
    Raster m(y.width, y.height, 1);
    for (int py = 0; py < y.height; ++py)
        for (int px = 0; px < y.width; ++px) {
            float c = y.at(px, py), d = 0;
            d = std::max(d, std::fabs(c - y.clamped(px - 1, py)));
            d = std::max(d, std::fabs(c - y.clamped(px + 1, py)));
            d = std::max(d, std::fabs(c - y.clamped(px, py - 1)));
            d = std::max(d, std::fabs(c - y.clamped(px, py + 1)));
            m.at(px, py) = d;
        }
    normalise_max(m);
    return m;
}

}  // namespace crex::guidance
