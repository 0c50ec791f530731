/// \file pipeline_plan.h
/// A pipeline's execution plan as plain data (spec/pipeline.md §3): the two stages'
/// programs and the typed graph of camera rays, buffers, guidance operators, selective
/// variables, cache, composite and outputs. The planner writes it, `crex run` reads it back
/// from JSON, and the runtime executes it; nothing here needs the parser.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "compiler/sched/program.h"

namespace crex {

struct PlanNode {
    std::string id, kind, stage, label;
    nlohmann::json params = nlohmann::json::object();
};

struct PlanEdge {
    std::string from, to, kind, label;
};

struct PlanRemoval {
    std::string what, at, reason;
};

struct PipelinePlan {
    std::string name;
    std::vector<std::string> chain;
    std::string scene;
    std::string census_hash;
    nlohmann::json settings = nlohmann::json::object();
    sched::Program program;  ///< .preselective / .selective: the two stages' programs
    std::vector<PlanNode> nodes;
    std::vector<PlanEdge> edges;
    std::vector<PlanRemoval> pruned;
};

/// The edges into `id`, in the order they were added (= argument order of a call).
inline std::vector<const PlanEdge*> edges_into(const PipelinePlan& plan, const std::string& id) {
    std::vector<const PlanEdge*> out;
    for (const auto& e : plan.edges)
        if (e.to == id) out.push_back(&e);
    return out;
}

inline const PlanNode* find_node(const PipelinePlan& plan, const std::string& id) {
    for (const auto& n : plan.nodes)
        if (n.id == id) return &n;
    return nullptr;
}

}  // namespace crex
