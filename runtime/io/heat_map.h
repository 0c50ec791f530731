/// \file heat_map.h
/// Pictures of per-pixel numbers (rays per pixel, samples, components) for eyes: a
/// perceptually ordered colour ramp (viridis, dark blue to yellow), display values in [0, 1].
#pragma once

#include <string>
#include <vector>

namespace crex {

/// Display RGB, 3 floats per value: 0 maps to the ramp's start, `max` (> 0) to its end.
std::vector<float> heat_colours(const std::vector<double>& values, double max);

/// The same ramp as a CSS gradient from left (0) to right (max), for colour bars on pages.
std::string heat_css_gradient();

}  // namespace crex
