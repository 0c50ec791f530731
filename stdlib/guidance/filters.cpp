// Separable filters on contiguous rows. Each output value is computed with the same float
// operations in the same order as the textbook per-pixel loop (tests/unit/guidance keeps that
// loop as the reference), so the speed comes from layout, not from changed arithmetic: rows
// are padded by their clamped border once, and the inner loops run over whole rows, which the
// compiler vectorises.
#include "stdlib/guidance/filters.h"

#include <algorithm>
#include <cmath>

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

size_t clamp_index(long i, long n) { return static_cast<size_t>(i < 0 ? 0 : (i >= n ? n - 1 : i)); }

// Row `src` of `width` pixels of `channels` floats, with `r` border pixels repeated on each
// side: pad[(x + r) * channels + c] is the clamped pixel x.
void pad_row(const float* src, int width, int channels, int r, std::vector<float>& pad) {
    const size_t ch = static_cast<size_t>(channels), w = static_cast<size_t>(width), rr = static_cast<size_t>(r);
    pad.resize((w + 2 * rr) * ch);
    std::copy(src, src + w * ch, pad.begin() + static_cast<std::ptrdiff_t>(rr * ch));
    for (size_t x = 0; x < rr; ++x)
        for (size_t c = 0; c < ch; ++c) {
            pad[x * ch + c] = src[c];
            pad[(rr + w + x) * ch + c] = src[(w - 1) * ch + c];
        }
}

// Horizontal pass: out[x] = sum_i k[i] * in(step * x + i - r), for `n_out` outputs per row.
// step 2 is blur-and-halve: only the pixels the pyramid keeps are computed. `split` is
// scratch space.
void blur_row(const std::vector<float>& pad, const std::vector<float>& k, int channels, int step, int n_out, float* out,
              std::vector<float>& split) {
    const size_t ch = static_cast<size_t>(channels), n = static_cast<size_t>(n_out) * ch;
    std::fill(out, out + n, 0.0f);
    if (step == 1) {
        for (size_t i = 0; i < k.size(); ++i)
            for (size_t j = 0; j < n; ++j) out[j] += k[i] * pad[i * ch + j];
    } else if (ch == 1) {
        // Even taps read the padded row's even pixels, odd taps its odd ones: split once into
        // the two halves, every tap is a contiguous (vectorised) run.
        const size_t half = (pad.size() + 1) / 2;
        split.resize(2 * half);
        float *even = split.data(), *odd = split.data() + half;
        for (size_t j = 0; j < pad.size() / 2; ++j) {
            even[j] = pad[2 * j];
            odd[j] = pad[2 * j + 1];
        }
        if (pad.size() % 2) even[half - 1] = pad.back();
        for (size_t i = 0; i < k.size(); ++i) {
            const float* p = split.data() + (i % 2) * half + i / 2;
            for (size_t x = 0; x < n; ++x) out[x] += k[i] * p[x];
        }
    } else {
        for (size_t i = 0; i < k.size(); ++i)
            for (size_t x = 0; x < static_cast<size_t>(n_out); ++x)
                for (size_t c = 0; c < ch; ++c) out[x * ch + c] += k[i] * pad[(2 * x + i) * ch + c];
    }
}

// Blur by `k`, keeping every `step`-th pixel of every `step`-th row (1: all of them).
Raster blur_and_decimate(const Raster& in, const std::vector<float>& k, int step) {
    const int r = static_cast<int>(k.size() / 2);
    const int ow = (in.width + step - 1) / step, oh = (in.height + step - 1) / step;
    const size_t ch = static_cast<size_t>(in.channels), in_row = static_cast<size_t>(in.width) * ch,
                 out_row = static_cast<size_t>(ow) * ch;
    // Horizontal pass over every input row (the vertical pass reads rows around each kept one).
    Raster tmp(ow, in.height, in.channels);
    std::vector<float> pad, split;
    for (size_t y = 0; y < static_cast<size_t>(in.height); ++y) {
        pad_row(in.v.data() + y * in_row, in.width, in.channels, r, pad);
        blur_row(pad, k, in.channels, step, ow, tmp.v.data() + y * out_row, split);
    }
    // Vertical pass: whole rows at a time, summed in the same order as the per-pixel loop.
    Raster out(ow, oh, in.channels);
    for (long y = 0; y < oh; ++y) {
        float* o = out.v.data() + static_cast<size_t>(y) * out_row;
        for (size_t i = 0; i < k.size(); ++i) {
            const float ki = k[i];
            const float* src = tmp.v.data() + clamp_index(step * y + static_cast<long>(i) - r, in.height) * out_row;
            for (size_t j = 0; j < out_row; ++j) o[j] += ki * src[j];
        }
    }
    return out;
}

}  // namespace

