// Maps made from maps: importance (thesis 4.8) and the small utilities.
#include <algorithm>
#include <cmath>

#include "stdlib/guidance/operators.h"

namespace crex::guidance {

Raster importance(const std::vector<const Raster*>& maps, const std::vector<double>& weights, const std::string& op) {
    if (maps.empty()) return {};
    Raster out(maps[0]->width, maps[0]->height, 1, op == "*" ? 1.0f : 0.0f);
    // A sum's weights are shared among the maps that hold something: a map 0 everywhere (a task
    // map with nothing tagged, or its object off screen) hands its weight to the others, so
    // `importance(task 0.5, sal 0.5, op "+")` is saliency on a scene without a task, not half
    // of it (cbtcr on the Cornell box ran none of D, R, M: issue 34).
    double scale = 1;
    if (op == "+") {
        double all = 0, held = 0;
        for (size_t k = 0; k < maps.size(); ++k) {
            all += weights[k];
            if (std::any_of(maps[k]->v.begin(), maps[k]->v.end(), [](float v) { return v > 0; })) held += weights[k];
        }
        if (held > 0 && held < all) scale = all / held;
    }
    for (size_t k = 0; k < maps.size(); ++k) {
        float w = static_cast<float>(weights[k] * scale);
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
