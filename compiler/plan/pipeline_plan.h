/// \file pipeline_plan.h
/// A pipeline's execution plan as plain, typed data (spec/pipeline.md §3): the settings with
/// units resolved by the compiler, the two stages' programs, the selective variables, the map
/// modulating `{ }`, the outputs, and the graph of camera rays, buffers, guidance operators,
/// selective variables, cache, composite and outputs. The planner writes it, `crex run` reads
/// it back from JSON (read_plan.cpp validates every field), and the runtime executes it without
/// parsing any text: numbers are numbers (angles in radians), names are registry enums.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "base/source.h"
#include "compiler/pipeline/registry.h"
#include "compiler/pipeline/settings_table.h"
#include "compiler/sched/program.h"

namespace crex {

/// `budget N s | N ms | N %`: seconds (ms resolved), or a share of a profiled full render.
struct PlanBudget {
    double amount = 0;
    bool percent = false;
    /// Where the pipeline says it (a runtime error about it points there); unknown in a kept plan.
    SourceLocation where;
};

/// The pipeline's settings (compiler/pipeline/settings_table.h gives their ranges); unset ones
/// leave the choice to `crex run`'s flags and defaults.
struct PlanSettings {
    std::optional<int> width, height;        ///< `image W x H`: both or neither
    uint32_t spp = 1;                        ///< pre-selective camera samples per pixel
    std::optional<uint32_t> selective_spp;   ///< `selective { spp N }`: every pixel's floor
    std::optional<uint32_t> rounds;          ///< `selective { rounds N }`: guidance and selective N times
    std::optional<uint64_t> seed;
    std::optional<double> lw, av, aa;
    std::optional<uint32_t> max_depth, ab, ad;
    /// `preselective { shadow_rays N }`: shadow rays per hit where `vary shadow_rays` does not say
    std::optional<uint32_t> shadow_rays;
    std::optional<PlanBudget> budget;
    std::optional<pipeline::SchedulingPolicy> policy;
    std::string reference;                   ///< "" when none
    /// Where the pipeline sets the limits whose light left out W404 names (unknown: not set, or
    /// a kept plan).
    SourceLocation lw_at, max_depth_at, ab_at;
};

/// The `output` section.
struct PlanOutputs {
    std::vector<std::string> images;
    bool components = false, maps = false;
    std::string report;                      ///< report directory, "" when none
};

/// `vary VARIABLE FROM .. TO by MAP using MODULATION`.
struct PlanVariable {
    pipeline::SelectiveVariable variable = pipeline::SelectiveVariable::kSpp;
    double from = 0, to = 0;
    pipeline::ModulationFunction modulation = pipeline::ModulationFunction::kLinear;
    std::string map;                         ///< id of the node giving the map
    /// `vary subsample(D) ...` (capict): the one component the variable applies to.
    std::optional<Component> component;
    /// capict: split a square again while its corners' light differs by more than this times
    /// their mean (`vary subsample(D) ... refine 0.5`).
    std::optional<double> refine;
};

/// One argument of a guidance operator: the node giving it (the preview, a buffer, a map or a
/// tagged-objects call) and, for importance(m w, ...), its weight.
struct PlanMapInput {
    std::string node;
    std::optional<double> weight;
};

/// An operator's literal parameters, typed (the registry's signature says which apply).
struct PlanMapParams {
    std::optional<double> constant;       ///< constant(v)
    std::optional<std::string> tag;       ///< tagged("name"); absent: every tagged object
    std::optional<double> fovea;          ///< task_map, distractors: radians
    std::optional<double> sigma, at;      ///< blur, threshold
    std::optional<std::string> combine;   ///< importance: "+", "max" or "*"
};

/// A map definition (`NAME = operator(...)`) or a call nested in one: what the runtime evaluates.
struct PlanMap {
    std::string id;                       ///< node id: "map.NAME", or "op.OWNER.K" for a nested call
    std::string defines;                  ///< NAME for a definition, "" for a nested call
    std::string name;                     ///< as the user wrote it: "sal = saliency(preview)"
    std::optional<pipeline::GuidanceOperator> op;  ///< absent: an alias `m = other` (one input)
    std::vector<PlanMapInput> inputs;     ///< in argument order
    PlanMapParams params;
};

/// A buffer guidance reads: "direct", "emission", "ambient", or a component letter.
struct PlanBuffer {
    std::string id;                       ///< node id: "buffer.direct", "op.OWNER.K" for component(X)
    std::string buffer;
};

/// A graph node, for the picture (DOT) and the JSON graph only: what the runtime executes is in
/// the typed fields of PipelinePlan. params holds only a crex stage's "crex".
struct PlanNode {
    std::string id, kind, stage, label;
    nlohmann::json params = nlohmann::json::object();
};

struct PlanEdge {
    std::string from, to, kind, label;
    std::optional<double> weight;            ///< importance(m w, ...): the weight of map m
};

struct PlanRemoval {
    std::string what, at, reason;
};

/// What the runtime executes, as typed fields (spec/pipeline.md §3); `nodes` and `edges` draw it.
struct PipelinePlan {
    std::string name;
    std::vector<std::string> chain;
    std::string scene;
    std::string census_hash;
    PlanSettings settings;
    PlanOutputs outputs;
    sched::Program program;  ///< .preselective / .selective: the two stages' programs
    /// A pipeline runs in stages (preview, guidance, selective: spec §1); a crex's plan (false)
    /// runs both programs in every sample pass.
    bool staged = false;
    /// D through a Ward irradiance cache (`vary ic_radius` or `vary ic_rays` with a D step left for the scene).
    bool irradiance_cache = false;
    std::vector<PlanMap> maps;               ///< live maps and nested calls, inputs before their users
    std::vector<PlanBuffer> buffers;
    std::vector<PlanVariable> variables;
    std::string modulation_map;              ///< node id of the map modulating `{ }`, "" when none
    std::vector<PlanNode> nodes;             ///< the graph: for pictures (DOT) and people (JSON) only
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

inline const PlanMap* find_map(const PipelinePlan& plan, const std::string& id) {
    for (const auto& m : plan.maps)
        if (m.id == id) return &m;
    return nullptr;
}

inline const PlanBuffer* find_buffer(const PipelinePlan& plan, const std::string& id) {
    for (const auto& b : plan.buffers)
        if (b.id == id) return &b;
    return nullptr;
}

/// The typed settings and outputs as JSON (plan format 2), and back is read_plan.cpp.
nlohmann::json plan_settings_to_json(const PlanSettings& s);
nlohmann::json plan_outputs_to_json(const PlanOutputs& o);
nlohmann::json plan_map_to_json(const PlanMap& m);

}  // namespace crex
