#include "stdlib/guidance/raster.h"

#include <algorithm>
#include <cmath>
#include <limits>

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

// These run over every map, several times: written as comparisons and selects, without
// calls, so that they vectorise. NaN fails every comparison.
void clamp01(Raster& map) {
    for (float& x : map.v) x = x >= 0.0f ? (x <= 1.0f ? x : 1.0f) : 0.0f;
}

float finite_max(const std::vector<float>& v) {
    constexpr float kLargest = std::numeric_limits<float>::max();
    float mx = 0;
#pragma omp simd reduction(max : mx)
    for (size_t i = 0; i < v.size(); ++i) mx = std::max(mx, std::fabs(v[i]) <= kLargest ? v[i] : 0.0f);
    return mx;
}

void normalise_max(Raster& map) { normalise_max(map, finite_max(map.v)); }

void normalise_max(Raster& map, float mx) {
    constexpr float kLargest = std::numeric_limits<float>::max();
    if (!(mx > 0)) {
        clamp01(map);
        return;
    }
    for (float& x : map.v) {
        float scaled = x / mx;  // for every x, so that no branch stops the loop vectorising
        scaled = std::fabs(x) <= kLargest ? scaled : (x > 0 ? 1.0f : 0.0f);
        x = scaled >= 0.0f ? (scaled <= 1.0f ? scaled : 1.0f) : 0.0f;  // clamp01
    }
}

}  // namespace crex::guidance
