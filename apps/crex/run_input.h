/// \file run_input.h
/// What `crex run` executes: a crex (-e), a pipeline file, or a plan kept from `crex plan`,
/// always as one PipelinePlan (a crex is a plan without guidance), with its scene loaded and
/// the pipeline's settings applied to the options no flag overrode.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "apps/crex/run_options.h"
#include "apps/crex/scene_input.h"
#include "base/diagnostic.h"
#include "compiler/plan/pipeline_plan.h"

namespace crex::app {

struct RunInput {
    std::unique_ptr<SourceFile> source;  ///< the crex, pipeline or plan text diagnostics point into
    PipelinePlan plan;
    bool pipeline = false;               ///< a pipeline (file or plan), not a bare crex
    std::string scene_spec;
    std::unique_ptr<SceneInput> scene;
    std::unique_ptr<SourceFile> view_source;  ///< --view FILE.vf (diagnostics point into it)
    double load_seconds = 0;
};

/// Reads the input and its scene; diagnostics are printed. Returns an exit code on failure,
/// std::nullopt when the run can go on.
std::optional<int> read_run_input(RunOptions& opt, RunInput& in);

/// Under mpirun, on ranks other than 0: what rank 0 read, as data: its plan as JSON (as
/// `crex plan --format json` writes it, checked again by the plan reader) and its scene
/// already loaded; the pipeline's settings applied as read_run_input() does. Returns an exit
/// code when the plan cannot be read (a bug: rank 0 wrote it; printed).
std::optional<int> read_run_input_from_rank0(RunOptions& opt, RunInput& in, const std::string& plan_json,
                                             std::unique_ptr<SceneInput> scene, const std::string& scene_spec);

}  // namespace crex::app
