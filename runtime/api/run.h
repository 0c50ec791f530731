/// \file run.h
/// Running a plan, as `crex run`, the Python module and the API examples do: the caller's
/// options resolved against the plan (run_options.h), the render as this process's part of
/// `group` (a LocalGroup for one process), progress and checkpoints through `observer`, and
/// the result as typed buffers (RunResult: image(), aov_image(), maps, samples_per_pixel()).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "runtime/api/run_options.h"
#include "runtime/driver/process_group.h"
#include "runtime/driver/run_observer.h"
#include "runtime/driver/run_plan.h"

namespace crex {

struct RunOutcome {
    ResolvedRun run;                  ///< the settings it ran with (executor.profile cleared)
    Profile measured;                 ///< the predicted profile with this run's measurements folded in
    std::optional<RunResult> result;  ///< empty on a process that answered the others' queries instead
};

/// resolve_run(plan, options), then run_resolved(). Throws RunOptionError, RunInputError,
/// std::runtime_error, and whatever `observer` throws (RunCancelled) to stop the render.
RunOutcome run_plan(const PipelinePlan& plan, const Scene& scene, const RunOptions& options, ProcessGroup& group,
                    RunObserver& observer);

/// The render with settings resolved already. In a distributed group a failure here ends
/// every process (ProcessGroup::fail()).
RunOutcome run_resolved(const PipelinePlan& plan, const Scene& scene, ResolvedRun run, ProcessGroup& group, RunObserver& observer);

/// The checkpoints of the same render under another budget policy.
using PolicyRun = std::pair<std::string, std::vector<Checkpoint>>;

/// The same render again under every policy but `used`, from the same profile, with
/// checkpoints every `interval` seconds scored by `scorer` (for a plot of all their errors
/// against time); `starting(name)` is called before each. Nothing else of theirs is kept.
std::vector<PolicyRun> render_other_policies(const PipelinePlan& plan, const Scene& scene, const ResolvedRun& run,
                                             pipeline::SchedulingPolicy used, double interval, const CheckpointScorer& scorer,
                                             const std::function<void(std::string_view)>& starting);

}  // namespace crex
