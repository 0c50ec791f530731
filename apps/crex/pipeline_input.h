/// \file pipeline_input.h
/// A pipeline file for `crex plan` and `crex run`: parse, check, resolve `extends`, load its
/// scene (or the one given), and plan it.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "apps/crex/scene_input.h"
#include "compiler/pipeline/resolve.h"
#include "compiler/plan/plan_pipeline.h"

namespace crex::app {

struct PipelineInput {
    std::unique_ptr<SourceFile> source;
    std::optional<pipeline::ast::File> ast;   ///< as parsed (checked unless the sink has errors)
    std::optional<pipeline::ResolvedPipeline> resolved;
    std::unique_ptr<SceneInput> scene;  ///< null when the pipeline names no scene and none was given
    std::string scene_spec;
    std::optional<PipelinePlan> plan;
    std::string failure;                ///< I/O: the file or scene could not be read (exit 3)
};

std::unique_ptr<PipelineInput> load_pipeline_input(const std::string& path, const std::string& pipeline_name,
                                                   const std::string& scene_override, DiagnosticSink& sink);
/// The same for a pipeline already read (`crex check` reads its files first, stdin too).
std::unique_ptr<PipelineInput> load_pipeline_input(std::unique_ptr<SourceFile> source, const std::string& pipeline_name,
                                                   const std::string& scene_override, DiagnosticSink& sink);

}  // namespace crex::app
