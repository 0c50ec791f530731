/// \file oracle.h
/// A plain recursive reference integrator: the same materials, emission rule, light sampling,
/// lobe splitting, weight limit and depth limit as the bin renderer, but each camera ray is
/// followed depth-first through every lobe, one ray at a time. Used only as a test oracle:
/// with the same seed it must reproduce `(TTMRSGD)*` up to summation order; with another seed
/// it must agree statistically.
#pragma once

#include <vector>

#include "runtime/render/shade.h"
#include "runtime/scene/scene.h"

namespace crex {

struct OracleOptions {
    int width = 16, height = 16;
    uint32_t spp = 1;
    uint32_t first_sample = 0;  ///< samples [first_sample, first_sample + spp)
    uint64_t seed = 0;
    ShadeParams shade;
};

/// The composite image (linear RGB, row-major) of `scene` by recursion.
std::vector<float> render_oracle(const Scene& scene, const OracleOptions& options);

}  // namespace crex
