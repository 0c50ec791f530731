#include "runtime/pipeline/guidance_grid.h"

#include <algorithm>

#include "base/check.h"

namespace crex {
namespace {

// 0, k, 2k, ... and the last: the columns (or rows) a preview at stride k sampled.
std::vector<int> grid_lines(int size, uint32_t stride) {
    std::vector<int> lines;
    for (int i = 0; i < size; i += static_cast<int>(stride)) lines.push_back(i);
    if (size > 0 && lines.back() != size - 1) lines.push_back(size - 1);
    return lines;
}

// For each frame coordinate: the grid lines at or before it and after it, and the weight of the second.
struct Span {
    size_t lo = 0, hi = 0;
    float t = 0;
};
std::vector<Span> spans(const std::vector<int>& lines, int size) {
    std::vector<Span> out(static_cast<size_t>(size));
    size_t k = 0;
    for (int x = 0; x < size; ++x) {
        while (k + 1 < lines.size() && lines[k + 1] <= x) ++k;
        Span& s = out[static_cast<size_t>(x)];
        s.lo = k, s.hi = std::min(k + 1, lines.size() - 1);
        const int gap = lines[s.hi] - lines[s.lo];
        s.t = gap > 0 ? static_cast<float>(x - lines[s.lo]) / static_cast<float>(gap) : 0.0f;
    }
    return out;
}

}  // namespace

GuidanceGrid::GuidanceGrid(int width, int height, uint32_t stride) : frame_width_(width), frame_height_(height) {
    xs_ = grid_lines(width, std::max<uint32_t>(stride, 1));
    ys_ = grid_lines(height, std::max<uint32_t>(stride, 1));
}

guidance::Raster GuidanceGrid::spread(const guidance::Raster& map) const {
    CREX_CHECK_EQ(static_cast<size_t>(map.width), xs_.size());
    CREX_CHECK_EQ(static_cast<size_t>(map.height), ys_.size());
    guidance::Raster out(frame_width_, frame_height_, map.channels);
    const std::vector<Span> sx = spans(xs_, frame_width_), sy = spans(ys_, frame_height_);
    for (int y = 0; y < frame_height_; ++y) {
        const Span& v = sy[static_cast<size_t>(y)];
        for (int x = 0; x < frame_width_; ++x) {
            const Span& u = sx[static_cast<size_t>(x)];
            for (int c = 0; c < map.channels; ++c) {
                const auto at = [&](size_t i, size_t j) { return map.at(static_cast<int>(i), static_cast<int>(j), c); };
                const float top = at(u.lo, v.lo) + (at(u.hi, v.lo) - at(u.lo, v.lo)) * u.t;
                const float bottom = at(u.lo, v.hi) + (at(u.hi, v.hi) - at(u.lo, v.hi)) * u.t;
                out.at(x, y, c) = top + (bottom - top) * v.t;
            }
        }
    }
    return out;
}

}  // namespace crex
