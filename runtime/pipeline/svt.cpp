#include "runtime/pipeline/svt.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace crex {

namespace {

using pipeline::ModulationFunction;
using ModulationFn = double (*)(double);

// One implementation per ModulationFunction, in enum order; a missing row fails to compile.
constexpr std::array<ModulationFn, pipeline::kModulationFunctionCount> kModulations = {
    [](double m) { return m; },                    // linear
    [](double m) { return m * m; },                // quadratic
    [](double m) { return std::sqrt(m); },         // sqrt
    [](double m) { return m >= 0.5 ? 1.0 : 0.0; },  // step
};
static_assert(std::ranges::none_of(kModulations, [](ModulationFn f) { return f == nullptr; }),
              "every pipeline::ModulationFunction needs an implementation in kModulations");

}  // namespace

double modulate(ModulationFunction function, double m) {
    m = std::isnan(m) ? 0.0 : std::clamp(m, 0.0, 1.0);
    return kModulations[static_cast<size_t>(function)](m);
}

std::optional<double> modulate(const std::string& function, double m) {
    if (function.empty()) return modulate(ModulationFunction::kLinear, m);
    auto f = pipeline::modulation_function_from_name(function);
    if (!f) return std::nullopt;
    return modulate(*f, m);
}

std::vector<double> variable_values(double from, double to, ModulationFunction function, const std::vector<float>& map,
                                    bool integer) {
    std::vector<double> out(map.size());
    for (size_t i = 0; i < map.size(); ++i) {
        double v = from + (to - from) * modulate(function, map[i]);
        out[i] = integer ? std::round(v) : v;
    }
    return out;
}

}  // namespace crex
