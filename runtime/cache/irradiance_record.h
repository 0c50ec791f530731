/// \file irradiance_record.h
/// One record of the Ward irradiance cache (Ward, Rubinstein, Clear 1988; gradients: Ward and
/// Heckbert 1992): plain data, so records can be written to a file and shipped between
/// processes. Positions are in the renderer's local (recentred) coordinates. What a lookup
/// computes for each record it meets (its weight, its extrapolation, Ward's in-front test) is
/// inline, so the lookup's loop has it in place.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>

#include "runtime/base/vec3.h"

namespace crex {

struct IrradianceRecord {
    Vec3 position;
    Vec3 normal;                      ///< unit
    Vec3 irradiance;                  ///< E, RGB
    double harmonic_distance = 0;     ///< R_i, in [r_min, r_max] and gradient-limited: never 0
    std::array<Vec3, 3> rotation{};   ///< rotational gradient of E, per channel (R, G, B)
    std::array<Vec3, 3> translation{};///< translational gradient of E, per channel
    float quality = 1;                ///< the accuracy `aa` of the pixel that asked for it
    uint16_t level = 0;               ///< ambient bounce: 0 for records camera paths use
    /// The level-0 hemisphere rays (ad) of the query that made it (`vary ic_rays`; level k
    /// traced ad / 2^k); 0: the cache's own setting.
    uint16_t divisions = 0;
};

/// Ward's weight of record `r` at point `x` with unit normal `n`:
///   w = 1 / (|x - x_i| / R_i + sqrt(1 - n . n_i)),
/// guarded: 0 for records facing away (n . n_i <= 0) or non-finite inputs, and capped at
/// 1e6 where the denominator vanishes (x on the record, same normal).
inline double ward_weight(const IrradianceRecord& r, const Vec3& x, const Vec3& n) {
    double cos_n = dot(n, r.normal);
    if (!(cos_n > 0) || !is_finite(x) || !is_finite(n)) return 0;  // facing away, or NaN
    double R = r.harmonic_distance;
    if (!(R > 0) || !std::isfinite(R)) return 0;
    double d = length(x - r.position) / R + std::sqrt(max_of(0.0, 1 - cos_n));
    if (!std::isfinite(d)) return 0;
    return d > 1e-6 ? 1 / d : 1e6;
}

/// How far a record's gradients may move its E's luminance when extrapolated, as a share of
/// it. Ward and Heckbert's gradients are estimated from the hemisphere's samples and are least
/// reliable next to close geometry, where they are also largest: unbounded, records near the
/// corridor's wall-floor and wall-ceiling corners extrapolated to dark half-discs (RMSE on
/// those corners 0.0080, bounded 0.0069, against a 256-spp reference; demo corridor, 2 seeds).
inline constexpr double kMaxGradientChange = 0.25;

/// E of `r` extrapolated to (x, n) with its gradients, the change bounded by
/// kMaxGradientChange of E's luminance, then clamped at 0 per channel; a non-finite gradient
/// term is left out.
inline Vec3 extrapolate(const IrradianceRecord& r, const Vec3& x, const Vec3& n) {
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
    return {max_of(r.irradiance.x + change.x, 0.0), max_of(r.irradiance.y + change.y, 0.0), max_of(r.irradiance.z + change.z, 0.0)};
}

/// R_i limited by the record's own translational gradient (the gradient limit of Krivanek et
/// al. 2006): within R_i the gradient may change E's luminance by at most E's luminance, so a
/// coarse accuracy (`vary ic_radius 0.75 ..`) cannot extrapolate a record across a strong
/// gradient into blotches; never below `r_min`, never above the record's own R_i.
double gradient_limited_radius(const IrradianceRecord& r, double r_min);

/// Is `r` "in front" of x (Ward's test: records ahead of the surface along the averaged normal
/// are not used, they see a different neighbourhood)?
inline bool in_front(const IrradianceRecord& r, const Vec3& x, const Vec3& n) {
    Vec3 avg = n + r.normal;
    return dot(x - r.position, avg) * 0.5 < -0.05 * r.harmonic_distance;
}

}  // namespace crex
