/// \file pipeline_warnings.h
/// What a pipeline asks of its scene that the scene cannot give (spec/pipeline.md §6), said
/// at the pipeline's line: `tagged("x")` when no object of the scene has that tag (W203), and
/// a guidance buffer `component(X)` that the pre-selective crex never fills because it never
/// executes X, or X can never occur in the scene (W204). Both checks see only names: the tags
/// of the scene's objects and the steps of the planned pre-selective program.
#pragma once

#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "compiler/pipeline/resolve.h"
#include "compiler/plan/pipeline_plan.h"

namespace crex {

/// `scene_tags` null: no scene is known, so W203 is not checked.
void warn_scene_mismatches(const pipeline::ResolvedPipeline& pipeline, const PipelinePlan& plan,
                           const std::vector<std::string>* scene_tags, DiagnosticSink& sink);

/// W206: `noise(...)` while no pixel has two samples before guidance (a 1-spp preview and no
/// selective floor): the even and odd halves it compares do not both exist, so it is 0.
void warn_noise_of_one_sample(const pipeline::ResolvedPipeline& pipeline, const PipelinePlan& plan, DiagnosticSink& sink);

/// W403: `vary media_samples` on a scene without a participating medium does nothing.
void warn_media_without_medium(const pipeline::ResolvedPipeline& pipeline, bool scene_has_medium, DiagnosticSink& sink);

/// W205: occurrences inside the selective crex's `{ }` that no pixel can run, because its
/// `by` map can never reach the importance they need (the map's largest value is bounded from
/// its definition: constants, thresholds, weighted importance).
void warn_unreachable_modulated_steps(const pipeline::ResolvedPipeline& pipeline, const PipelinePlan& plan, DiagnosticSink& sink);

}  // namespace crex
