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
    // hypot of floats, as glibc's hypotf computes it (exact squares in double), without its
    // call per pixel: this loop vectorises.
    for (size_t i = 0; i < m.v.size(); ++i) {
        double a = gx.v[i], b = gy.v[i];
        m.v[i] = static_cast<float>(std::sqrt(a * a + b * b));
    }
    float scale = m.v.empty() ? 0.0f : nth_smallest(m.v, (m.v.size() - 1) * 99 / 100);
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
    const size_t w = static_cast<size_t>(y.width), h = static_cast<size_t>(y.height);
    Raster m(y.width, y.height, 1);
    for (size_t py = 0; py < h; ++py) {
        // Borders are clamped: the missing neighbour is the pixel itself, a difference of 0.
        const float* c = &y.v[py * w];
        const float* up = py > 0 ? c - w : c;
        const float* down = py + 1 < h ? c + w : c;
        float* out = &m.v[py * w];
        for (size_t px = 0; px < w; ++px) {
            float left = c[px > 0 ? px - 1 : px], right = c[px + 1 < w ? px + 1 : px], d = 0;
            d = std::max(d, std::fabs(c[px] - left));
            d = std::max(d, std::fabs(c[px] - right));
            d = std::max(d, std::fabs(c[px] - up[px]));
            d = std::max(d, std::fabs(c[px] - down[px]));
            out[px] = d;
        }
    }
    normalise_max(m);
    return m;
}

}  // namespace crex::guidance
