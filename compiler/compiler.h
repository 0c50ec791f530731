/// \file compiler.h
/// The compiler's public API, one header for the layer: source text to an execution plan, the
/// shape of Mitsuba's parse -> instantiate and Halide's lowering passes. Every pass is a named
/// free function, run by compile_pipeline() in this order:
///   1. parse_pipeline_file   (compiler/pipeline/parse.h)     text -> syntax tree
///   2. check_pipeline_file   (compiler/pipeline/check.h)     names, types, ranges: E2xx, W2xx
///   3. resolve_pipeline      (compiler/pipeline/resolve.h)   `extends` applied
///   4. lower_stages          (compiler/plan/plan_pipeline.h) both stages' crex lowered, settings typed
///   5. prune_steps_for_scene                                 steps the scene's materials never feed
///   6. prune_variables                                       variables left without their step
///   7. mark_live_maps                                        maps nothing left consumes
///   8. build_plan_graph                                      typed maps, variables, outputs; the graph
///   9. warn_*                (compiler/plan/pipeline_warnings.h) what the scene cannot give: W203-W206, W403
/// A crex alone goes through compile_crex() (parse, check, lower) and plan_crex(). Plans kept as
/// JSON are written by pipeline_plan_to_json() / plan_to_json() and read back by read_plan().
/// The compiler knows a scene only by its census (SceneFacts); loading scenes is the runtime's
/// (runtime/runtime.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "compiler/crex/compile.h"
#include "compiler/pipeline/ast.h"
#include "compiler/pipeline/resolve.h"
#include "compiler/plan/bin_occupancy.h"
#include "compiler/plan/emit_plan.h"
#include "compiler/plan/pipeline_plan.h"
#include "compiler/plan/plan_pipeline.h"
#include "compiler/plan/read_plan.h"

namespace crex {

/// What the compiler knows of a scene: its census (runtime/scene/census.h takes it).
struct SceneFacts {
    std::string spec;               ///< the scene as named (recorded in the plan)
    std::string census_hash;        ///< 16 hex digits: a plan runs only on a scene with this census
    BinSet spawnable;               ///< the bins some material of the scene can fill
    std::vector<std::string> tags;  ///< names of tagged objects
    bool has_medium = false;
};

/// A pipeline file as far as compile_pipeline() got: each field is set once its pass ran.
struct PipelineCompilation {
    std::optional<pipeline::ast::File> ast;              ///< passes 1-2 (checked unless the sink has errors)
    std::optional<pipeline::ResolvedPipeline> resolved;  ///< pass 3
    std::optional<PipelinePlan> plan;                    ///< passes 4-9
};

/// Passes 1-3. `pipeline_name` "": the file's last pipeline (E210 when the file has none).
PipelineCompilation compile_pipeline_front_end(const SourceFile& source, const std::string& pipeline_name, DiagnosticSink& sink);

/// The scene a resolved pipeline names (`scene "..."`): as written when it exists from here,
/// else relative to the pipeline file's folder or a folder above it; nullopt when it names none.
struct NamedScene {
    std::string spec;
    SourceSpan where;
};
std::optional<NamedScene> pipeline_scene(const pipeline::ResolvedPipeline& pipeline, const std::string& pipeline_path);

/// Passes 4-9 on a front end's result. `scene` null: planned without pruning and without the
/// warnings that need a scene.
void plan_for_scene(PipelineCompilation& compilation, const SceneFacts* scene, DiagnosticSink& sink);

/// Passes 1-9: `source` (a pipeline file) planned for `scene` (null: for no scene in particular).
PipelineCompilation compile_pipeline(const SourceFile& source, const SceneFacts* scene, DiagnosticSink& sink,
                                     const std::string& pipeline_name = "");

/// A crex compiled by compile_crex(), as the plan `crex plan -e` keeps: for a scene, its steps
/// that can never have work removed and listed.
CrexPlan plan_crex(const std::string& source, const CompiledCrex& compiled, const SceneFacts* scene);

}  // namespace crex
