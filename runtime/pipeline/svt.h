/// \file svt.h
/// The selective variable table at run time: `vary V A .. B by MAP [using F]` gives pixel p
/// the value A + (B - A) f(MAP(p)), rounded for integer variables (spec/pipeline.md §1). The
/// modulation functions f are bound here, one per pipeline::ModulationFunction.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "compiler/pipeline/registry.h"

namespace crex {

/// f(m), m clamped to [0, 1] (NaN counts as 0).
double modulate(pipeline::ModulationFunction function, double m);
/// The same by name ("" is linear); std::nullopt for a name registry.h does not know.
std::optional<double> modulate(const std::string& function, double m);

/// The per-pixel values of one variable. `map` is in [0, 1] (NaN counts as 0).
std::vector<double> variable_values(double from, double to, pipeline::ModulationFunction function, const std::vector<float>& map,
                                    bool integer);

}  // namespace crex
