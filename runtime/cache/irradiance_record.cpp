#include "runtime/cache/irradiance_record.h"

#include <algorithm>
#include <cmath>

namespace crex {

double ward_weight(const IrradianceRecord& r, const Vec3& x, const Vec3& n) {
    double cos_n = dot(n, r.normal);
    if (!(cos_n > 0) || !is_finite(x) || !is_finite(n)) return 0;  // facing away, or NaN
    double R = r.harmonic_distance;
    if (!(R > 0) || !std::isfinite(R)) return 0;
    double d = length(x - r.position) / R + std::sqrt(std::fmax(0.0, 1 - cos_n));
    if (!std::isfinite(d)) return 0;
    return d > 1e-6 ? 1 / d : 1e6;
}

Vec3 extrapolate(const IrradianceRecord& r, const Vec3& x, const Vec3& n) {
    const Vec3 turn = cross(r.normal, n), shift = x - r.position;
    Vec3 change{};
    double* c[3] = {&change.x, &change.y, &change.z};
    for (size_t k = 0; k < 3; ++k) {
        const double v = dot(turn, r.rotation[k]) + dot(shift, r.translation[k]);
        *c[k] = std::isfinite(v) ? v : 0.0;
    }
    // The first-order change, scaled down (all channels alike: the hue stays) where it would
    // move E's luminance by more than kMaxGradientChange of it.
    const double e = luminance(r.irradiance), moved = std::fabs(luminance(change));
    if (moved > kMaxGradientChange * e) change = change * (kMaxGradientChange * e / moved);
    return {std::fmax(r.irradiance.x + change.x, 0.0), std::fmax(r.irradiance.y + change.y, 0.0),
            std::fmax(r.irradiance.z + change.z, 0.0)};
}

double gradient_limited_radius(const IrradianceRecord& r, double r_min) {
    const double e = luminance(r.irradiance);
    const Vec3 g = r.translation[0] * 0.2126 + r.translation[1] * 0.7152 + r.translation[2] * 0.0722;
    const double slope = length(g);
    if (!(e > 0) || !(slope > 0) || !std::isfinite(slope)) return r.harmonic_distance;
    return std::clamp(e / slope, std::min(r_min, r.harmonic_distance), r.harmonic_distance);
}

bool in_front(const IrradianceRecord& r, const Vec3& x, const Vec3& n) {
    Vec3 avg = n + r.normal;
    return dot(x - r.position, avg) * 0.5 < -0.05 * r.harmonic_distance;
}

}  // namespace crex
