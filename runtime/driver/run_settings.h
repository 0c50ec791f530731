/// \file run_settings.h
/// What the render driver runs with (run_plan.h): the settings of a render, resolved already
/// (runtime/api/run_options.h resolves a caller's options against a plan), and the error of
/// input a run cannot use.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "compiler/pipeline/settings_table.h"
#include "runtime/cache/irradiance_cache.h"
#include "runtime/driver/pixel_history.h"
#include "runtime/driver/sample_passes.h"
#include "runtime/render/camera_samples.h"
#include "runtime/render/executor.h"

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
    /// The lookup grids of an earlier render over the first of `ic_records` (RunResult::ic_grids),
    /// taken over instead of filing those records again; null: all are filed.
    std::shared_ptr<IcGrids> ic_grids;
    /// Hand the cache's lookup grids on in RunResult::ic_grids (a sequence that carries its cache).
    bool hand_on_ic_grids = false;
    std::string ic_file;        ///< with a cache: load records from it if it exists, save them there at the end
    /// The bytes of `ic_file` read already (distributed runs: by rank 0, the one process that
    /// has the file); loaded instead of reading `ic_file`, which is still where they are saved
    /// (by the process the ProcessGroup names).
    std::optional<std::string> ic_file_bytes;
    /// false: `ic_file` is only where the cache is saved, not read (the frames of a sequence
    /// after its first carry their records in `ic_records`, the file holds the last frame's).
    bool ic_file_read = true;
    size_t max_memory = kDefaultMaxMemory;  ///< the process's memory the passes are sized for
    /// Every component's image is wanted (RunResult::aov_image): the film keeps every buffer.
    /// false: only those the render reads itself (film_layout.h), so a 3840x2160 film is a
    /// seventh of the size; aov_image() of another component is empty.
    bool component_images = true;
    /// Texture lookups filter over this many pixels' footprint (0: none, the sharpest lookups:
    /// tests show what filtering prevents).
    double texture_filter_width = 1;
    uint32_t pass_samples = 0;  ///< samples per pixel per pass at most (0: as many as fit)
    UniformQuality uniform = UniformQuality::kOff;
    uint32_t rounds = 0;        ///< rounds of guidance and selective rendering (0: the plan's, else 1)
    /// A pipeline's preview renders only every `preview_stride`-th pixel of every
    /// `preview_stride`-th row (and the last row and column); guidance sees the others
    /// interpolated, and the selective stage renders them. 0: automatic, coarse to fine under a
    /// budget (preview_levels.h), else every pixel.
    uint32_t preview_stride = 1;
    /// Under a budget: the render's end after its last stage (stand-ins, warnings) as a
    /// profile predicts it; the stages stop that much before the budget, so the run ends on it.
    double end_seconds = 0;
    /// A pipeline's full render whose profile is saved: after the clock stops, time the work a
    /// preview at every kCoarsestPreviewStride-th pixel does per pixel of the frame (its grid
    /// and sample ranges, the composite, the fill), which the floor adds to its samples' cost;
    /// and the end a budgeted render would have (RunResult::budgeted_end_seconds).
    bool time_strided_preview = false;
    /// How a budget is spent (--policy); unset: the plan's, else the default of spec/pipeline.md
    /// §7: whole tasks for a pipeline without `vary`, queues for one with, and progressive
    /// passes for a plain crex (a plan with no name).
    std::optional<pipeline::SchedulingPolicy> policy;
    /// --resume (issue 19): rows already final, taken from a partial image; the camera samples of
    /// the render's last stage are not traced there (a plain crex: none at all; a pipeline: its
    /// last round's selective samples; the preview and earlier rounds are rendered whole, since
    /// guidance sees the whole image). Those rows of the result are the caller's to replace.
    std::vector<char> final_rows;
    /// Without an irradiance cache: photons for a caustic map (runtime/cache/caustic_photons.h)
    /// that gives the light of paths L S+ D at diffuse hits, instead of D rays that find a lamp
    /// through mirrors and glass (fireflies); used when the plan executes D rays and the scene
    /// has mirrors, glass or trans surfaces. 0: those paths are path traced.
    uint32_t caustic_photons = 0;
    /// A caustic map built already for this scene, photon count and seed (RunResult::caustic_map
    /// of an earlier render: a sequence's frames share one, the photons do not depend on the
    /// camera); null: built here when one is needed. An empty map says the scene has no caustic
    /// paths: nothing is built, nothing looked up.
    std::shared_ptr<const CausticPhotons> caustic_map;
    /// The BVH, lights, textures and materials built already from the very Scene object the run
    /// is given (a sequence's frames: only its camera moves, which set_view() reads again).
    /// Null: built here.
    std::shared_ptr<RenderScene> render_scene;
    /// Samples each pixel inherits from the frame before (pixel_history.h; a sequence's
    /// `--reuse-frames`): it takes that many fewer of its own, at least one, and the image
    /// blends them in. Null: none.
    std::shared_ptr<const PixelHistory> history;
    /// A walk whose frames inherit: where in its pixel a sample lies, for a pixel that inherits
    /// nothing (no `history` there), from this seed instead of `seed`, the same in every frame.
    /// Such a pixel (an object's outline, where two surfaces meet) takes all its samples afresh
    /// every frame; drawn at new positions, its blend of the two surfaces jumped from frame to
    /// frame (half of a walk's flicker). Its light is still drawn from `seed`. Unset: `seed`.
    std::optional<uint64_t> position_seed;
};

/// Input the run cannot use (a malformed irradiance-cache file, a plan this runtime cannot
/// execute): the user's to fix (exit 1), unlike runtime failures (std::runtime_error, exit 3).
struct RunInputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace crex
