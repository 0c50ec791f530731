/// \file medium.h
/// A homogeneous participating medium filling the scene (thesis chapter 8, "Mist Cornell"):
/// every ray segment is attenuated by its transmittance exp(-sigma_t d) (Beer-Lambert), and
/// camera rays gather light scattered once toward the eye from the scene's lights (single
/// scattering), with distances along the ray drawn by equiangular sampling (Kulla & Fajardo
/// 2012: the pdf follows 1/r^2 of the light point, so a lamp inside the mist is not noise).
#pragma once

#include <cmath>
#include <optional>

#include "runtime/base/sampling.h"
#include "runtime/base/vec3.h"
#include "runtime/scene/scene.h"

namespace crex {

struct MediumModel {
    Vec3 sigma_t;  ///< extinction per scene unit
    Vec3 sigma_s;  ///< scattering: albedo x extinction
    double g = 0;  ///< Henyey-Greenstein eccentricity
    bool bounded = false;  ///< only inside [lo, hi] (local coordinates)
    Vec3 lo, hi;

    /// exp(-sigma_t d) per channel over a length d inside the medium; an infinite d gives 0
    /// where sigma_t > 0 (a ray leaving an unbounded medium brings nothing back).
    Vec3 transmittance(double d) const {
        auto one = [d](double s) { return s > 0 ? (std::isfinite(d) ? std::exp(-s * d) : 0.0) : 1.0; };
        return {one(sigma_t.x), one(sigma_t.y), one(sigma_t.z)};
    }
    /// The part [t0, t1] of origin + t dir, t in [0, tmax], inside the medium; false if none.
    bool inside(const Vec3& origin, const Vec3& dir, double tmax, double& t0, double& t1) const;
    /// Along origin + t dir, t in [0, tmax]: the transmittance of its part inside the medium.
    Vec3 transmittance(const Vec3& origin, const Vec3& dir, double tmax) const {
        if (!bounded) return transmittance(tmax);
        double t0, t1;
        return inside(origin, dir, tmax, t0, t1) ? transmittance(t1 - t0) : Vec3{1, 1, 1};
    }
};

/// The scene's medium, if it has one that does anything; a box in local coordinates (the
/// scene's less `origin_offset`).
std::optional<MediumModel> medium_of(const Scene& scene, const Vec3& origin_offset = {});

/// Henyey-Greenstein phase function (per steradian) of the angle between the light's
/// direction of travel and the scattered light's: cos_theta = dot(travel_in, travel_out).
inline double henyey_greenstein(double cos_theta, double g) {
    const double denom = 1 + g * g - 2 * g * cos_theta;
    return (1 - g * g) / (4 * kPi * denom * std::sqrt(denom));
}

struct DistanceSample {
    double t = 0;    ///< along the ray, in [0, tmax]
    double pdf = 0;  ///< per unit length
};

/// Equiangular sampling of t in [tmin, tmax] (tmax may be infinite) along origin + t dir (unit)
/// toward `light`: t = Delta + D tan(theta), theta uniform between the angles of the
/// segment's ends as seen from the light. pdf = D / ((theta_b - theta_a)(D^2 + (t - Delta)^2)).
/// Returns pdf 0 when the light lies on the ray's line (D below 1e-9 of the distance scale).
DistanceSample sample_equiangular(const Vec3& origin, const Vec3& dir, double tmax, const Vec3& light, double u, double tmin = 0);

}  // namespace crex
