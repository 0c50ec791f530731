/// \file run_pipeline.h
/// run_pipeline(): executes a pipeline's plan (spec/pipeline.md §1, §3):
///  1. pre-selective: camera rays at the base spp, then the pre-selective crex; the composite
///     is the preview, the AOVs are the buffers guidance reads;
///  2. guidance: every map of the plan, by the stdlib operators;
///  3. selective: the svt gives each pixel its variables. Pixels whose `spp` exceeds the base
///     get new camera samples, continuing the preview's Halton sequence; those rays run the
///     pre-selective crex in their own bins, which then join the preview's carried-over bins,
///     and the selective crex runs over all of them with per-pixel shadow rays and specular
///     threshold, `{ }` modulated by its map. The preview's samples are kept: nothing is
///     rendered twice.
/// With an irradiance cache, D is interpolated; `ic_radius` varies its accuracy per pixel: the
/// preview uses the value where the map is 0 for every pixel, and in the selective stage the
/// preview's own D samples of pixels asking for finer accuracy are answered again (their old
/// answer replaced), most important pixels first, making records only where needed.
/// With `subsample` varied, only the corners of the adaptive grid get selective samples, and
/// every other pixel of the final image is interpolated from them.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "compiler/plan/pipeline_plan.h"
#include "runtime/pipeline/subsample.h"
#include "runtime/render/render.h"
#include "stdlib/guidance/raster.h"

namespace crex {

struct PipelineRunOptions {
    int width = 128, height = 128;
    uint32_t preview_spp = 1;  ///< camera samples per pixel of the pre-selective stage
    uint64_t seed = 0;
    PixelFilter filter = PixelFilter::kBox;
    Vec3 ambient{0, 0, 0};
    ExecutorOptions executor;  ///< base-quality shading, budget, profile, progress
    CheckpointRecorder* recorder = nullptr;  ///< reports: image snapshots during the render
    std::optional<IcSettings> irradiance_cache;  ///< D through the cache (ic_radius varies its accuracy)
    std::vector<IrradianceRecord> ic_records;
};

struct PipelineRunResult {
    PipelineRunResult(int width, int height) : render(width, height) {}
    RenderResult render;            ///< every sample of both stages
    std::vector<float> preview;     ///< linear RGB at the end of the pre-selective stage
    std::vector<std::pair<std::string, guidance::Raster>> maps;  ///< name ("sal", or a node id), map
    std::vector<std::string> notes;  ///< what the runtime did not execute, and why
    std::optional<SubsampleGrid> subsample;
    double preview_seconds = 0, guidance_seconds = 0, selective_seconds = 0;
    /// The progressive selective cache (thesis 8.2): records made in the preview, preview D
    /// samples answered again at a finer accuracy in the selective stage, records made then.
    size_t ic_preview_records = 0, ic_reprocessed = 0, ic_selective_records = 0;
    uint64_t preview_rays = 0, selective_rays = 0;

    /// The final image: the composite, sub-sampled pixels interpolated.
    std::vector<float> image() const;
    /// One AOV of the final image, interpolated like it.
    std::vector<float> aov_image(size_t aov) const;
};

/// Throws std::runtime_error for a plan it cannot execute (an unknown operator, a malformed
/// number) and for Embree failures.
PipelineRunResult run_pipeline(const Scene& scene, const PipelinePlan& plan, const PipelineRunOptions& options);

/// Does the plan have anything beyond two crex stages (maps, variables)? Plans without are
/// rendered exactly as `render()` renders their crex.
bool has_guidance(const PipelinePlan& plan);

}  // namespace crex
