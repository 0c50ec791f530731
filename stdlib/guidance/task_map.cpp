// Task and distractor maps: quality where the viewer looks (thesis 4.5, 4.8). Both fall off
// with *visual angle*, the angle at the viewer's eye between two points of the display,
// which is what foveal vision is measured in.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "stdlib/guidance/filters.h"
#include "stdlib/guidance/operators.h"

namespace crex::guidance {

double ViewGeometry::visual_angle(double d_pixels) const {
    double display_width_pixels = std::max(1, width);
    return std::atan(d_pixels / (std::max(view_distance, 1e-6) * display_width_pixels));
}

namespace {

// A map value as a function of the squared distance to the nearest feature, d2, which the
// distance transform gives as an integer: each distinct d2 is evaluated once (an atan), not
// once per pixel. Past the foveal radius every value is the one at "no feature at all".
template <class F>
class ByDistance {
public:
    ByDistance(F f, const ViewGeometry& view, double fovea) : f_(std::move(f)), far_(f_(kNoFeature)) {
        double w = std::max(view.width - 1, 0), h = std::max(view.height - 1, 0);
        double largest = w * w + h * h;  // no two pixels are farther apart
        double size = largest + 1;
        if (!(fovea > 0)) {
            size = 1;  // only d2 = 0 is on the object
        } else if (fovea < std::numbers::pi / 2) {
            // Past radius^2 + 1 the angle exceeds the fovea by far more than rounding.
            double radius = std::tan(fovea) * std::max(view.view_distance, 1e-6) * std::max(1, view.width);
            size = std::min(size, std::floor(radius * radius) + 2);
        }
        table_.assign(static_cast<size_t>(size), std::numeric_limits<float>::quiet_NaN());
    }
    /// Distances at or past this many pixels all have the far value.
    double reach() const { return std::sqrt(static_cast<double>(table_.size())); }
    float far() const { return far_; }
    float operator()(double d2) {
        if (!(d2 < static_cast<double>(table_.size()))) return far_;
        float& v = table_[static_cast<size_t>(d2)];
        if (std::isnan(v)) v = f_(d2);
        return v;
    }

private:
    F f_;
    float far_;
    std::vector<float> table_;  // NaN: not evaluated yet
};

}  // namespace

Raster task_map(const std::vector<std::vector<bool>>& covered, const std::vector<double>& value, const ViewGeometry& view,
                double fovea, double base) {
    const double low = std::clamp(base, 0.0, 1.0);
    Raster m(view.width, view.height, 1, static_cast<float>(low));
    for (size_t s = 0; s < covered.size(); ++s) {
        const double v = std::clamp(value[s], 0.0, 1.0);
        ByDistance value_at(
            [&](double d2) {
                double angle = view.visual_angle(std::sqrt(d2));
                // Linear from v on the object to base at the foveal radius; never below base.
                double t = fovea > 0 ? std::clamp(angle / fovea, 0.0, 1.0) : (d2 > 0 ? 1.0 : 0.0);
                return static_cast<float>(v + (low - v) * t);
            },
            view, fovea);
        squared_distance_rows(covered[s], view.width, view.height, value_at.reach(), [&](int y, const double* d2) {
            float* row = &m.v[static_cast<size_t>(y) * static_cast<size_t>(view.width)];
            if (!d2) {
                for (size_t x = 0; x < static_cast<size_t>(view.width); ++x) row[x] = std::max(row[x], value_at.far());
                return;
            }
            for (size_t x = 0; x < static_cast<size_t>(view.width); ++x) row[x] = std::max(row[x], value_at(d2[x]));
        });
    }
    clamp01(m);
    return m;
}

float QBuffer::request(size_t pixel, float quality) {
    float q = std::clamp(std::isnan(quality) ? 0.0f : quality, 0.0f, 1.0f);
    float extra = std::max(0.0f, q - q_[pixel]);
    q_[pixel] += extra;
    return extra;
}

Raster distractor_map(const std::vector<bool>& detectable, const ViewGeometry& view, double fovea, std::vector<float>* granted) {
    // Every detectable pixel requests 1 - angle / fovea of the pixels around it through the
    // q-buffer, which keeps each pixel's highest request: the one from the nearest detectable
    // pixel. So the buffer's end state is a function of that distance, and the total granted
    // to a pixel is that highest request.
    ByDistance quality_at(
        [&](double d2) {
            double quality = fovea > 0 ? 1 - view.visual_angle(std::sqrt(d2)) / fovea : (d2 == 0 ? 1 : 0);
            return static_cast<float>(std::max(quality, 0.0));
        },
        view, fovea);
    Raster m(view.width, view.height, 1);
    squared_distance_rows(detectable, view.width, view.height, quality_at.reach(), [&](int y, const double* d2) {
        float* row = &m.v[static_cast<size_t>(y) * static_cast<size_t>(view.width)];
        for (size_t x = 0; x < static_cast<size_t>(view.width); ++x) row[x] = d2 ? quality_at(d2[x]) : quality_at.far();
    });
    clamp01(m);
    if (granted) *granted = m.v;
    return m;
}

}  // namespace crex::guidance
