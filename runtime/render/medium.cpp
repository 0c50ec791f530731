#include "runtime/render/medium.h"

#include <algorithm>

namespace crex {

std::optional<MediumModel> medium_of(const Scene& scene) {
    if (!scene.medium || !(max_component(scene.medium->extinction) > 0)) return std::nullopt;
    MediumModel m;
    m.sigma_t = scene.medium->extinction;
    m.sigma_s = scene.medium->extinction * scene.medium->albedo;
    m.g = std::clamp(scene.medium->eccentricity, -0.999, 0.999);
    return m;
}

DistanceSample sample_equiangular(const Vec3& origin, const Vec3& dir, double tmax, const Vec3& light, double u) {
    const double delta = dot(light - origin, dir);  // the foot of the light's perpendicular
    const Vec3 foot = origin + dir * delta;
    const double d = length(light - foot);
    const double scale = std::max({std::fabs(delta), length(light - origin), 1e-30});
    if (!(d > 1e-9 * scale)) return {};
    const double theta_a = std::atan2(0 - delta, d);
    const double theta_b = std::isfinite(tmax) ? std::atan2(tmax - delta, d) : kPi / 2;
    if (!(theta_b > theta_a)) return {};
    const double theta = theta_a + u * (theta_b - theta_a);
    DistanceSample s;
    s.t = std::clamp(delta + d * std::tan(theta), 0.0, std::isfinite(tmax) ? tmax : 1e300);
    const double x = s.t - delta;
    s.pdf = d / ((theta_b - theta_a) * (d * d + x * x));
    return s;
}

}  // namespace crex
