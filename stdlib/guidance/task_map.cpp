// Task and distractor maps: quality where the viewer looks (thesis 4.5, 4.8). Both fall off
// with *visual angle*, the angle at the viewer's eye between two points of the display,
// which is what foveal vision is measured in.
#include <algorithm>
#include <cmath>

#include "stdlib/guidance/filters.h"
#include "stdlib/guidance/operators.h"

namespace crex::guidance {

double ViewGeometry::visual_angle(double d_pixels) const {
    double display_width_pixels = std::max(1, width);
    return std::atan(d_pixels / (std::max(view_distance, 1e-6) * display_width_pixels));
}

Raster task_map(const std::vector<std::vector<bool>>& covered, const std::vector<double>& value, const ViewGeometry& view,
                double fovea, double base) {
    Raster m(view.width, view.height, 1, static_cast<float>(std::clamp(base, 0.0, 1.0)));
    for (size_t s = 0; s < covered.size(); ++s) {
        double v = std::clamp(value[s], 0.0, 1.0);
        std::vector<double> d2 = squared_distance_transform(covered[s], view.width, view.height);
        for (size_t i = 0; i < m.v.size(); ++i) {
            double angle = view.visual_angle(std::sqrt(d2[i]));
            // Linear from v on the object to base at the foveal radius; never below base.
            double t = fovea > 0 ? std::clamp(angle / fovea, 0.0, 1.0) : (d2[i] > 0 ? 1.0 : 0.0);
            double here = v + (std::clamp(base, 0.0, 1.0) - v) * t;
            m.v[i] = std::max(m.v[i], static_cast<float>(here));
        }
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
    const int w = view.width, h = view.height;
    QBuffer qbuffer(static_cast<size_t>(w) * static_cast<size_t>(h));
    if (granted) granted->assign(qbuffer.qualities().size(), 0.0f);
    // Radius in pixels of the foveal disc around a detected pixel.
    double radius = std::tan(std::max(fovea, 0.0)) * std::max(view.view_distance, 1e-6) * w;
    int r = static_cast<int>(std::ceil(radius));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (!detectable[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)]) continue;
            for (int dy = -r; dy <= r; ++dy)
                for (int dx = -r; dx <= r; ++dx) {
                    int qx = x + dx, qy = y + dy;
                    if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
                    double angle = view.visual_angle(std::hypot(dx, dy));
                    double quality = fovea > 0 ? 1 - angle / fovea : (dx == 0 && dy == 0 ? 1 : 0);
                    if (quality <= 0) continue;
                    size_t p = static_cast<size_t>(qy) * static_cast<size_t>(w) + static_cast<size_t>(qx);
                    float extra = qbuffer.request(p, static_cast<float>(quality));
                    if (granted) (*granted)[p] += extra;
                }
        }
    Raster m(w, h, 1);
    m.v = qbuffer.qualities();
    clamp01(m);
    return m;
}

}  // namespace crex::guidance
