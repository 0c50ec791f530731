/// \file oracle.h
/// A plain recursive reference integrator: the same materials, emission rule, light sampling,
/// lobe splitting, weight limit and depth limit as the bin renderer, but each camera ray is
/// followed depth-first through every lobe, one ray at a time. Used only as a test oracle:
/// with the same seed it must reproduce `(TTMRSGD)*` up to summation order; with another seed
/// it must agree statistically.
#pragma once

#include <vector>

#include "runtime/render/render.h"

namespace crex {

/// The composite image (linear RGB, row-major) of `scene` by recursion.
std::vector<float> render_oracle(const Scene& scene, const RenderOptions& options);

}  // namespace crex
