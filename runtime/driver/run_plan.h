/// \file run_plan.h
/// The one render driver (spec/pipeline.md §1, §4): run_plan() executes a plan on one Embree
/// scene in stages, camera -> pre-selective -> guidance -> selective. A plain crex run is a
/// plan without guidance: its samples run both programs pass after pass.
///  1. pre-selective: camera samples [0, spp) in sample passes, each running the pre-selective
///     crex over its own bins; the composite is the preview, the AOVs are the buffers guidance
///     reads. The rays left waiting are carried over to the selective stage.
///  2. guidance: every map of the plan, by the stdlib operators.
///  3. selective: the svt gives each pixel its variables. The carried-over rays run the
///     selective crex first; then pixels whose `spp` exceeds the preview's get new camera
///     samples in passes, continuing the preview's Halton sequence, each pass running the
///     pre-selective and then the selective crex with per-pixel shadow rays and specular
///     threshold, `{ }` modulated by its map. The preview's samples are kept: nothing is
///     rendered twice.
/// Sample passes keep memory bounded (issue 13): a pass holds at most `max_memory` worth of
/// rays, and when one sample of every pixel is over that, a pass covers a band of rows. Every
/// random number of a path is keyed by its pixel and sample index, so the image does not
/// depend on the pass size or the thread count beyond the order of the film's sums (and, with
/// an irradiance cache, on the order records are made in).
/// With an irradiance cache, D is interpolated; `ic_radius` varies its accuracy per pixel (the
/// progressive selective cache, thesis 8.2). With `subsample` varied, only the corners of the
/// adaptive grid get selective samples, and the other pixels are interpolated from them; with
/// `subsample(X)` varied (capict), only component X's first-bounce rays are sub-sampled so, and
/// its branch is interpolated in the other pixels (runtime/pipeline/component_subsample.h).
#pragma once

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "compiler/plan/pipeline_plan.h"
#include "runtime/cache/irradiance_cache.h"
#include "runtime/driver/sample_passes.h"
#include "runtime/driver/process_group.h"
#include "runtime/driver/run_observer.h"
#include "runtime/pipeline/component_subsample.h"
#include "runtime/pipeline/subsample.h"
#include "runtime/render/camera_samples.h"
#include "runtime/render/executor.h"
#include "runtime/render/film.h"
#include "runtime/scene/scene.h"
#include "stdlib/guidance/raster.h"

namespace crex {

/// `--uniform`: every selective variable at its base (min) or its maximum (max) in every
/// pixel, as if every map were 0 or 1; guidance is not computed. `max` is a pipeline's own gold.
enum class UniformQuality { kOff, kMin, kMax };

inline constexpr size_t kDefaultMaxMemory = size_t{1} << 30;

struct RunSettings {
    int width = 128, height = 128;
    /// Camera samples per pixel: of a plain crex run all of them, of a pipeline the preview's.
    uint32_t spp = 1;
    uint32_t first_sample = 0;  ///< a plain crex run renders samples [first_sample, first_sample + spp)
    /// A plain crex run renders only the pixels of these windows of the frame, each exactly as
    /// a render of the whole frame would (windowed references); empty: every pixel.
    std::vector<PixelWindow> windows;
    uint64_t seed = 0;
    PixelFilter filter = PixelFilter::kBox;
    Vec3 ambient{0, 0, 0};      ///< `av`: radiance standing in for unexecuted D work
    /// Instead of `ambient`: every ray left unexecuted in any bin stands in with what rays of
    /// its component brought back on average in this render (its AOV over the throughput of
    /// its executed rays), or the image's mean radiance where none of them ran. So a pixel
    /// whose components were skipped is never black for lack of work (spec/pipeline.md §6).
    bool ambient_auto = false;
    ExecutorOptions executor;   ///< base-quality shading, budget, profile
    std::optional<IcSettings> irradiance_cache;  ///< D through a Ward irradiance cache
    std::vector<IrradianceRecord> ic_records;    ///< records to start from
    std::string ic_file;        ///< with a cache: load records from it if it exists, save them there at the end
    /// The bytes of `ic_file` read already (distributed runs: by rank 0, the one process that
    /// has the file); loaded instead of reading `ic_file`, which is still where they are saved
    /// (by the process the ProcessGroup names).
    std::optional<std::string> ic_file_bytes;
    size_t max_memory = kDefaultMaxMemory;  ///< the process's memory the passes are sized for
    /// Texture lookups filter over this many pixels' footprint (0: none, the sharpest lookups:
    /// tests show what filtering prevents).
    double texture_filter_width = 1;
    uint32_t pass_samples = 0;  ///< samples per pixel per pass at most (0: as many as fit)
    UniformQuality uniform = UniformQuality::kOff;
    uint32_t rounds = 0;        ///< rounds of guidance and selective rendering (0: the plan's, else 1)
    /// How a budget is spent (--policy); unset: the plan's, else the default of spec/pipeline.md
    /// §7: whole tasks for a pipeline without `vary`, queues for one with, and progressive
    /// passes for a plain crex (a plan with no name).
    std::optional<pipeline::SchedulingPolicy> policy;
    /// --resume (issue 19): rows already final, taken from a partial image; the camera samples of
    /// the render's last stage are not traced there (a plain crex: none at all; a pipeline: its
    /// last round's selective samples; the preview and earlier rounds are rendered whole, since
    /// guidance sees the whole image). Those rows of the result are the caller's to replace.
    std::vector<char> final_rows;
};

/// Input the run cannot use (a malformed irradiance-cache file, a plan this runtime cannot
/// execute): the user's to fix (exit 1), unlike runtime failures (std::runtime_error, exit 3).
struct RunInputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct RunResult {
    RunResult(int width, int height) : film(width, height) {}
    Film film;
    std::vector<double> ambient;   ///< per pixel RGB, sample-summed: av for D rays never executed
    ExecutorStats stats;
    std::vector<std::string> warnings;
    std::vector<std::string> notes;  ///< what the runtime did not execute, and why
    /// With ambient_auto: the radiance that stood in for each component's unexecuted rays.
    std::array<Vec3, kComponentCount> auto_ambient{};
    double setup_seconds = 0;      ///< Embree scene and BVH build (and opening the textures)
    double render_seconds = 0;     ///< from the first camera ray
    double render_cpu_seconds = 0; ///< the process's CPU time over the same span (all threads)
    double render_thread_seconds = 0;  ///< render_seconds times the worker threads it had
    std::optional<TextureStats> textures;  ///< a textured scene's texture cache and lookups
    std::array<size_t, kComponentCount> rays_left{};  ///< dropped at the end of passes, per bin
    size_t passes = 0;             ///< sample passes over all stages
    uint64_t budget_stopped_samples = 0;  ///< camera samples the budget left out
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
    IcStats ic_stats;
    size_t ic_loaded = 0;          ///< records read from `ic_file`
    /// Distributed rendering: the split of the render's last stage (row_bands.h); empty in one process.
    std::vector<int> row_bands;

