/// \file plan_helpers.h
/// Plans a pipeline file from text for tests (and the golden snapshots).
#pragma once

#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "compiler/pipeline/check.h"
#include "compiler/pipeline/parse.h"
#include "compiler/pipeline/resolve.h"
#include "compiler/plan/pipeline_warnings.h"
#include "compiler/plan/plan_pipeline.h"
#include "runtime/scene/census.h"
#include "runtime/scene/load_scene.h"

namespace crex::testing {

inline std::string read_text(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

struct PlannedPipeline {
    std::unique_ptr<SourceFile> file;
    std::optional<PipelinePlan> plan;
    std::vector<Diagnostic> diagnostics;
};

/// `name` is how the file is called in positions (keep it relative: plans are goldens).
/// `tags` given: also the scene-aware warnings (W203, W204) for a scene with those tags, W205 and W206.
inline PlannedPipeline plan_text(const std::string& name, const std::string& text, const std::optional<BinSet>& spawnable,
                                 const std::string& scene = "", const std::string& hash = "",
                                 const std::vector<std::string>* tags = nullptr) {
    PlannedPipeline r;
    r.file = std::make_unique<SourceFile>(name, text);
    DiagnosticSink sink;
    auto ast = pipeline::parse_pipeline_file(*r.file, sink);
    if (ast) pipeline::check_pipeline_file(*ast, sink);
    if (ast && !sink.has_errors())
        if (auto resolved = pipeline::resolve_pipeline(*ast, "", sink))
            if ((r.plan = plan_pipeline(*resolved, spawnable, scene, hash, sink)) && tags) {
                warn_scene_mismatches(*resolved, *r.plan, tags, sink);
                warn_unreachable_modulated_steps(*resolved, *r.plan, sink);
                warn_noise_of_one_sample(*resolved, *r.plan, sink);
            }
    r.diagnostics = sink.sorted();
    return r;
}

}  // namespace crex::testing
