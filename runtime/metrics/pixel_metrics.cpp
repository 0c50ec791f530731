// RMSE, relMSE and SSIM.
#include <algorithm>
#include <array>
#include <cmath>
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "runtime/io/image_io.h"
#include "runtime/metrics/metrics.h"

namespace crex::metrics {

double rmse(const Image& t, const Image& r) {
    double sum = 0;  // long double is not needed: squares of values in a few hundred channels
    for (size_t i = 0; i < r.rgb.size(); ++i) {
        double d = static_cast<double>(t.rgb[i]) - r.rgb[i];
        sum += d * d;
    }
    return r.rgb.empty() ? 0 : std::sqrt(sum / static_cast<double>(r.rgb.size()));
}

double relmse(const Image& t, const Image& r, double eps) {
    double sum = 0;
    for (size_t i = 0; i < r.rgb.size(); ++i) {
        double d = static_cast<double>(t.rgb[i]) - r.rgb[i];
        sum += d * d / (static_cast<double>(r.rgb[i]) * r.rgb[i] + eps);
    }
    return r.rgb.empty() ? 0 : sum / static_cast<double>(r.rgb.size());
}

std::optional<double> ssim(const Image& t, const Image& r) {
    constexpr int kWin = 11;
    constexpr double kSigma = 1.5, c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
    const int w = r.width, h = r.height;
    if (w < kWin || h < kWin) return std::nullopt;
    double weight[kWin], total = 0;
    for (int i = 0; i < kWin; ++i) total += weight[i] = std::exp(-0.5 * (i - kWin / 2) * (i - kWin / 2) / (kSigma * kSigma));
    for (double& x : weight) x /= total;
    auto luma = [](const Image& img) {
        std::vector<double> y(img.rgb.size() / 3);
        for (size_t i = 0; i < y.size(); ++i) y[i] = 0.2126 * img.rgb[3 * i] + 0.7152 * img.rgb[3 * i + 1] + 0.0722 * img.rgb[3 * i + 2];
        return y;
    };
    std::vector<double> x = luma(t), y = luma(r);
    // Windows a band of rows at a time in parallel, each window's value as on one thread, then
    // summed in row order: the same mean bit for bit, a band's values the only memory it takes.
    const int cols = w - kWin + 1, rows = h - kWin + 1, band = 64;
    std::vector<double> values(static_cast<size_t>(band) * static_cast<size_t>(cols));
    double sum = 0;
    size_t count = 0;
    for (int top = 0; top < rows; top += band) {
        const int n = std::min(band, rows - top);
        tbb::parallel_for(0, n, [&](int b) {
            const int oy = top + b;
            for (int ox = 0; ox < cols; ++ox) {
                double mx = 0, my = 0, sxx = 0, syy = 0, sxy = 0;
                for (int j = 0; j < kWin; ++j)
                    for (int i = 0; i < kWin; ++i) {
                        double wt = weight[i] * weight[j];
                        size_t p = static_cast<size_t>(oy + j) * static_cast<size_t>(w) + static_cast<size_t>(ox + i);
                        mx += wt * x[p], my += wt * y[p];
                        sxx += wt * x[p] * x[p], syy += wt * y[p] * y[p], sxy += wt * x[p] * y[p];
                    }
                double vx = sxx - mx * mx, vy = syy - my * my, cxy = sxy - mx * my;
                values[static_cast<size_t>(b) * static_cast<size_t>(cols) + static_cast<size_t>(ox)] =
                    (2 * mx * my + c1) * (2 * cxy + c2) / ((mx * mx + my * my + c1) * (vx + vy + c2));
            }
        });
        for (size_t k = 0; k < static_cast<size_t>(n) * static_cast<size_t>(cols); ++k) sum += values[k], ++count;
    }
    return sum / static_cast<double>(count);
}

double perr(const std::vector<float>& flip, double threshold) {
    if (flip.empty()) return 0;
    size_t over = static_cast<size_t>(std::count_if(flip.begin(), flip.end(), [&](float v) { return v >= threshold; }));
    return 100.0 * static_cast<double>(over) / static_cast<double>(flip.size());
}

double mean(const std::vector<float>& values) {
    double sum = 0;
    for (float v : values) sum += v;
    return values.empty() ? 0 : sum / static_cast<double>(values.size());
}

WeightedSum weighted_sum(const std::vector<float>& values, const std::vector<float>& weights) {
    WeightedSum s;
    if (values.size() != weights.size()) return s;
    for (size_t i = 0; i < values.size(); ++i) {
        double w = std::isfinite(weights[i]) && weights[i] > 0 ? weights[i] : 0.0;
        s.sum += w * values[i], s.weight += w;
    }
    return s;
}

std::optional<double> weighted_mean(const std::vector<float>& values, const std::vector<float>& weights) {
    if (values.size() != weights.size()) return std::nullopt;
    const WeightedSum s = weighted_sum(values, weights);
    if (!(s.weight > 0)) return std::nullopt;
    return s.sum / s.weight;
}

std::string DisplayView::describe() const {
    return hdr ? fmt::format("HDR inputs tone-mapped with the reference's exposure {:.6g} (key 0.18 over its log-average "
                             "luminance), Reinhard, sRGB curve",
                             exposure)
               : "LDR inputs compared as stored (sRGB)";
}

Image display_view(const Image& linear, const DisplayView& view) {
    Image out{linear.width, linear.height, {}};
    if (view.hdr) {
        out.rgb = to_display(linear.rgb, view.exposure);
        return out;
    }
    out.rgb.resize(linear.rgb.size());
    for (size_t i = 0; i < out.rgb.size(); ++i) {  // back to the sRGB values the file held
        double v = std::clamp(static_cast<double>(linear.rgb[i]), 0.0, 1.0);
        out.rgb[i] = static_cast<float>(v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055);
    }
    return out;
}

size_t firefly_count(const Image& img) {
    const int w = img.width, h = img.height;
    const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
    if (n == 0 || img.rgb.size() < 3 * n) return 0;
    std::vector<double> lum(n);
    double sum = 0;
    for (size_t p = 0; p < n; ++p) {
        const double l = 0.2126 * img.rgb[3 * p] + 0.7152 * img.rgb[3 * p + 1] + 0.0722 * img.rgb[3 * p + 2];
        lum[p] = std::isfinite(l) ? l : 0.0;
        sum += lum[p];
    }
    const double floor = 0.01 * sum / static_cast<double>(n);
    size_t count = 0;
    std::array<double, 9> around;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double l = lum[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)];
            if (!(l > floor)) continue;
            size_t k = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int yy = std::clamp(y + dy, 0, h - 1), xx = std::clamp(x + dx, 0, w - 1);
                    around[k++] = lum[static_cast<size_t>(yy) * static_cast<size_t>(w) + static_cast<size_t>(xx)];
                }
            std::nth_element(around.begin(), around.begin() + 4, around.end());
            count += l > 10 * around[4];
        }
    return count;
}

}  // namespace crex::metrics