    // Pipelines: they run in stages.
    bool staged = false;
    std::vector<float> preview;    ///< linear RGB at the end of the pre-selective stage
    std::vector<std::pair<std::string, guidance::Raster>> maps;  ///< name ("sal", or a node id), map
    std::optional<SubsampleGrid> subsample;
    ComponentSubsampling component_subsample;  ///< capict's grids, one per component varied
    size_t refinements = 0;        ///< capict: rounds of splitting squares whose corners differ
    double preview_seconds = 0, guidance_seconds = 0, selective_seconds = 0;
    /// The progressive selective cache (thesis 8.2): records made in the preview, preview D
    /// samples answered again at a finer accuracy in the selective stage, records made then.
    size_t ic_preview_records = 0, ic_reprocessed = 0, ic_selective_records = 0;
    /// Progressive direct light (thesis 8.2): preview samples whose camera-hit direct light was
    /// estimated again with their pixel's shadow_rays, and the shadow rays that took.
    size_t direct_light_redone = 0;
    uint64_t direct_light_redone_shadow_rays = 0;
    uint64_t preview_rays = 0, selective_rays = 0;

    /// The final image: the composite plus the ambient stand-in, sub-sampled pixels interpolated.
    std::vector<float> image() const;
    /// One AOV of the final image, interpolated like it.
    std::vector<float> aov_image(size_t aov) const;
};

/// Executes `plan` on `scene` with resolved settings (runtime/api/run.h resolves a caller's
/// options against the plan first), as one process of `group` (distributed rendering: this
/// process's rows, the exchanges), telling `observer` what it does. Throws RunInputError for
/// input it cannot use, std::runtime_error for runtime failures (Embree, I/O of the cache
/// file), and whatever the observer throws to stop it.
RunResult run_plan(const Scene& scene, const PipelinePlan& plan, const RunSettings& settings, ProcessGroup& group, RunObserver& observer);
/// One process, nobody watching.
RunResult run_plan(const Scene& scene, const PipelinePlan& plan, const RunSettings& settings);

/// A plain crex run: the plan of `program` without guidance.
RunResult render(const Scene& scene, const sched::Program& program, const RunSettings& settings, RunObserver& observer);
RunResult render(const Scene& scene, const sched::Program& program, const RunSettings& settings);

/// The cache's settings for `plan`: a plan varying ic_radius starts at its `from` accuracy and
/// sizes the index for the coarsest of its values.
IcSettings plan_cache_settings(const PipelinePlan& plan, IcSettings settings);

/// The plan's rounds of guidance and selective rendering (the cyclic process), at least 1.
uint32_t plan_rounds(const PipelinePlan& plan);

/// Does the plan have anything beyond two crex stages (maps, variables)?
bool has_guidance(const PipelinePlan& plan);

/// Rays executed in total (camera rays and every component's).
uint64_t total_rays(const ExecutorStats& stats);

}  // namespace crex
