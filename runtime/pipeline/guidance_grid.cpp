#include "runtime/pipeline/guidance_grid.h"

#include <algorithm>

#include "base/check.h"

namespace crex {

GuidanceGrid::GuidanceGrid(int width, int height, uint32_t stride)
    : preview_(width, height, std::vector<double>(static_cast<size_t>(std::max(width, 0)) * static_cast<size_t>(std::max(height, 0)),
                                                  static_cast<double>(std::max<uint32_t>(stride, 1)))) {
    // A uniform grid: its columns are the corners of the first row, its rows those of the first column.
    for (int x = 0; x < width; ++x)
        if (preview_.rendered(static_cast<uint32_t>(x))) xs_.push_back(x);
    for (int y = 0; y < height && width > 0; ++y)
        if (preview_.rendered(static_cast<uint32_t>(y * width))) ys_.push_back(y);
    corners_.resize(static_cast<size_t>(std::max(width, 0)) * static_cast<size_t>(std::max(height, 0)));
    for (size_t p = 0; p < corners_.size(); ++p) corners_[p] = preview_.rendered(static_cast<uint32_t>(p));
}

guidance::Raster GuidanceGrid::spread(const guidance::Raster& map) const {
    CREX_CHECK_EQ(static_cast<size_t>(map.width), xs_.size());
    CREX_CHECK_EQ(static_cast<size_t>(map.height), ys_.size());
    guidance::Raster out(preview_.width(), preview_.height(), map.channels);
    for (size_t j = 0; j < ys_.size(); ++j)
        for (size_t i = 0; i < xs_.size(); ++i)
            for (int c = 0; c < map.channels; ++c) out.at(xs_[i], ys_[j], c) = map.at(static_cast<int>(i), static_cast<int>(j), c);
    preview_.fill_unsampled(out.v, corners_);
    return out;
}

}  // namespace crex
