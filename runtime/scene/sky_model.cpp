#include "runtime/scene/sky_model.h"

#include "runtime/base/sampling.h"
#include <algorithm>
#include <cmath>

namespace crex {
namespace {


double safe_acos(double x) { return std::acos(std::clamp(x, -1.0, 1.0)); }

}  // namespace

double cie_sky_shape(SkyModel::Type type, const Vec3& sun, const Vec3& d) {
    const double cos_gamma = std::clamp(dot(d, sun), -1.0, 1.0);
    const double gamma = safe_acos(cos_gamma);  // from the sun to d
    const double zt = safe_acos(sun.z);         // from the zenith to the sun
    const double eta = safe_acos(d.z);          // from the zenith to d
    switch (type) {
    case SkyModel::Type::kClear:
        // CIE clear sky: scattering indicatrix f(gamma) times the gradation 1 - exp(-0.32 / cos).
        return (0.91 + 10 * std::exp(-3 * gamma) + 0.45 * cos_gamma * cos_gamma) *
               (d.z > 0.01 ? 1.0 - std::exp(-0.32 / d.z) : 1.0);
    case SkyModel::Type::kOvercast: return (1 + 2 * d.z) / 3;  // CIE overcast (Moon and Spencer)
    case SkyModel::Type::kUniform: return 1;
    case SkyModel::Type::kIntermediate:
        // Matsuura's intermediate sky, as RADIANCE's gensky writes it.
        return ((1.35 * std::sin(5.631 - 3.59 * eta) + 3.12) * std::sin(4.396 - 2.6 * zt) + 6.37 - eta) / 2.326 *
               std::exp(gamma * -0.563 * ((2.629 - eta) * (1.562 - zt) + 0.812));
    }
    return 0;
}

double sky_brightness(const SkyModel& sky, const Vec3& d) {
    double above = sky.zenith * cie_sky_shape(sky.type, sky.sun, d);
    if (sky.type == SkyModel::Type::kClear || sky.type == SkyModel::Type::kIntermediate)
        above /= sky.normalization > 0 ? sky.normalization : 1.0;
    // Blend into the ground's brightness around the horizon, with weights (z + 1.01)^(+-10).
    const double a = std::pow(d.z + 1.01, 10.0), b = std::pow(d.z + 1.01, -10.0);
    return (a * above + b * sky.ground) / (a + b);
}

double sky_normalization(SkyModel::Type type, const Vec3& sun) {
    // gensky's fits of the shape at the zenith (its F2), by which it divides the clear and
    // intermediate skies so that their zenith brightness is the one given.
    const double altitude = std::asin(std::clamp(sun.z, -1.0, 1.0)), zt = kPi / 2 - altitude;
    if (type == SkyModel::Type::kClear) return 0.274 * (0.91 + 10.0 * std::exp(-3.0 * zt) + 0.45 * sun.z * sun.z);
    if (type == SkyModel::Type::kIntermediate)
        return (2.739 + 0.9891 * std::sin(0.3119 + 2.6 * altitude)) * std::exp(-zt * (0.4441 + 1.48 * altitude));
    return 1;
}

double sky_horizontal_irradiance(const SkyModel& sky) {
    // Midpoint rule in (cos theta, phi): cells of equal solid angle; the shape is smooth
    // except the clear sky's circumsolar peak, which 512 x 1024 cells resolve to ~1e-4.
    const int nz = 512, nphi = 1024;
    double sum = 0;
    for (int i = 0; i < nz; ++i) {
        const double z = (i + 0.5) / nz, s = std::sqrt(std::max(0.0, 1 - z * z));
        double ring = 0;
        for (int j = 0; j < nphi; ++j) {
            const double phi = 2 * kPi * (j + 0.5) / nphi;
            const Vec3 d{s * std::cos(phi), s * std::sin(phi), z};
            // The sky alone: its value above the horizon, without the blend into the ground.
            double v = sky.zenith * cie_sky_shape(sky.type, sky.sun, d);
            if (sky.type == SkyModel::Type::kClear || sky.type == SkyModel::Type::kIntermediate)
                v /= sky.normalization > 0 ? sky.normalization : 1.0;
            ring += v;
        }
        sum += ring * z;
    }
    return sum * (2 * kPi / nphi) * (1.0 / nz);
}

}  // namespace crex
