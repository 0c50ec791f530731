/// \file plan_pipeline.h
/// plan_pipeline(): a resolved pipeline as an execution plan (spec/pipeline.md §3), in the
/// passes below, run in their order (compiler/compiler.h's compile_pipeline() runs the front
/// end before them and the scene-aware warnings after): both
/// stages' crex lowered (bins carry over from the first to the second), and a typed graph of
/// camera rays, stage programs, the preview and buffers, guidance operators, selective
/// variables, the irradiance cache, composite and outputs, with edges labelled by what flows
/// (bin, image, buffer, map, svt, cache). With a scene census: steps that can never have work,
/// the irradiance cache when no D step is left, and maps nothing consumes are removed, each
/// listed in `pruned` with its reason. Node ids are stable names, never counters of memory.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "compiler/pipeline/resolve.h"
#include "compiler/plan/bin_occupancy.h"
#include "compiler/plan/pipeline_plan.h"
#include "compiler/sched/program.h"

namespace crex {

/// Pass 1: the two stages' crex lowered into `plan.program` (the selective `{ }` groups name
/// their map), the typed settings, and `staged`. False when a crex has errors (in `sink`).
bool lower_stages(const pipeline::ResolvedPipeline& p, PipelinePlan& plan, DiagnosticSink& sink);

/// Pass 2 (with a scene): steps whose bin no material of the scene can fill removed, each
/// listed in `plan.pruned`; the scene and its census hash recorded.
void prune_steps_for_scene(const BinSet& spawnable, const std::string& scene, const std::string& census_hash, PipelinePlan& plan);

/// Pass 3: the selective variables that still mean something once steps are pruned (ic_radius
/// needs a D step, subsample(X) an X step); `plan.irradiance_cache` set. The others are listed
/// in `plan.pruned`.
std::vector<const pipeline::ResolvedVariable*> prune_variables(const pipeline::ResolvedPipeline& p, PipelinePlan& plan);

/// Pass 4: the maps a surviving variable or the `{ }` modulation consumes, transitively through
/// other maps; the rest are listed in `plan.pruned`.
std::set<std::string> mark_live_maps(const pipeline::ResolvedPipeline& p, const std::vector<const pipeline::ResolvedVariable*>& vary,
                                     PipelinePlan& plan);

/// Pass 5: the typed maps, buffers, variables, modulation map and outputs of what is live, and
/// the graph that draws them (nodes and edges, for pictures only).
void build_plan_graph(const pipeline::ResolvedPipeline& p, const std::vector<const pipeline::ResolvedVariable*>& vary,
                      const std::set<std::string>& live_maps, PipelinePlan& plan);

/// Passes 1-5. `spawnable` given: prune for that scene (census hash recorded too).
std::optional<PipelinePlan> plan_pipeline(const pipeline::ResolvedPipeline& p, const std::optional<BinSet>& spawnable,
                                          const std::string& scene, const std::string& census_hash, DiagnosticSink& sink);

nlohmann::json pipeline_plan_to_json(const PipelinePlan& plan);
std::string pipeline_plan_to_dot(const PipelinePlan& plan);
std::string pipeline_plan_to_text(const PipelinePlan& plan);

}  // namespace crex
