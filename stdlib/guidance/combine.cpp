// Maps made from maps: importance (thesis 4.8) and the small utilities.
#include <algorithm>
#include <cmath>

#include "stdlib/guidance/operators.h"

namespace crex::guidance {

Raster importance(const std::vector<const Raster*>& maps, const std::vector<double>& weights, const std::string& op) {
    if (maps.empty()) return {};
    Raster out(maps[0]->width, maps[0]->height, 1, op == "*" ? 1.0f : 0.0f);
    for (size_t k = 0; k < maps.size(); ++k) {
        float w = static_cast<float>(weights[k]);
        for (size_t i = 0; i < out.v.size(); ++i) {
            float x = w * maps[k]->v[i];
            if (op == "+") out.v[i] += x;
            else if (op == "max") out.v[i] = std::max(out.v[i], x);
            else out.v[i] *= x;
        }
    }
    clamp01(out);
    return out;
}

Raster constant_map(int width, int height, double value) {
    Raster m(width, height, 1, static_cast<float>(value));
    clamp01(m);
    return m;
}

Raster threshold(const Raster& map, double at) {
    Raster m(map.width, map.height, 1);
    for (size_t i = 0; i < m.v.size(); ++i) m.v[i] = map.v[i] >= at ? 1.0f : 0.0f;
    return m;
}

}  // namespace crex::guidance
