#include "stdlib/guidance/raster.h"

#include <algorithm>
#include <cmath>

namespace crex::guidance {

Raster luminance(const Raster& rgb) {
    Raster y(rgb.width, rgb.height, 1);
    if (rgb.channels < 3) {
        for (size_t i = 0; i < y.pixels(); ++i) y.v[i] = rgb.v[i * static_cast<size_t>(rgb.channels)];
        return y;
    }
    for (size_t i = 0; i < y.pixels(); ++i) {
        const float* p = &rgb.v[i * static_cast<size_t>(rgb.channels)];
        y.v[i] = 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
    }
    return y;
}

void clamp01(Raster& map) {
    for (float& x : map.v) x = std::isnan(x) ? 0.0f : std::clamp(x, 0.0f, 1.0f);
}

void normalise_max(Raster& map) {
    float mx = 0;
    for (float x : map.v)
        if (std::isfinite(x)) mx = std::max(mx, x);
    if (mx > 0)
        for (float& x : map.v) x = std::isfinite(x) ? x / mx : (x > 0 ? 1.0f : 0.0f);
    clamp01(map);
}

}  // namespace crex::guidance
