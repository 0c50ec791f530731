#include "stdlib/guidance/filters.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace crex::guidance {
namespace {

std::vector<float> gaussian_kernel(double sigma) {
    int r = std::max(1, static_cast<int>(std::ceil(3 * sigma)));
    std::vector<float> k(static_cast<size_t>(2 * r + 1));
    double sum = 0;
    for (int i = -r; i <= r; ++i) sum += k[static_cast<size_t>(i + r)] = static_cast<float>(std::exp(-0.5 * i * i / (sigma * sigma)));
    for (float& x : k) x = static_cast<float>(x / sum);
    return k;
}

}  // namespace

Raster gaussian_blur(const Raster& in, double sigma) {
    if (!(sigma > 0) || in.pixels() == 0) return in;
    std::vector<float> k = gaussian_kernel(sigma);
    int r = static_cast<int>(k.size() / 2);
    Raster tmp(in.width, in.height, in.channels), out(in.width, in.height, in.channels);
    for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x)
            for (int c = 0; c < in.channels; ++c) {
                float s = 0;
                for (int i = -r; i <= r; ++i) s += k[static_cast<size_t>(i + r)] * in.clamped(x + i, y, c);
                tmp.at(x, y, c) = s;
            }
    for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x)
            for (int c = 0; c < in.channels; ++c) {
                float s = 0;
                for (int i = -r; i <= r; ++i) s += k[static_cast<size_t>(i + r)] * tmp.clamped(x, y + i, c);
                out.at(x, y, c) = s;
            }
    return out;
}

std::vector<Raster> gaussian_pyramid(const Raster& in, int max_levels) {
    std::vector<Raster> levels{in};
    while (static_cast<int>(levels.size()) < max_levels && levels.back().width > 1 && levels.back().height > 1) {
        Raster b = gaussian_blur(levels.back(), 1.0);
        Raster half((b.width + 1) / 2, (b.height + 1) / 2, b.channels);
        for (int y = 0; y < half.height; ++y)
            for (int x = 0; x < half.width; ++x)
                for (int c = 0; c < b.channels; ++c) half.at(x, y, c) = b.clamped(2 * x, 2 * y, c);
        levels.push_back(std::move(half));
    }
    return levels;
}

Raster resize_bilinear(const Raster& in, int w, int h) {
    Raster out(w, h, in.channels);
    if (in.pixels() == 0) return out;
    double sx = static_cast<double>(in.width) / w, sy = static_cast<double>(in.height) / h;
    for (int y = 0; y < h; ++y) {
        double fy = (y + 0.5) * sy - 0.5;
        int y0 = static_cast<int>(std::floor(fy));
        float ty = static_cast<float>(fy - y0);
        for (int x = 0; x < w; ++x) {
            double fx = (x + 0.5) * sx - 0.5;
            int x0 = static_cast<int>(std::floor(fx));
            float tx = static_cast<float>(fx - x0);
            for (int c = 0; c < in.channels; ++c) {
                float a = in.clamped(x0, y0, c) * (1 - tx) + in.clamped(x0 + 1, y0, c) * tx;
                float b = in.clamped(x0, y0 + 1, c) * (1 - tx) + in.clamped(x0 + 1, y0 + 1, c) * tx;
                out.at(x, y, c) = a * (1 - ty) + b * ty;
            }
        }
    }
    return out;
}

void sobel(const Raster& in, Raster& gx, Raster& gy) {
    gx = Raster(in.width, in.height, 1);
    gy = Raster(in.width, in.height, 1);
    for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x) {
            auto p = [&](int dx, int dy) { return in.clamped(x + dx, y + dy, 0); };
            gx.at(x, y) = (p(1, -1) + 2 * p(1, 0) + p(1, 1)) - (p(-1, -1) + 2 * p(-1, 0) + p(-1, 1));
            gy.at(x, y) = (p(-1, 1) + 2 * p(0, 1) + p(1, 1)) - (p(-1, -1) + 2 * p(0, -1) + p(1, -1));
        }
}

namespace {

// One dimension of the Felzenszwalb-Huttenlocher transform: lower envelope of parabolas.
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
    k = 0;
    for (int q = 0; q < n; ++q) {
        while (z[static_cast<size_t>(k) + 1] < q) ++k;
        int p = v[static_cast<size_t>(k)];
        double fp = f[static_cast<size_t>(p)];
        d[static_cast<size_t>(q)] = std::isfinite(fp) ? (q - p) * (q - p) + fp : inf;
    }
}

}  // namespace

std::vector<double> squared_distance_transform(const std::vector<bool>& feature, int width, int height) {
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<double> grid(static_cast<size_t>(width) * static_cast<size_t>(height));
    for (size_t i = 0; i < grid.size(); ++i) grid[i] = feature[i] ? 0.0 : inf;
    int n = std::max(width, height);
    std::vector<double> f(static_cast<size_t>(n)), d(static_cast<size_t>(n)), z(static_cast<size_t>(n) + 1);
    std::vector<int> v(static_cast<size_t>(n));
    f.resize(static_cast<size_t>(height)), d.resize(static_cast<size_t>(height));
    for (int x = 0; x < width; ++x) {
        for (int y = 0; y < height; ++y) f[static_cast<size_t>(y)] = grid[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
        distance_1d(f, d, v, z);
        for (int y = 0; y < height; ++y) grid[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] = d[static_cast<size_t>(y)];
    }
    f.resize(static_cast<size_t>(width)), d.resize(static_cast<size_t>(width));
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) f[static_cast<size_t>(x)] = grid[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
        distance_1d(f, d, v, z);
        for (int x = 0; x < width; ++x) grid[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] = d[static_cast<size_t>(x)];
    }
    for (double& g : grid)
        if (!std::isfinite(g)) g = 1e30;
    return grid;
}

}  // namespace crex::guidance
