#include "runtime/api/frame_reuse.h"

#include <algorithm>

namespace crex {
namespace {

bool view_independent(const Material& m) {
    switch (m.type) {
        case MaterialType::kGlass:
        case MaterialType::kDielectric:
        case MaterialType::kMirror:
            return false;
        case MaterialType::kLight:
        case MaterialType::kGlow:
        case MaterialType::kIllum:
            return !m.spot.has_value();
        case MaterialType::kPlastic:
        case MaterialType::kMetal:
        case MaterialType::kTrans: {
            const bool specular = m.specularity > 0 || m.textures.specularity || m.metallic > 0 || m.textures.metallic;
            const bool ideal = specular && m.roughness <= 0 && !m.textures.roughness;
            const bool see_through = m.type == MaterialType::kTrans && m.transmissivity > 0 && m.transmitted_specular > 0;
            return !ideal && !see_through;
        }
        default:
            return true;
    }
}

}  // namespace

std::vector<char> shapes_that_inherit(const Scene& scene) {
    std::vector<char> out(scene.shapes.size(), 0);
    for (size_t i = 0; i < scene.shapes.size(); ++i) {
        const Material* m = scene.find_material(scene.shapes[i].material);
        out[i] = m && view_independent(*m) ? 1 : 0;
    }
    return out;
}

PixelHistory inherited_history(const PixelHistory& previous, const std::vector<PixelTaps>& from, const std::vector<int32_t>& shape,
                               const std::vector<char>& inherits, float frames) {
    const size_t n = from.size();
    PixelHistory out;
    out.rgb.assign(3 * n, 0.0f);
    out.weight.assign(n, 0.0f);
    out.frames = frames;
    if (previous.weight.size() != n || previous.rgb.size() != 3 * n || shape.size() != n) return out;
    for (size_t p = 0; p < n; ++p) {
        const int32_t s = shape[p];
        if (s < 0 || static_cast<size_t>(s) >= inherits.size() || !inherits[static_cast<size_t>(s)]) continue;
        // Taps whose pixel had samples of its own; their bilinear weights made to add up to 1.
        double total = 0, weight = 0, rgb[3] = {0, 0, 0};
        for (size_t t = 0; t < 4; ++t) {
            const int32_t q = from[p].pixel[t];
            if (q < 0 || static_cast<size_t>(q) >= n || !(previous.weight[static_cast<size_t>(q)] > 0)) continue;
            const double w = from[p].weight[t];
            const size_t k = static_cast<size_t>(q);
            total += w, weight += w * previous.weight[k];
            for (size_t c = 0; c < 3; ++c) rgb[c] += w * previous.rgb[3 * k + c];
        }
        if (!(total > 0)) continue;
        out.weight[p] = static_cast<float>(weight / total);
        for (size_t c = 0; c < 3; ++c) out.rgb[3 * p + c] = static_cast<float>(rgb[c] / total);
    }
    return out;
}

std::pair<double, double> inherited_share(const PixelHistory& history) {
    size_t inherited = 0;
    double samples = 0;
    for (size_t p = 0; p < history.weight.size(); ++p) {
        const float w = history.weight[p];
        if (!(w > 0)) continue;
        ++inherited;
        samples += history.counted(p, own_samples(w, w, history.frames));  // the fewest own that carry it
    }
    return {static_cast<double>(inherited) / static_cast<double>(std::max<size_t>(1, history.weight.size())),
            inherited ? samples / static_cast<double>(inherited) : 0.0};
}

}  // namespace crex
