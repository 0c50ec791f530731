#include "runtime/cache/irradiance_record.h"

#include <algorithm>
#include <cmath>

namespace crex {

double gradient_limited_radius(const IrradianceRecord& r, double r_min) {
    const double e = luminance(r.irradiance);
    const Vec3 g = r.translation[0] * 0.2126 + r.translation[1] * 0.7152 + r.translation[2] * 0.0722;
    const double slope = length(g);
    if (!(e > 0) || !(slope > 0) || !std::isfinite(slope)) return r.harmonic_distance;
    return std::clamp(e / slope, std::min(r_min, r.harmonic_distance), r.harmonic_distance);
}

}  // namespace crex
