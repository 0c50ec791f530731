// LDR-FLIP, from its published definition (Andersson, Nilsson, Akenine-Moller, Oskarsson,
// Astrom, Fairchild: "FLIP: A Difference Evaluator for Alternating Images", HPG 2020):
//  colour pipeline: sRGB -> linear RGB -> XYZ -> YCxCz; each opponent channel filtered by its
//  contrast sensitivity function (sums of Gaussians, in degrees of visual angle); back to
//  linear RGB, clamped; CIELAB with the Hunt adjustment; HyAB distance; compressed (q_c = 0.7)
//  and redistributed around p_c = 0.4, p_t = 0.95 of the largest difference (green vs blue);
//  feature pipeline: edges (first Gaussian derivative) and points (second derivative) of the
//  achromatic channel, w = 0.082 deg; their difference scaled by 1/sqrt(2) with q_f = 0.5;
//  error = colour^(1 - feature).
// Every kernel here is separable, so filtering is two 1D passes.
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "runtime/io/image_io.h"
#include "runtime/metrics/metrics.h"

namespace crex::metrics {
namespace {

using Vec = std::array<double, 3>;
constexpr double kPi = std::numbers::pi;

Vec linear_rgb_to_xyz(const Vec& c) {
    return {0.41238656 * c[0] + 0.35759149 * c[1] + 0.18045049 * c[2], 0.21263682 * c[0] + 0.71518298 * c[1] + 0.0721802 * c[2],
            0.01933062 * c[0] + 0.11919716 * c[1] + 0.95037259 * c[2]};
}
Vec xyz_to_linear_rgb(const Vec& c) {
    return {3.24156502 * c[0] - 1.53766093 * c[1] - 0.49870156 * c[2], -0.96893102 * c[0] + 1.87509217 * c[1] + 0.04155173 * c[2],
            0.05562977 * c[0] - 0.20395741 * c[1] + 1.05685353 * c[2]};
}
const Vec& white() {
    static const Vec w = linear_rgb_to_xyz({1, 1, 1});
    return w;
}
Vec xyz_to_ycxcz(const Vec& c) {
    const Vec& n = white();
    double y = c[1] / n[1];
    return {116 * y - 16, 500 * (c[0] / n[0] - y), 200 * (y - c[2] / n[2])};
}
Vec ycxcz_to_xyz(const Vec& c) {
    const Vec& n = white();
    double y = (c[0] + 16) / 116;
    return {(c[1] / 500 + y) * n[0], y * n[1], (y - c[2] / 200) * n[2]};
}
Vec xyz_to_lab(const Vec& c) {
    const Vec& n = white();
    auto f = [](double t) {
        constexpr double d = 6.0 / 29.0;
        return t > d * d * d ? std::cbrt(t) : t / (3 * d * d) + 4.0 / 29.0;
    };
    double fx = f(c[0] / n[0]), fy = f(c[1] / n[1]), fz = f(c[2] / n[2]);
    return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}
Vec hunt(const Vec& lab) { return {lab[0], 0.01 * lab[0] * lab[1], 0.01 * lab[0] * lab[2]}; }
double hyab(const Vec& a, const Vec& b) { return std::fabs(a[0] - b[0]) + std::hypot(a[1] - b[1], a[2] - b[2]); }

// Runs body(i) for i in [0, n), rows or pixels, in parallel: every output element is computed
// from the inputs alone, so the map is the same bit for bit whatever the threads. (A 960x540
// checkpoint took 0.74 s to score on one thread, on the render's pool left idle meanwhile.)
template <class Body>
void each(size_t n, const Body& body) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) body(i);
    });
}

