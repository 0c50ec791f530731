/// \file noise.h
/// RADIANCE's noise functions, as its function files call them (its noise3.c, rewritten from
/// what they compute): noise3 is Ken Perlin's improved noise (2002) over a lattice of period
/// 256, 0 at every lattice point; noise3x/y/z its partial derivatives by RADIANCE's backward
/// difference of 0.0005; fnoise3 RADIANCE's fractal noise, a midpoint displacement over a
/// 1/2000 grid in ten levels of halving amplitude (from 0.5), constant within each grid cell.
/// Patterns written for RADIANCE look the same in crex because the values are the same.
#pragma once

namespace crex::radiance {

double noise3(double x, double y, double z);
/// axis 0, 1, 2: RADIANCE's noise3x, noise3y, noise3z.
double noise3_partial(double x, double y, double z, int axis);
double fnoise3(double x, double y, double z);

}  // namespace crex::radiance
