/// \file svt.h
/// The selective variable table at run time: `vary V A .. B by MAP [using F]` gives pixel p
/// the value A + (B - A) f(MAP(p)), rounded for integer variables (spec/pipeline.md §1).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace crex {

/// The modulation functions `using` may name; linear when none is given.
inline constexpr const char* kModulationFunctions[] = {"linear", "quadratic", "sqrt", "step"};

/// f(m) for m in [0, 1]; std::nullopt for an unknown function name.
std::optional<double> modulate(const std::string& function, double m);

/// The per-pixel values of one variable. `map` is in [0, 1] (NaN counts as 0).
std::vector<double> variable_values(double from, double to, const std::string& function, const std::vector<float>& map,
                                    bool integer);

/// A plan's number text ("16", "0.5", "2 deg") as a number (degrees become radians); nullopt
/// when it is not one.
std::optional<double> plan_number(const std::string& text);

}  // namespace crex
