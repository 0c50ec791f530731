/// \file pass_sizing.h
/// How big a sample pass may be (issue 13): a model of the memory a render holds, not a
/// measurement of the process, so that the passes (and so the order of the film's sums) are the
/// same on every run. A pass holds what the limit leaves beside the film, its buffers, the scene
/// and the rays carried over; the first pass of a stage takes an eighth of that, and the rest
/// are planned again on the rays it actually held (where lobe splitting keeps many more rays in
/// flight than the model, as in the room's trans and glass: 2.9 GB under a 1 GiB limit).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "compiler/plan/pipeline_plan.h"
#include "runtime/driver/sample_passes.h"
#include "runtime/render/render_scene.h"

namespace crex {

struct RunSettings;

/// A camera sample in flight: its ray, hit and shading buffers and the children it leaves.
inline constexpr size_t kBytesPerSample = 512;

/// capict: the components whose first-bounce branches the film tracks (their `subsample(X)`).
uint8_t subsampled_components(const PipelinePlan& plan);

/// What a render holds beside its passes' rays: the process's baseline, the film (its
/// `layout` and capict's branches), the ambient stand-ins (`ambient`), and for a pipeline
/// (`staged`) its preview image, maps and per-pixel settings.
size_t resident_bytes(size_t pixels, const FilmLayout& layout, uint8_t tracked_branches, bool ambient, bool staged);

/// What a render holds whatever its passes, at its peak: resident_bytes() and the larger of
/// guidance's buffers and the output images, which are made between passes and after them.
size_t fixed_bytes(size_t pixels, const FilmLayout& layout, uint8_t tracked_branches, bool staged, bool ambient);

/// The run keeps per-pixel ambient stand-ins: they are automatic, or `--ambient` is not 0.
bool keeps_ambient(const RunSettings& settings);

/// Throws std::runtime_error for a render whose film and buffers alone need more than the
/// machine has free, before anything is allocated.
void refuse_what_cannot_fit(const PipelinePlan& plan, const RunSettings& settings);

/// A note when what no pass size can shrink is over the run's --max-memory ("": it is not),
/// with the limit that would hold it.
std::string memory_over_limit_note(const PipelinePlan& plan, const RunSettings& settings);

/// Bytes the next pass's rays may take: `max_memory` less what the process holds (`fixed`,
/// `held` by rays carried over, the scene's triangles), at least one row of `width` samples.
size_t pass_bytes(size_t fixed, size_t held, const RenderScene& scene, int width, size_t max_memory);

/// Samples a pass at most so that a stage of `frame` (the whole frame's ranges, whatever part
/// of it this process renders) goes in kProgressivePasses passes or more: each pass that ends
/// gives every pixel its samples finished, so the image, its error curve and the progress move
/// through the stage instead of all at its end (sel_rp's 16-spp selective stage in one pass
/// kept its report's curve flat for 80 % of the run). 0 for a stage of one sample a pixel.
inline constexpr uint32_t kProgressivePasses = 16;
uint32_t progressive_pass_samples(const SampleRanges& frame);

/// The sample passes of one stage.
class StagePasses {
public:
    /// `limits.bytes` from pass_bytes(); `budgeted`: one sample index a pass (each admitted on
    /// its cost); `pass_samples`: a given number of samples a pass (no replanning); else at
    /// most `progressive` a pass (0: as many as fit).
    StagePasses(int width, int height, const SampleRanges& ranges, PassLimits limits, bool budgeted, uint32_t pass_samples,
                uint32_t progressive = 0);

    std::vector<SamplePass>& passes() { return passes_; }

    /// After the first pass, which held `peak_rays_held` rays at most: the rest planned again on
    /// what its samples really took, when more follow (a first pass of some rows only: the
    /// later passes merged). Returns the bytes a sample was sized by (0: not planned again).
    size_t replan_after_first(uint64_t peak_rays_held, size_t pixels);

private:
    void merge_later_passes();

    int width_, height_;
    SampleRanges ranges_;
    PassLimits limits_;
    size_t full_bytes_;
    bool replan_;
    std::vector<SamplePass> passes_;
};

}  // namespace crex
