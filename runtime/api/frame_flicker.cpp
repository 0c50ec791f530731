#include "runtime/api/frame_flicker.h"

#include <cmath>

namespace crex {

std::optional<FrameFlicker> frame_flicker(const FrameGeometry& previous, const std::vector<float>& previous_image,
                                          const FrameGeometry& current, const std::vector<float>& image, const Vec3& origin_offset) {
    const size_t n = current.point.size();
    if (image.size() != 3 * n || previous_image.size() != 3 * n) return std::nullopt;
    const std::vector<int32_t> from = previous_pixels(previous, current, origin_offset);
    double sum = 0;
    size_t matched = 0;
    for (size_t p = 0; p < n; ++p) {
        if (from[p] < 0) continue;
        const size_t q = static_cast<size_t>(from[p]);
        for (size_t c = 0; c < 3; ++c) {
            const double a = image[3 * p + c], b = previous_image[3 * q + c];
            if (std::isfinite(a) && std::isfinite(b)) sum += std::fabs(a - b);
        }
        ++matched;
    }
    if (matched == 0) return std::nullopt;
    return FrameFlicker{sum / (3.0 * static_cast<double>(matched)), static_cast<double>(matched) / static_cast<double>(n)};
}

}  // namespace crex
