/// \file capict_refinement.h
/// capict's recursion (thesis 7.2): after the selective stage, the squares of a component's
/// sub-sampling grid whose corners' light differs by more than the component's threshold
/// (`vary subsample(X) ... refine T`) split, and the new corners render the branch they skipped,
/// by tracing their selective samples again with everything but that branch not counted. Each
/// split halves a square, so a spacing of 2^k ends within k rounds.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "compiler/plan/pipeline_plan.h"
#include "runtime/driver/sample_passes.h"
#include "runtime/pipeline/component_subsample.h"
#include "runtime/render/film.h"

namespace crex {

/// At most this many rounds: a spacing of 2^11 pixels has split to one by then.
inline constexpr int kMaxRefinementRounds = 11;

/// One round: which pixels trace their selective samples again, and for which branches.
struct Refinement {
    SampleRanges ranges;            ///< samples [preview spp, the pixel's samples) of the new corners
    std::vector<uint8_t> runs;      ///< per pixel: bit c set where component c's first bounces run
    uint8_t replay = 0;             ///< the branches replayed (bit c: component c)
};

/// The next round for `plan`'s refined components (their grids in `subsampling` split as the
/// film's light says); nullopt when no square splits any more. `preview_spp`: the samples every
/// pixel had before the selective stage, which the new corners keep.
std::optional<Refinement> next_refinement(const PipelinePlan& plan, ComponentSubsampling& subsampling, const Film& film,
                                          uint32_t preview_spp);

}  // namespace crex
