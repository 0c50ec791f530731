#include "runtime/render/medium.h"

#include <algorithm>

namespace crex {

std::optional<MediumModel> medium_of(const Scene& scene, const Vec3& origin_offset) {
    if (!scene.medium || !(max_component(scene.medium->extinction) > 0)) return std::nullopt;
    MediumModel m;
    m.sigma_t = scene.medium->extinction;
    m.sigma_s = scene.medium->extinction * scene.medium->albedo;
    m.g = std::clamp(scene.medium->eccentricity, -0.999, 0.999);
    m.bounded = scene.medium->bounded;
    m.lo = scene.medium->box_min - origin_offset;
    m.hi = scene.medium->box_max - origin_offset;
    return m;
}

bool MediumModel::inside(const Vec3& origin, const Vec3& dir, double tmax, double& t0, double& t1) const {
    t0 = 0, t1 = tmax;
    if (!bounded) return tmax > 0;
    // The slabs of the box, axis by axis (a ray parallel to a slab is inside it or never).
    const double o[3] = {origin.x, origin.y, origin.z}, d[3] = {dir.x, dir.y, dir.z};
    const double a[3] = {lo.x, lo.y, lo.z}, b[3] = {hi.x, hi.y, hi.z};
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0) {
            if (o[k] < a[k] || o[k] > b[k]) return false;
            continue;
        }
        double near = (a[k] - o[k]) / d[k], far = (b[k] - o[k]) / d[k];
        if (near > far) std::swap(near, far);
        t0 = std::max(t0, near), t1 = std::min(t1, far);
    }
    return t1 > t0;
}

DistanceSample sample_equiangular(const Vec3& origin, const Vec3& dir, double tmax, const Vec3& light, double u, double tmin) {
    const double delta = dot(light - origin, dir);  // the foot of the light's perpendicular
    const Vec3 foot = origin + dir * delta;
    const double d = length(light - foot);
    const double scale = std::max({std::fabs(delta), length(light - origin), 1e-30});
    if (!(d > 1e-9 * scale)) return {};
    const double theta_a = std::atan2(tmin - delta, d);
    const double theta_b = std::isfinite(tmax) ? std::atan2(tmax - delta, d) : kPi / 2;
    if (!(theta_b > theta_a)) return {};
    const double theta = theta_a + u * (theta_b - theta_a);
    DistanceSample s;
    s.t = std::clamp(delta + d * std::tan(theta), tmin, std::isfinite(tmax) ? tmax : 1e300);
    const double x = s.t - delta;
    s.pdf = d / ((theta_b - theta_a) * (d * d + x * x));
    return s;
}

}  // namespace crex
