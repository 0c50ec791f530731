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
#include "runtime/driver/process_group.h"
#include "runtime/driver/run_observer.h"
#include "runtime/driver/run_result.h"
#include "runtime/driver/run_settings.h"
#include "runtime/scene/scene.h"

namespace crex {

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
/// sizes the index for the coarsest of its values; one varying ic_rays makes the preview's
/// records with the fewer rays of its two ends.
IcSettings plan_cache_settings(const PipelinePlan& plan, IcSettings settings);

/// Can a pixel ask the cache for a finer accuracy than the preview's (`vary ic_radius A .. B`
/// with B < A) or for more rays (`vary ic_rays` over two values)? Only then are the preview's
/// answers kept, to be answered again.
bool may_refine_accuracy(const PipelinePlan& plan);

/// The plan's rounds of guidance and selective rendering (the cyclic process), at least 1.
uint32_t plan_rounds(const PipelinePlan& plan);

/// Does the plan have anything beyond two crex stages (maps, variables)?
bool has_guidance(const PipelinePlan& plan);

/// W405 for each occurrence inside `{ }` that found rays in its bin and ran none of them: the
/// map modulating the braces (or the constant --importance) never reached what it needs.
std::vector<Diagnostic> modulation_warnings(const ExecutorStats& stats, const PipelinePlan& plan, double constant_importance);

/// Rays executed in total (camera rays and every component's).
uint64_t total_rays(const ExecutorStats& stats);

}  // namespace crex
