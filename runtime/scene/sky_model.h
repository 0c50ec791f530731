/// \file sky_model.h
/// The brightness of RADIANCE's standard skies in a direction (what gensky's skybright.cal
/// computes): the CIE clear, intermediate and overcast skies and a uniform one above the
/// horizon, blended smoothly into the ground's brightness below it. Also the formulas gensky
/// uses to set them up from a sun position: the zenith brightness and the normalisation that
/// divides the clear and intermediate skies.
#pragma once

#include "runtime/scene/scene.h"

namespace crex {

/// Relative brightness of `sky` towards unit direction `d` (z up), times its zenith value.
double sky_brightness(const SkyModel& sky, const Vec3& d);

/// The CIE distributions' shape alone (zenith brightness 1, normalisation 1, no ground),
/// above the horizon: what the normalisation integrates.
double cie_sky_shape(SkyModel::Type type, const Vec3& sun, const Vec3& d);

/// gensky's normalisation of the clear and intermediate skies for a sun direction: its fit of
/// their shape at the zenith, which divides them so the zenith has the brightness given. The
/// overcast and uniform skies need none (1).
double sky_normalization(SkyModel::Type type, const Vec3& sun);

/// Irradiance of a horizontal surface facing up under `sky` alone (ground excluded), by
/// numerical integration of sky_brightness: what the published formulas are checked against.
double sky_horizontal_irradiance(const SkyModel& sky);

}  // namespace crex
