#include "runtime/io/heat_map.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

namespace crex {

namespace {
// Viridis at nine evenly spaced stops (matplotlib's table, sRGB display values).
constexpr std::array<std::array<float, 3>, 9> ramp = {{{0.267f, 0.005f, 0.329f}, {0.278f, 0.175f, 0.483f},
                                                       {0.229f, 0.322f, 0.546f}, {0.173f, 0.449f, 0.558f},
                                                       {0.128f, 0.567f, 0.551f}, {0.153f, 0.680f, 0.504f},
                                                       {0.369f, 0.789f, 0.383f}, {0.678f, 0.864f, 0.190f},
                                                       {0.993f, 0.906f, 0.144f}}};
}  // namespace

std::string heat_css_gradient() {
    std::string css = "linear-gradient(to right";
    for (size_t k = 0; k < ramp.size(); ++k)
        css += fmt::format(", rgb({:.0f},{:.0f},{:.0f}) {:.1f}%", 255 * ramp[k][0], 255 * ramp[k][1], 255 * ramp[k][2],
                           100.0 * static_cast<double>(k) / static_cast<double>(ramp.size() - 1));
    return css + ")";
}

std::vector<float> heat_colours(const std::vector<double>& values, double max) {
    std::vector<float> out(3 * values.size());
    for (size_t i = 0; i < values.size(); ++i) {
        double t = max > 0 && std::isfinite(values[i]) ? std::clamp(values[i] / max, 0.0, 1.0) : 0.0;
        double x = t * (ramp.size() - 1);
        size_t k = std::min(static_cast<size_t>(x), ramp.size() - 2);
        float f = static_cast<float>(x - static_cast<double>(k));
        for (size_t c = 0; c < 3; ++c) out[3 * i + c] = ramp[k][c] * (1 - f) + ramp[k + 1][c] * f;
    }
    return out;
}

}  // namespace crex