// One channel, row-major, filtered along x then y by the 1D kernels kx and ky (clamped borders).
std::vector<double> separable(const std::vector<double>& in, int w, int h, const std::vector<double>& kx, const std::vector<double>& ky) {
    const int rx = static_cast<int>(kx.size() / 2), ry = static_cast<int>(ky.size() / 2);
    std::vector<double> tmp(in.size()), out(in.size());
    each(static_cast<size_t>(h), [&](size_t row) {
        const int y = static_cast<int>(row);
        const double* src = in.data() + static_cast<size_t>(y) * static_cast<size_t>(w);
        for (int x = 0; x < w; ++x) {
            double s = 0;
            if (x >= rx && x + rx < w)  // inside: no clamping, the same sum in the same order
                for (int i = -rx; i <= rx; ++i) s += kx[static_cast<size_t>(i + rx)] * src[x + i];
            else
                for (int i = -rx; i <= rx; ++i) s += kx[static_cast<size_t>(i + rx)] * src[std::clamp(x + i, 0, w - 1)];
            tmp[static_cast<size_t>(y * w + x)] = s;
        }
    });
    // Down the columns a row at a time, so the inner loop runs along memory: each pixel still
    // sums its taps from the top one down.
    each(static_cast<size_t>(h), [&](size_t row) {
        const int y = static_cast<int>(row);
        double* dst = out.data() + static_cast<size_t>(y) * static_cast<size_t>(w);
        for (int i = -ry; i <= ry; ++i) {
            const double k = ky[static_cast<size_t>(i + ry)];
            const double* src = tmp.data() + static_cast<size_t>(std::clamp(y + i, 0, h - 1)) * static_cast<size_t>(w);
            for (int x = 0; x < w; ++x) dst[x] += k * src[x];
        }
    });
    return out;
}

// The CSF of one opponent channel: a1 sqrt(pi/b1) exp(-pi^2 r^2/b1) + a2 sqrt(pi/b2) exp(...),
// normalised to sum 1 over the (2r+1)^2 window; each Gaussian term is separable.
std::vector<double> csf_filter(const std::vector<double>& in, int w, int h, double ppd, double a1, double b1, double a2, double b2) {
    const double max_b = 0.04;  // the largest scale parameter of the three channels (BY, b1)
    int r = static_cast<int>(std::ceil(3 * std::sqrt(max_b / (2 * kPi * kPi)) * ppd));
    double dx = 1.0 / ppd;
    std::vector<double> out(in.size(), 0.0);
    double total = 0;
    std::vector<std::pair<double, std::vector<double>>> terms;
    for (auto [a, b] : {std::pair{a1, b1}, std::pair{a2, b2}}) {
        if (a == 0) continue;
        std::vector<double> k(static_cast<size_t>(2 * r + 1));
        double s = 0;
        for (int i = -r; i <= r; ++i) s += k[static_cast<size_t>(i + r)] = std::exp(-kPi * kPi * (i * dx) * (i * dx) / b);
        double c = a * std::sqrt(kPi / b);
        total += c * s * s;
        terms.push_back({c, std::move(k)});
    }
    for (const auto& [c, k] : terms) {
        std::vector<double> f = separable(in, w, h, k, k);
        for (size_t i = 0; i < out.size(); ++i) out[i] += c * f[i];
    }
    for (double& v : out) v /= total;
    return out;
}

// Feature kernels: d/dx of a Gaussian (edges) or the second derivative (points), with the
// positive weights normalised to sum 1 and the negative ones to -1; the other axis a
// normalised Gaussian. Returns the gradient magnitude of both orientations.
std::vector<double> feature_magnitude(const std::vector<double>& y, int w, int h, double ppd, bool points) {
    const double sd = 0.5 * 0.082 * ppd;
    int r = static_cast<int>(std::ceil(3 * sd));
    std::vector<double> g(static_cast<size_t>(2 * r + 1)), d(g.size());
    double gs = 0, pos = 0, neg = 0;
    for (int i = -r; i <= r; ++i) {
        double gi = std::exp(-(i * i) / (2 * sd * sd));
        g[static_cast<size_t>(i + r)] = gi;
        gs += gi;
        double di = points ? (i * i / (sd * sd) - 1) * gi : -i * gi;
        d[static_cast<size_t>(i + r)] = di;
        (di > 0 ? pos : neg) += di;
    }
    for (double& v : g) v /= gs;
    for (double& v : d) v = v > 0 ? v / pos : (v < 0 ? v / -neg : 0);
    std::vector<double> fx = separable(y, w, h, d, g), fy = separable(y, w, h, g, d);
    for (size_t i = 0; i < fx.size(); ++i) fx[i] = std::hypot(fx[i], fy[i]);
    return fx;
}

}  // namespace

