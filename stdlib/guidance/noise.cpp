#include <algorithm>
#include <cmath>

#include "stdlib/guidance/filters.h"
#include "stdlib/guidance/operators.h"

namespace crex::guidance {

Raster noise_map(const Raster& display_high, const Raster& display_low) {
    // What a viewer would see of the noise: the displayed luminance of (mean + error) minus
    // that of (mean - error), spread over a pixel's neighbours (each pixel's own estimate is
    // noisy), in units of the 98th percentile so a few fireflies do not flatten the rest.
    Raster high = luminance(display_high), low = luminance(display_low);
    Raster m(high.width, high.height, 1);
    for (size_t p = 0; p < m.v.size(); ++p) {
        float d = std::fabs(high.v[p] - low.v[p]);
        m.v[p] = std::isfinite(d) ? d : 0.0f;
    }
    m = gaussian_blur(m, 1.0);
    if (m.v.empty()) return m;
    float scale = nth_smallest(m.v, std::min(m.v.size() - 1, static_cast<size_t>(0.98 * static_cast<double>(m.v.size()))));
    for (float& v : m.v) v = scale > 0 ? v / scale : 0.0f;
    clamp01(m);
    return m;
}

}  // namespace crex::guidance
