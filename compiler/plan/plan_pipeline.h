/// \file plan_pipeline.h
/// plan_pipeline(): a resolved pipeline as an execution plan (spec/pipeline.md §3): both
/// stages' crex lowered (bins carry over from the first to the second), and a typed graph of
/// camera rays, stage programs, the preview and buffers, guidance operators, selective
/// variables, the irradiance cache, composite and outputs, with edges labelled by what flows
/// (bin, image, buffer, map, svt, cache). With a scene census: steps that can never have work,
/// the irradiance cache when no D step is left, and maps nothing consumes are removed, each
/// listed in `pruned` with its reason. Node ids are stable names, never counters of memory.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "compiler/pipeline/resolve.h"
#include "compiler/plan/bin_occupancy.h"
#include "compiler/plan/pipeline_plan.h"
#include "compiler/sched/program.h"

namespace crex {

/// `spawnable` given: prune for that scene (census hash recorded too).
std::optional<PipelinePlan> plan_pipeline(const pipeline::ResolvedPipeline& p, const std::optional<BinSet>& spawnable,
                                          const std::string& scene, const std::string& census_hash, DiagnosticSink& sink);

nlohmann::json pipeline_plan_to_json(const PipelinePlan& plan);
std::string pipeline_plan_to_dot(const PipelinePlan& plan);
std::string pipeline_plan_to_text(const PipelinePlan& plan);

}  // namespace crex
