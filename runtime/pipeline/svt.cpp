#include "runtime/pipeline/svt.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace crex {

std::optional<double> modulate(const std::string& function, double m) {
    m = std::isnan(m) ? 0.0 : std::clamp(m, 0.0, 1.0);
    if (function.empty() || function == "linear") return m;
    if (function == "quadratic") return m * m;
    if (function == "sqrt") return std::sqrt(m);
    if (function == "step") return m >= 0.5 ? 1.0 : 0.0;
    return std::nullopt;
}

std::vector<double> variable_values(double from, double to, const std::string& function, const std::vector<float>& map,
                                    bool integer) {
    std::vector<double> out(map.size());
    for (size_t i = 0; i < map.size(); ++i) {
        double f = modulate(function, map[i]).value_or(map[i]);
        double v = from + (to - from) * f;
        out[i] = integer ? std::round(v) : v;
    }
    return out;
}

std::optional<double> plan_number(const std::string& text) {
    try {
        size_t used = 0;
        double v = std::stod(text, &used);
        std::string unit = text.substr(used);
        unit.erase(0, unit.find_first_not_of(' '));
        if (unit == "deg") return v * std::numbers::pi / 180;
        if (unit.empty() || unit == "rad") return v;
        if (unit == "%") return v / 100;
        return std::nullopt;
    } catch (...) {
        return std::nullopt;
    }
}

}  // namespace crex
