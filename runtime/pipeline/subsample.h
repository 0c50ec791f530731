/// \file subsample.h
/// Adaptive sub-sampling on a square grid (thesis 4.6, Case III): squares of the largest
/// spacing are split while any pixel inside asks for a smaller spacing; only the corners of
/// the final squares are rendered, every other pixel is the bilinear interpolation of its
/// square's corners.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace crex {

class SubsampleGrid {
public:
    /// `spacing`: the corner spacing each pixel asks for (>= 1), row-major.
    SubsampleGrid(int width, int height, const std::vector<double>& spacing);

    bool rendered(uint32_t pixel) const { return corner_[pixel]; }
    size_t rendered_count() const;
    /// Replaces every non-corner pixel of `rgb` (3 floats per pixel) by its interpolation.
    void fill(std::vector<float>& rgb) const;
    /// Replaces each pixel without samples (`sampled[p]` 0) by the bilinear interpolation of
    /// those of its square's corners that have samples, their weights renormalised; a pixel
    /// none of whose corners has any keeps its value. `values` holds the same number of floats
    /// for every pixel. (A preview rendered at the corners only, whose other pixels the
    /// selective stage fills, may be cut short by a budget: issue 34.)
    void fill_unsampled(std::vector<float>& values, const std::vector<uint8_t>& sampled) const;
    /// The same as weights made once and applied to many buffers (guidance reads several).
    struct Fill {
        size_t pixels = 0;  ///< of the frame
        /// Per pixel: its square's corners with samples and their renormalised weights; all
        /// weights 0 where the pixel has samples or keeps its value.
        std::vector<std::array<uint32_t, 4>> from;
        std::vector<std::array<float, 4>> weight;
    };
    Fill unsampled_fill(const std::vector<uint8_t>& sampled) const;
    static void apply(const Fill& fill, std::vector<float>& values);
    /// x0, y0, x1, y1 of the final square `pixel` lies in (its corners are rendered).
    std::array<uint16_t, 4> square(uint32_t pixel) const { return square_[pixel]; }
    int width() const { return width_; }
    int height() const { return height_; }

private:
    bool corner_weights(size_t p, const std::vector<uint8_t>& sampled, std::array<uint32_t, 4>& from, std::array<float, 4>& weight) const;
    void split(int x0, int y0, int size, const std::vector<double>& spacing);
    int width_, height_;
    std::vector<bool> corner_;
    std::vector<std::array<uint16_t, 4>> square_;  ///< x0, y0, x1, y1 of each pixel's square
};

}  // namespace crex
