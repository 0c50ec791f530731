// The exact Euclidean distance transform of a binary image (Felzenszwalb and Huttenlocher
// 2012, in the two-phase form of Meijster et al. 2000). Phase one, the distance to the nearest
// feature in the same column, is two scans over whole rows (for a binary image the 1-D
// transform of a column is just that), so the image is only ever read row by row; phase two
// is the lower envelope of parabolas along each row.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "stdlib/guidance/filters.h"

namespace crex::guidance {
namespace {

// One row of phase two: d[q] = min_p (q - p)^2 + f[p], f infinite where the column has no
// feature (at least one is finite). v and z hold the envelope (parabola apexes, the
// boundaries between them).
void distance_1d(const std::vector<double>& f, std::vector<double>& d, std::vector<int>& v, std::vector<double>& z) {
    const int n = static_cast<int>(f.size());
    const double inf = std::numeric_limits<double>::infinity();
    int k = 0;
    v[0] = 0;
    z[0] = -inf;
    z[1] = inf;
    for (int q = 1; q < n; ++q) {
        if (!std::isfinite(f[static_cast<size_t>(q)])) continue;
        if (!std::isfinite(f[static_cast<size_t>(v[static_cast<size_t>(k)])])) {  // the envelope was empty
            v[static_cast<size_t>(k)] = q;
            continue;
        }
        double s;
        for (;;) {
            int p = v[static_cast<size_t>(k)];
            s = ((f[static_cast<size_t>(q)] + q * q) - (f[static_cast<size_t>(p)] + p * p)) / (2.0 * (q - p));
            if (s <= z[static_cast<size_t>(k)] && k > 0) --k;
            else break;
        }
        ++k;
        v[static_cast<size_t>(k)] = q;
        z[static_cast<size_t>(k)] = s;
        z[static_cast<size_t>(k) + 1] = inf;
    }
    k = 0;  // every parabola left in the envelope has a finite apex
    for (int q = 0; q < n; ++q) {
        while (z[static_cast<size_t>(k) + 1] < q) ++k;
        int p = v[static_cast<size_t>(k)];
        d[static_cast<size_t>(q)] = (q - p) * (q - p) + f[static_cast<size_t>(p)];
    }
}

}  // namespace

void squared_distance_rows(const std::vector<bool>& feature, int width, int height, double reach,
                           const std::function<void(int, const double*)>& row) {
    if (width <= 0 || height <= 0) return;
    const size_t w = static_cast<size_t>(width), h = static_cast<size_t>(height);
    // Phase one: g = rows to the nearest feature in the column. A column whose feature is
    // `reach` rows away or more cannot give any pixel a distance below reach: `none`.
    const int32_t none = reach < std::numeric_limits<int32_t>::max() - 1 ? static_cast<int32_t>(std::ceil(std::max(reach, 0.0)))
                                                                         : std::numeric_limits<int32_t>::max() - 1;
    std::vector<int32_t> g(w * h);
    for (size_t x = 0; x < w; ++x) g[x] = feature[x] ? 0 : none;
    for (size_t y = 1; y < h; ++y) {
        const int32_t* above = &g[(y - 1) * w];
        int32_t* here = &g[y * w];
        for (size_t x = 0; x < w; ++x) here[x] = feature[y * w + x] ? 0 : std::min(above[x] + 1, none);
    }
    for (size_t y = h - 1; y-- > 0;) {
        const int32_t* below = &g[(y + 1) * w];
        int32_t* here = &g[y * w];
        for (size_t x = 0; x < w; ++x) here[x] = std::min(here[x], std::min(below[x] + 1, none));
    }
    // Phase two along each row.
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<double> f(w), d(w), z(w + 1);
    std::vector<int> v(w);
    for (size_t y = 0; y < h; ++y) {
        const int32_t* gy = &g[y * w];
        bool any = false;
        for (size_t x = 0; x < w; ++x) {
            any |= gy[x] != none;
            f[x] = gy[x] == none ? inf : static_cast<double>(gy[x]) * static_cast<double>(gy[x]);
        }
        if (!any) {
            row(static_cast<int>(y), nullptr);
            continue;
        }
        distance_1d(f, d, v, z);
        row(static_cast<int>(y), d.data());
    }
}

std::vector<double> squared_distance_transform(const std::vector<bool>& feature, int width, int height) {
    std::vector<double> grid(static_cast<size_t>(std::max(width, 0)) * static_cast<size_t>(std::max(height, 0)));
    squared_distance_rows(feature, width, height, std::numeric_limits<double>::infinity(), [&](int y, const double* d2) {
        auto out = grid.begin() + static_cast<std::ptrdiff_t>(y) * width;
        if (d2) std::copy_n(d2, width, out);
        else std::fill_n(out, width, kNoFeature);
    });
    return grid;
}

}  // namespace crex::guidance
