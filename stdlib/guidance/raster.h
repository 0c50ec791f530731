/// \file raster.h
/// A guidance map or buffer: a float image, row-major, top row first, `channels` floats per
/// pixel. Plain data (serialisable), the only image type the guidance operators exchange.
#pragma once

#include <cstddef>
#include <vector>

namespace crex::guidance {

struct Raster {
    int width = 0, height = 0, channels = 1;
    std::vector<float> v;

    Raster() = default;
    Raster(int w, int h, int c = 1, float fill = 0.0f)
        : width(w), height(h), channels(c), v(static_cast<size_t>(w) * static_cast<size_t>(h) * static_cast<size_t>(c), fill) {}

    size_t pixels() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
    size_t index(int x, int y, int c = 0) const {
        return (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * static_cast<size_t>(channels) +
               static_cast<size_t>(c);
    }
    float& at(int x, int y, int c = 0) { return v[index(x, y, c)]; }
    float at(int x, int y, int c = 0) const { return v[index(x, y, c)]; }
    /// Clamped to the border: filters read beyond the edge as the edge.
    float clamped(int x, int y, int c = 0) const {
        x = x < 0 ? 0 : (x >= width ? width - 1 : x);
        y = y < 0 ? 0 : (y >= height ? height - 1 : y);
        return at(x, y, c);
    }
};

/// Rec.709 luminance of an RGB raster (one channel).
Raster luminance(const Raster& rgb);

/// Scales a map so its maximum is 1 (an all-zero map stays zero) and clamps to [0, 1]; NaN
/// becomes 0. Every operator ends with this or an explicit clamp, so maps are always in [0, 1].
void normalise_max(Raster& map);
/// The same with the maximum already known: `max` is finite_max(map.v).
void normalise_max(Raster& map, float max);
void clamp01(Raster& map);
/// The largest finite value, or 0 when none is positive.
float finite_max(const std::vector<float>& values);

/// The k-th smallest of `values` (k < size), the value std::nth_element would put at k, for
/// percentiles. Linear time and no copy when no value is negative or NaN, as in a map.
float nth_smallest(const std::vector<float>& values, size_t k);

}  // namespace crex::guidance
