#include "runtime/pipeline/subsample.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace crex {

SubsampleGrid::SubsampleGrid(int width, int height, const std::vector<double>& spacing)
    : width_(width), height_(height), corner_(static_cast<size_t>(width) * static_cast<size_t>(height), false),
      square_(corner_.size()) {
    double largest = 1;
    for (double s : spacing) largest = std::max(largest, std::isfinite(s) ? s : 1.0);
    int top = 1;
    while (top * 2 <= std::min(largest, 1024.0)) top *= 2;
    for (int y = 0; y < height; y += top)
        for (int x = 0; x < width; x += top) split(x, y, top, spacing);
}

void SubsampleGrid::split(int x0, int y0, int size, const std::vector<double>& spacing) {
    int x1 = std::min(x0 + size, width_ - 1), y1 = std::min(y0 + size, height_ - 1);
    double need = 1e30;
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) need = std::min(need, spacing[static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x)]);
    if (size > 1 && size > need) {
        int h = size / 2;
        for (int dy : {0, h})
            for (int dx : {0, h})
                if (x0 + dx < width_ && y0 + dy < height_) split(x0 + dx, y0 + dy, h, spacing);
        return;
    }
    for (int y : {y0, y1})
        for (int x : {x0, x1}) corner_[static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x)] = true;
    std::array<uint16_t, 4> sq = {static_cast<uint16_t>(x0), static_cast<uint16_t>(y0), static_cast<uint16_t>(x1), static_cast<uint16_t>(y1)};
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) square_[static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x)] = sq;
}

size_t SubsampleGrid::rendered_count() const { return static_cast<size_t>(std::count(corner_.begin(), corner_.end(), true)); }

void SubsampleGrid::fill(std::vector<float>& rgb) const {
    std::vector<float> src = rgb;
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) {
            size_t p = static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x);
            if (corner_[p]) continue;
            auto [x0, y0, x1, y1] = square_[p];
            float tx = x1 > x0 ? static_cast<float>(x - x0) / static_cast<float>(x1 - x0) : 0.0f;
            float ty = y1 > y0 ? static_cast<float>(y - y0) / static_cast<float>(y1 - y0) : 0.0f;
            auto at = [&](int cx, int cy, int c) { return src[3 * (static_cast<size_t>(cy) * static_cast<size_t>(width_) + static_cast<size_t>(cx)) + static_cast<size_t>(c)]; };
            for (int c = 0; c < 3; ++c) {
                float top = at(x0, y0, c) * (1 - tx) + at(x1, y0, c) * tx;
                float bottom = at(x0, y1, c) * (1 - tx) + at(x1, y1, c) * tx;
                rgb[3 * p + static_cast<size_t>(c)] = top * (1 - ty) + bottom * ty;
            }
        }
}

// Pixel p's square's corners that have samples, with their bilinear weights renormalised over
// them; false where p has samples or no corner has (it keeps its value).
bool SubsampleGrid::corner_weights(size_t p, const std::vector<uint8_t>& sampled, std::array<uint32_t, 4>& from,
                                   std::array<float, 4>& weight) const {
    from = {}, weight = {};
    if (sampled[p]) return false;
    const size_t w = static_cast<size_t>(width_), x = p % w, y = p / w;
    const auto [x0, y0, x1, y1] = square_[p];
    const double tx = x1 > x0 ? double(x - x0) / double(x1 - x0) : 0.0, ty = y1 > y0 ? double(y - y0) / double(y1 - y0) : 0.0;
    const std::array<std::pair<size_t, double>, 4> corners = {{
        {y0 * w + x0, (1 - tx) * (1 - ty)},
        {y0 * w + x1, tx * (1 - ty)},
        {y1 * w + x0, (1 - tx) * ty},
        {y1 * w + x1, tx * ty},
    }};
    double total = 0;
    for (const auto& [q, wq] : corners)
        if (q != p && wq > 0 && sampled[q]) total += wq;
    if (!(total > 0)) return false;
    for (size_t k = 0; k < 4; ++k) {
        const auto& [q, wq] = corners[k];
        if (q != p && wq > 0 && sampled[q]) from[k] = static_cast<uint32_t>(q), weight[k] = static_cast<float>(wq / total);
    }
    return true;
}

namespace {

// values[p] = the weighted corners, every channel. Only pixels without samples are written,
// and only pixels with samples read: in place.
void blend_corners(size_t p, const std::array<uint32_t, 4>& from, const std::array<float, 4>& weight, size_t channels,
                   std::vector<float>& values) {
    for (size_t c = 0; c < channels; ++c) {
        double v = 0;
        for (size_t k = 0; k < 4; ++k)
            if (weight[k] > 0) v += static_cast<double>(weight[k]) * static_cast<double>(values[from[k] * channels + c]);
        values[p * channels + c] = static_cast<float>(v);
    }
}

}  // namespace

SubsampleGrid::Fill SubsampleGrid::unsampled_fill(const std::vector<uint8_t>& sampled) const {
    Fill fill;
    const size_t pixels = corner_.size();
    if (sampled.size() != pixels) return fill;
    fill.pixels = pixels;
    fill.from.resize(pixels);  // dense, so that rows are made in parallel
    fill.weight.resize(pixels);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels, 4096), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t p = r.begin(); p < r.end(); ++p) corner_weights(p, sampled, fill.from[p], fill.weight[p]);
    });
    return fill;
}

void SubsampleGrid::apply(const Fill& fill, std::vector<float>& values) {
    if (fill.pixels == 0 || values.size() % fill.pixels != 0) return;
    const size_t channels = values.size() / fill.pixels;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, fill.pixels, 4096), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t p = r.begin(); p < r.end(); ++p) {
            const std::array<float, 4>& weight = fill.weight[p];
            if (weight[0] > 0 || weight[1] > 0 || weight[2] > 0 || weight[3] > 0) blend_corners(p, fill.from[p], weight, channels, values);
        }
    });
}

void SubsampleGrid::fill_unsampled(std::vector<float>& values, const std::vector<uint8_t>& sampled) const {
    // Used once: the weights are made as they are applied, with no per-pixel table (the
    // table was most of the 5 ms a strided preview's fill took at 384x288).
    const size_t pixels = corner_.size();
    if (sampled.size() != pixels || pixels == 0 || values.size() % pixels != 0) return;
    const size_t channels = values.size() / pixels;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels, 4096), [&](const tbb::blocked_range<size_t>& r) {
        std::array<uint32_t, 4> from;
        std::array<float, 4> weight;
        for (size_t p = r.begin(); p < r.end(); ++p)
            if (corner_weights(p, sampled, from, weight)) blend_corners(p, from, weight, channels, values);
    });
}

}  // namespace crex
