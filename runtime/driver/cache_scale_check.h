/// \file cache_scale_check.h
/// Whether the irradiance cache's smallest record is coarse beside what the camera sees. Its
/// radii follow the whole scene's extent over --ar (RADIANCE's -ar), which counts every shape,
/// seen or not: a set piece beside a vast ground gets records wider than itself, and its
/// indirect light comes out in blotches, with no error anywhere else to say so.
#pragma once

#include <optional>

#include "base/diagnostic.h"
#include "runtime/cache/irradiance_cache_file.h"

namespace crex {

class RenderScene;

/// W407 when the cache's smallest record (`cache.min_radius`) is wider than 5 % of the distance
/// within which nine in ten of the surfaces seen lie (camera rays through a grid of the
/// `width` x `height` frame's pixels); nothing otherwise, or when the camera sees too little.
std::optional<Diagnostic> coarse_cache_warning(const RenderScene& scene, const IcFileSettings& cache, int width, int height);

}  // namespace crex
