/// \file emit_plan.h
/// A lowered, scene-pruned crex as a plan: JSON (versioned, keys sorted, no addresses or
/// timings: the same input gives byte-identical output) and Graphviz DOT (one cluster per
/// stage, a cluster per group, steps in execution order, repeat loops as back edges labelled
/// with their count, pruned steps drawn dashed with their reason).
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "compiler/plan/bin_occupancy.h"
#include "compiler/plan/pipeline_plan.h"
#include "compiler/sched/program.h"

namespace crex {

struct CrexPlan {
    std::string source;          ///< the crex as written
    SourceLocation where;        ///< where it was written
    sched::Program program;      ///< after pruning
    std::vector<DeadStep> pruned;
    std::string scene;           ///< scene spec, "" when planned without a scene
    std::string census_hash;     ///< 16 hex digits, "" without a scene
    std::optional<PipelinePlan> pipeline;         ///< a pipeline's plan read back: settings, variables, graph
};

/// 2: typed settings, outputs, variables and node parameters (numbers, radians, registry names).
inline constexpr int kPlanFormatVersion = 2;

nlohmann::json plan_to_json(const CrexPlan& plan);
std::string plan_to_dot(const CrexPlan& plan);
std::string plan_to_text(const CrexPlan& plan);

}  // namespace crex
