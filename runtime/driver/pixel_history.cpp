#include "runtime/driver/pixel_history.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace crex {

void blend_history(std::vector<float>& rgb, const Film& film, const PixelHistory& history) {
    const size_t n = film.pixel_count();
    if (rgb.size() != 3 * n || history.rgb.size() != 3 * n || history.weight.size() != n) return;
    const std::vector<float> own_rgb = rgb;  // the neighbourhoods are of the frame's own samples
    const int w = film.width(), h = film.height();
    // Rows in parallel: each pixel reads the frame's own values (a copy) and writes only itself.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 12), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t p = range.begin(); p < range.end(); ++p) {
            const double own = film.samples(static_cast<uint32_t>(p)), inherited = history.counted(p, own);
            if (!(own > 0) || !(inherited > 0)) continue;
            // The inherited value clipped to what the pixel's 3x3 neighbourhood of this frame's own
            // samples makes likely (mean +- kHistoryClip standard deviations, each channel): light
            // the frame before saw and this one does not (a firefly, a change) does not linger.
            const int x = static_cast<int>(p % static_cast<size_t>(w)), y = static_cast<int>(p / static_cast<size_t>(w));
            double sum[3] = {0, 0, 0}, squares[3] = {0, 0, 0}, count = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int qx = x + dx, qy = y + dy;
                    if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
                    const size_t q = static_cast<size_t>(qy) * static_cast<size_t>(w) + static_cast<size_t>(qx);
                    if (film.samples(static_cast<uint32_t>(q)) == 0) continue;
                    bool finite = true;
                    for (size_t c = 0; c < 3; ++c) finite = finite && std::isfinite(own_rgb[3 * q + c]);
                    if (!finite) continue;
                    for (size_t c = 0; c < 3; ++c) sum[c] += own_rgb[3 * q + c], squares[c] += double(own_rgb[3 * q + c]) * own_rgb[3 * q + c];
                    ++count;
                }
            for (size_t c = 0; c < 3; ++c) {
                double past = history.rgb[3 * p + c];
                if (count > 0) {
                    const double mean = sum[c] / count, sigma = std::sqrt(std::max(0.0, squares[c] / count - mean * mean));
                    past = std::clamp(past, mean - kHistoryClip * sigma, mean + kHistoryClip * sigma);
                }
                const double v = (own * rgb[3 * p + c] + inherited * past) / (own + inherited);
                if (std::isfinite(v)) rgb[3 * p + c] = static_cast<float>(v);
            }
        }
    });
}

PixelHistory history_of(const std::vector<float>& image, const Film& film, const PixelHistory* inherited) {
    const size_t n = film.pixel_count();
    PixelHistory out;
    out.rgb = image;
    out.weight.assign(n, 0.0f);
    if (inherited) out.frames = inherited->frames;
    if (image.size() != 3 * n) return out;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 12), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t p = range.begin(); p < range.end(); ++p) {
            const uint32_t own = film.samples(static_cast<uint32_t>(p));
            bool finite = true;
            for (size_t c = 0; c < 3; ++c) finite = finite && std::isfinite(image[3 * p + c]);
            if (own > 0 && finite) out.weight[p] = static_cast<float>(own + (inherited ? inherited->counted(p, own) : 0.0));
        }
    });
    return out;
}

}  // namespace crex
