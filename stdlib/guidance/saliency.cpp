// Itti, Koch and Niebur (1998), "A model of saliency-based visual attention", as the thesis
// uses it (3.3): feature maps are centre-surround differences between pyramid levels c and s,
// each normalised by N() (promote maps with few strong peaks), summed into conspicuity maps
// for intensity, colour and orientation, which are normalised and averaged.
#include <algorithm>
#include <array>
#include <cmath>

#include "stdlib/guidance/filters.h"
#include "stdlib/guidance/operators.h"

namespace crex::guidance {
namespace {

// N(): scale to [0, 1], then multiply by (1 - m)^2 where m is the mean of the local maxima
// other than the global one. A map with one peak keeps it; a map with many similar peaks fades.
Raster itti_normalise(Raster m) {
    // Differences below 1e-4 display units are float rounding of flat regions, not features:
    // scaling them up to 1 would make a flat image salient everywhere.
    float mx = 0;
    for (float x : m.v) mx = std::max(mx, std::isfinite(x) ? x : 0.0f);
    if (mx < 1e-4f) return Raster(m.width, m.height, 1);
    normalise_max(m);
    double sum = 0;
    int count = 0;
    for (int y = 0; y < m.height; ++y)
        for (int x = 0; x < m.width; ++x) {
            float c = m.at(x, y);
            if (c <= 0 || c >= 1) continue;
            bool peak = true;
            for (int dy = -1; dy <= 1 && peak; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    if ((dx || dy) && m.clamped(x + dx, y + dy) > c) {
                        peak = false;
                        break;
                    }
            if (peak) sum += c, ++count;
        }
    double mean = count ? sum / count : 0;
    float w = static_cast<float>((1 - mean) * (1 - mean));
    for (float& x : m.v) x *= w;
    return m;
}

void add_to(Raster& acc, const Raster& m) {
    for (size_t i = 0; i < acc.v.size(); ++i) acc.v[i] += m.v[i];
}

// The centre-surround pairs (c, s) of Itti et al. are c in {2,3,4}, s = c + {3,4} on a
// 9-level pyramid; smaller images shift them down so every s exists.
std::vector<std::pair<int, int>> scale_pairs(int levels) {
    int shift = std::max(0, 9 - levels);
    std::vector<std::pair<int, int>> pairs;
    for (int c = 2; c <= 4; ++c)
        for (int d = 3; d <= 4; ++d) {
            int cc = c - shift, ss = c + d - shift;
            if (cc >= 0 && ss < levels && ss > cc) pairs.push_back({cc, ss});
        }
    if (pairs.empty() && levels >= 2) pairs.push_back({0, levels - 1});
    return pairs;
}

// Sum over the pairs of N(|F(c) - F(s)|), at full resolution. `signed_pair`: F is (A - B) at
// the centre against (B - A) in the surround, the opponency of Itti's RG and BY maps.
Raster centre_surround(const std::vector<Raster>& pyr, const std::vector<std::pair<int, int>>& pairs, int w, int h,
                       const std::vector<Raster>* opponent = nullptr) {
    Raster acc(w, h, 1);
    for (auto [c, s] : pairs) {
        Raster centre = resize_bilinear(pyr[static_cast<size_t>(c)], w, h);
        Raster surround = resize_bilinear(opponent ? (*opponent)[static_cast<size_t>(s)] : pyr[static_cast<size_t>(s)], w, h);
        Raster diff(w, h, 1);
        for (size_t i = 0; i < diff.v.size(); ++i)
            diff.v[i] = opponent ? std::fabs(centre.v[i] + surround.v[i]) : std::fabs(centre.v[i] - surround.v[i]);
        add_to(acc, itti_normalise(std::move(diff)));
    }
    return acc;
}

}  // namespace

Raster saliency(const Raster& rgb) {
    const int w = rgb.width, h = rgb.height;
    Raster intensity(w, h), rg(w, h), by(w, h);
    for (size_t i = 0; i < intensity.pixels(); ++i) {
        const float* p = &rgb.v[i * static_cast<size_t>(rgb.channels)];
        float r = p[0], g = rgb.channels > 1 ? p[1] : r, b = rgb.channels > 2 ? p[2] : r;
        float in = (r + g + b) / 3;
        intensity.v[i] = in;
        // Broadly tuned colour channels; hue is meaningless in the dark (Itti: I < max/10).
        float R = r - (g + b) / 2, G = g - (r + b) / 2, B = b - (r + g) / 2, Y = (r + g) / 2 - std::fabs(r - g) / 2 - b;
        float norm = in > 0.1f ? 1.0f / in : 0.0f;
        rg.v[i] = (std::max(R, 0.0f) - std::max(G, 0.0f)) * norm;
        by.v[i] = (std::max(B, 0.0f) - std::max(Y, 0.0f)) * norm;
    }
    auto pi = gaussian_pyramid(intensity, 9);
    auto prg = gaussian_pyramid(rg, 9), pby = gaussian_pyramid(by, 9);
    auto pairs = scale_pairs(static_cast<int>(pi.size()));
    if (pairs.empty()) return Raster(w, h, 1);  // a 1-pixel image has no surround

    Raster ibar = centre_surround(pi, pairs, w, h);
    // RG(c,s) = |(R-G)(c) - (G-R)(s)|: the opponent pyramid is the negated one.
    auto negate = [](std::vector<Raster> p) {
        for (auto& l : p)
            for (float& x : l.v) x = -x;
        return p;
    };
    std::vector<Raster> nrg = negate(prg), nby = negate(pby);
    Raster cbar = centre_surround(prg, pairs, w, h, &nrg);
    add_to(cbar, centre_surround(pby, pairs, w, h, &nby));
    // Orientation: oriented derivative energy at 0, 45, 90 and 135 degrees on every level.
    Raster obar(w, h, 1);
    for (int theta = 0; theta < 4; ++theta) {
        std::vector<Raster> po;
        for (const auto& level : pi) {
            Raster gx, gy;
            sobel(level, gx, gy);
            Raster o(level.width, level.height, 1);
            for (size_t i = 0; i < o.v.size(); ++i) {
                float a = gx.v[i], b = gy.v[i];
                o.v[i] = std::fabs(theta == 0 ? a : theta == 1 ? (a + b) * 0.70710678f : theta == 2 ? b : (a - b) * 0.70710678f);
            }
            po.push_back(std::move(o));
        }
        add_to(obar, itti_normalise(centre_surround(po, pairs, w, h)));
    }
    Raster s(w, h, 1);
    add_to(s, itti_normalise(std::move(ibar)));
    add_to(s, itti_normalise(std::move(cbar)));
    add_to(s, itti_normalise(std::move(obar)));
    normalise_max(s);
    return s;
}

}  // namespace crex::guidance