Raster gaussian_blur(const Raster& in, double sigma) {
    if (!(sigma > 0) || in.pixels() == 0) return in;
    return blur_and_decimate(in, gaussian_kernel(sigma), 1);
}

std::vector<Raster> gaussian_pyramid(Raster in, int max_levels) {
    const std::vector<float> k = gaussian_kernel(1.0);
    std::vector<Raster> levels;
    levels.push_back(std::move(in));
    while (static_cast<int>(levels.size()) < max_levels && levels.back().width > 1 && levels.back().height > 1)
        levels.push_back(blur_and_decimate(levels.back(), k, 2));
    return levels;
}

Raster resize_bilinear(const Raster& in, int w, int h) {
    Raster out(w, h, in.channels);
    if (in.pixels() == 0) return out;
    const size_t ch = static_cast<size_t>(in.channels), in_row = static_cast<size_t>(in.width) * ch,
                 out_row = static_cast<size_t>(w) * ch;
    // Where each output column reads (clamped) and its weight: the same for every row.
    const double sx = static_cast<double>(in.width) / w, sy = static_cast<double>(in.height) / h;
    std::vector<size_t> left(static_cast<size_t>(w)), right(static_cast<size_t>(w));
    std::vector<float> tx(static_cast<size_t>(w));
    for (int x = 0; x < w; ++x) {
        double fx = (x + 0.5) * sx - 0.5;
        long x0 = static_cast<long>(std::floor(fx));
        tx[static_cast<size_t>(x)] = static_cast<float>(fx - static_cast<double>(x0));
        left[static_cast<size_t>(x)] = clamp_index(x0, in.width) * ch;
        right[static_cast<size_t>(x)] = clamp_index(x0 + 1, in.width) * ch;
    }
    // Each input row resampled across once, when an output row first needs it.
    std::vector<float> across(static_cast<size_t>(in.height) * out_row);
    std::vector<char> done(static_cast<size_t>(in.height), 0);
    auto row = [&](size_t y) -> const float* {
        float* a = across.data() + y * out_row;
        if (!done[y]) {
            const float* src = in.v.data() + y * in_row;
            for (size_t x = 0; x < static_cast<size_t>(w); ++x)
                for (size_t c = 0; c < ch; ++c) {
                    float t = tx[x];
                    a[x * ch + c] = src[left[x] + c] * (1 - t) + src[right[x] + c] * t;
                }
            done[y] = 1;
        }
        return a;
    };
    for (int y = 0; y < h; ++y) {
        double fy = (y + 0.5) * sy - 0.5;
        long y0 = static_cast<long>(std::floor(fy));
        const float ty = static_cast<float>(fy - static_cast<double>(y0));
        const float* a = row(clamp_index(y0, in.height));
        const float* b = row(clamp_index(y0 + 1, in.height));
        float* o = out.v.data() + static_cast<size_t>(y) * out_row;
        for (size_t j = 0; j < out_row; ++j) o[j] = a[j] * (1 - ty) + b[j] * ty;
    }
    return out;
}

void sobel(const Raster& in, Raster& gx, Raster& gy) {
    const int w = in.width, h = in.height;
    gx = Raster(w, h, 1);
    gy = Raster(w, h, 1);
    if (in.pixels() == 0) return;
    // Channel 0 of the rows above, at and below, each padded by one clamped pixel: p[x + 1] is x.
    std::vector<float> rows[3];
    for (auto& r : rows) r.resize(static_cast<size_t>(w) + 2);
    auto load = [&](std::vector<float>& r, long y) {
        const size_t base = clamp_index(y, h) * static_cast<size_t>(w);
        for (long x = -1; x <= w; ++x) r[static_cast<size_t>(x + 1)] = in.v[(base + clamp_index(x, w)) * static_cast<size_t>(in.channels)];
    };
    for (int d = 0; d < 3; ++d) load(rows[d], d - 1);
    for (long y = 0; y < h; ++y) {
        if (y > 0) {  // move down a row: the middle becomes the top, the bottom the middle
            std::swap(rows[0], rows[1]);
            std::swap(rows[1], rows[2]);
            load(rows[2], y + 1);
        }
        const float *u = rows[0].data(), *m = rows[1].data(), *b = rows[2].data();
        float* ox = gx.v.data() + static_cast<size_t>(y) * static_cast<size_t>(w);
        float* oy = gy.v.data() + static_cast<size_t>(y) * static_cast<size_t>(w);
        for (size_t x = 0; x < static_cast<size_t>(w); ++x) {
            // x - 1, x, x + 1 are x, x + 1, x + 2 in the padded rows.
            ox[x] = (u[x + 2] + 2 * m[x + 2] + b[x + 2]) - (u[x] + 2 * m[x] + b[x]);
            oy[x] = (b[x] + 2 * b[x + 1] + b[x + 2]) - (u[x] + 2 * u[x + 1] + u[x + 2]);
        }
    }
}

}  // namespace crex::guidance
