/// \file run_result.h
/// What a render gives back (run_plan.h): the film and its stand-ins, statistics, notes, and for
/// a pipeline its stages' images, maps and sub-sampling; image() and aov_image() are the final
/// buffers.
#pragma once

#include <array>
#include <optional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "compiler/pipeline/settings_table.h"
#include "runtime/cache/irradiance_cache.h"
#include "runtime/driver/pixel_history.h"
#include "runtime/pipeline/component_subsample.h"
#include "runtime/pipeline/subsample.h"
#include "runtime/render/executor.h"
#include "runtime/render/film.h"
#include "runtime/texture/surface_textures.h"
#include "stdlib/guidance/raster.h"

namespace crex {

struct RunResult {
    RunResult(int width, int height, FilmLayout layout = {}) : film(width, height, layout) {}
    Film film;
    std::vector<double> ambient;   ///< per pixel RGB, sample-summed: av for D rays never executed
    ExecutorStats stats;
    std::vector<Diagnostic> warnings;  ///< each once, in (where, code) order
    std::vector<std::string> notes;  ///< what the runtime did not execute, and why
    /// With ambient_auto: the radiance that stood in for each component's unexecuted rays.
    std::array<Vec3, kComponentCount> auto_ambient{};
    double setup_seconds = 0;      ///< Embree scene and BVH build (and opening the textures, the caustic map)
    double caustic_map_seconds = 0;  ///< building the caustic map (path tracing's or the cache's), in setup_seconds
    double render_seconds = 0;     ///< from the first camera ray
    double render_cpu_seconds = 0; ///< the process's CPU time over the same span (all threads)
    double render_thread_seconds = 0;  ///< render_seconds times the worker threads it had
    std::optional<TextureStats> textures;  ///< a textured scene's texture cache and lookups
    std::array<size_t, kComponentCount> rays_left{};  ///< dropped at the end of passes, per bin
    size_t passes = 0;             ///< sample passes over all stages
    uint64_t budget_stopped_samples = 0;  ///< camera samples the budget left out
    bool stopped = false;                 ///< the observer asked to stop: the image so far
    uint64_t stopped_samples = 0;         ///< camera samples the stop left out of its stage
    size_t bytes_per_sample = 0;   ///< what the passes after the first were sized by (0: one pass)
    pipeline::SchedulingPolicy policy = pipeline::SchedulingPolicy::kTasks;  ///< the one used under a budget
    /// The share of the image's light the limits left out, estimated (0..1; issue 37): paths
    /// ended by max_depth, paths dropped below lw without roulette, and the cache's bounces past
    /// its last (when no --ambient stands in). A path cut with throughput t is taken to have
    /// lost t times what a camera sample brings (so the share is T / (1 + T), T the cut
    /// throughput per camera sample); the cache's lost light is its D light times the product
    /// of its levels' mean albedos. Both assume the light beyond the cut is like the light
    /// before it, which in a closed room of high albedo makes them a lower bound.
    double light_cut_by_depth = 0, light_cut_by_weight = 0, light_cut_by_cache = 0;
    std::vector<IrradianceRecord> ic_records;  ///< the cache at the end (with an irradiance cache)
    std::shared_ptr<IcGrids> ic_grids;         ///< its lookup grids, with RunSettings::hand_on_ic_grids
    IcStats ic_stats;
    size_t ic_loaded = 0;          ///< records read from `ic_file`
    /// The caustic map the render built or was given (the cache's or path tracing's; null:
    /// none asked for; empty: the scene has no caustic paths): a later render of the same scene
    /// and settings can take it (RunSettings::caustic_map) instead of tracing its photons again.
    std::shared_ptr<const CausticPhotons> caustic_map;
    /// What the pixels inherited from the frame before (RunSettings::history): image() blends
    /// it in; the components' images are the frame's own samples. Null: nothing.
    std::shared_ptr<const PixelHistory> history;
    /// Distributed rendering: the split of the render's last stage (row_bands.h); empty in one process.
    std::vector<int> row_bands;

    // Pipelines: they run in stages.
    bool staged = false;
    std::vector<float> preview;    ///< linear RGB at the end of the pre-selective stage
    std::vector<std::pair<std::string, guidance::Raster>> maps;  ///< name ("sal", or a node id), map
    std::optional<SubsampleGrid> subsample;
    /// A preview at every k-th pixel (RunSettings::preview_stride): the grid its pixels are the
    /// corners of. Pixels still without samples at the end are interpolated from it.
    std::optional<SubsampleGrid> preview_grid;
    ComponentSubsampling component_subsample;  ///< capict's grids, one per component varied
    size_t refinements = 0;        ///< capict: rounds of splitting squares whose corners differ
    double preview_seconds = 0, guidance_seconds = 0, selective_seconds = 0;
    double end_seconds = 0;  ///< after the last stage: stand-ins, warnings (StageCosts::end_seconds)
    double strided_preview_seconds = 0;  ///< RunSettings::time_strided_preview's figure; 0 if not timed
    /// With RunSettings::time_strided_preview: the end a budgeted render of this frame would
    /// take (every component's light left standing in), timed after the clock; 0 if not timed.
    double budgeted_end_seconds = 0;
    /// The progressive selective cache (thesis 8.2): records made in the preview, preview D
    /// samples answered again at a finer accuracy in the selective stage, records made then.
    size_t ic_preview_records = 0, ic_reprocessed = 0, ic_selective_records = 0;
    double ic_preview_record_seconds = 0;  ///< making the preview's records
    /// Progressive direct light (thesis 8.2): preview samples whose camera-hit direct light was
    /// estimated again with their pixel's shadow_rays, and the shadow rays that took.
    size_t direct_light_redone = 0;
    uint64_t direct_light_redone_shadow_rays = 0;
    uint64_t preview_rays = 0, selective_rays = 0;
    uint64_t preview_samples = 0;  ///< the preview's camera samples
    uint32_t preview_stride = 1;   ///< the preview rendered every k-th pixel (preview_levels.h)

    /// The final image: the composite plus the ambient stand-in, sub-sampled pixels interpolated.
    std::vector<float> image() const;
    /// One AOV of the final image, interpolated like it.
    std::vector<float> aov_image(size_t aov) const;
    /// A strided preview's pixels that no stage rendered, interpolated (any floats per pixel).
    /// `fill`: preview_grid's unsampled_fill(sampled_pixels()), made once for many buffers.
    void fill_unsampled_preview(std::vector<float>& values, const SubsampleGrid::Fill* fill = nullptr) const;
    /// 1 for each pixel with a sample.
    std::vector<uint8_t> sampled_pixels() const;
};

}  // namespace crex