std::vector<float> flip_map(const Image& test, const Image& reference, double ppd) {
    const int w = reference.width, h = reference.height;
    const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
    // YCxCz of both images, channel planes.
    std::array<std::vector<double>, 3> yt, yr;
    for (auto* planes : {&yt, &yr})
        for (auto& p : *planes) p.resize(n);
    each(n, [&](size_t i) {
        for (auto [img, planes] : {std::pair{&test, &yt}, std::pair{&reference, &yr}}) {
            Vec lin;
            for (size_t c = 0; c < 3; ++c) lin[c] = srgb_decode(std::clamp(static_cast<double>(img->rgb[3 * i + c]), 0.0, 1.0));
            Vec o = xyz_to_ycxcz(linear_rgb_to_xyz(lin));
            for (size_t c = 0; c < 3; ++c) (*planes)[c][i] = o[c];
        }
    });
    // Colour pipeline.
    auto filtered_lab = [&](const std::array<std::vector<double>, 3>& p) {
        std::vector<double> a = csf_filter(p[0], w, h, ppd, 1, 0.0047, 0, 1e-5);
        std::vector<double> rg = csf_filter(p[1], w, h, ppd, 1, 0.0053, 0, 1e-5);
        std::vector<double> by = csf_filter(p[2], w, h, ppd, 34.1, 0.04, 13.5, 0.025);
        std::vector<Vec> lab(n);
        each(n, [&](size_t i) {
            Vec rgb = xyz_to_linear_rgb(ycxcz_to_xyz({a[i], rg[i], by[i]}));
            for (double& v : rgb) v = std::clamp(v, 0.0, 1.0);
            lab[i] = hunt(xyz_to_lab(linear_rgb_to_xyz(rgb)));
        });
        return lab;
    };
    std::vector<Vec> lt = filtered_lab(yt), lr = filtered_lab(yr);
    constexpr double qc = 0.7, qf = 0.5, pc = 0.4, pt = 0.95;
    const double cmax = std::pow(hyab(hunt(xyz_to_lab(linear_rgb_to_xyz({0, 1, 0}))), hunt(xyz_to_lab(linear_rgb_to_xyz({0, 0, 1})))), qc);
    // Feature pipeline on the normalised achromatic channel of the unfiltered images.
    auto norm_y = [&](const std::array<std::vector<double>, 3>& p) {
        std::vector<double> y(n);
        for (size_t i = 0; i < n; ++i) y[i] = (p[0][i] + 16) / 116;
        return y;
    };
    std::vector<double> yt0 = norm_y(yt), yr0 = norm_y(yr);
    std::vector<double> et = feature_magnitude(yt0, w, h, ppd, false), er = feature_magnitude(yr0, w, h, ppd, false);
    std::vector<double> pt_ = feature_magnitude(yt0, w, h, ppd, true), pr = feature_magnitude(yr0, w, h, ppd, true);
    std::vector<float> out(n);
    each(n, [&](size_t i) {
        double e = std::pow(hyab(lr[i], lt[i]), qc);
        double dc = e < pc * cmax ? pt / (pc * cmax) * e : pt + (e - pc * cmax) / (cmax - pc * cmax) * (1 - pt);
        double df = std::clamp(std::max(std::fabs(er[i] - et[i]), std::fabs(pr[i] - pt_[i])), 0.0, 1.0);
        df = std::pow(df / std::sqrt(2.0), qf);
        double v = std::pow(dc, 1 - df);
        out[i] = static_cast<float>(std::isfinite(v) ? std::clamp(v, 0.0, 1.0) : 1.0);
    });
    return out;
}

}  // namespace crex::metrics
