/// \file filters.h
/// The image filters the guidance operators are built from: separable Gaussian blur, the
/// Gaussian pyramid, bilinear resampling, Sobel gradients and the exact Euclidean distance
/// transform. Borders are clamped. Small and dependency-free on purpose: OpenImageIO's
/// ImageBufAlgo would do the same, but linking OIIO into the tool costs every command 0.4 s
/// of start-up (see runtime/io). They run at full-HD frame sizes in milliseconds on one core
/// (bench/guidance_bench).
#pragma once

#include <functional>
#include <vector>

#include "stdlib/guidance/raster.h"

namespace crex::guidance {

/// Gaussian blur with standard deviation `sigma` pixels (kernel radius 3 sigma); sigma <= 0: copy.
Raster gaussian_blur(const Raster& in, double sigma);

/// Gaussian pyramid: level 0 is the input, each next level blurred (sigma 1) and halved, down
/// to `max_levels` levels or a level of width or height 1.
std::vector<Raster> gaussian_pyramid(Raster in, int max_levels);

/// Bilinear resampling to w x h (pixel centres aligned).
Raster resize_bilinear(const Raster& in, int w, int h);

/// Sobel derivatives of channel 0: gx (left to right) and gy (top to bottom).
void sobel(const Raster& in, Raster& gx, Raster& gy);

/// What the distance transforms give where `feature` has no pixel at all.
constexpr double kNoFeature = 1e30;

/// Squared Euclidean distance (in pixels) from every pixel to the nearest pixel where
/// `feature` is true (Felzenszwalb-Huttenlocher, exact, linear time); kNoFeature when there
/// is none.
std::vector<double> squared_distance_transform(const std::vector<bool>& feature, int width, int height);

/// The same, handed over a row at a time (`row(y, d2)`, d2 valid during the call only), for
/// callers that map distances to values and need no full-image grid of doubles. Distances
/// below `reach` pixels are exact; any other is reported as some value >= reach^2, and
/// d2 is null when the whole row is that far. A finite reach saves the work far from features.
void squared_distance_rows(const std::vector<bool>& feature, int width, int height, double reach,
                           const std::function<void(int, const double*)>& row);

}  // namespace crex::guidance
