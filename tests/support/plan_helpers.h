/// \file plan_helpers.h
/// Plans a pipeline file from text for tests (and the golden snapshots).
#pragma once

#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "base/components.h"
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

/// The bins of component letters ("DS": diffuse and specular).
inline BinSet bins(const std::string& letters) {
    BinSet b;
    for (char c : letters) b.set(static_cast<size_t>(*component_from_letter(c)));
    return b;
}

/// The plan of pipeline `text` for `scene`; throws when it does not plan.
inline PipelinePlan plan_for(const std::string& text, const Scene& scene) {
    auto r = plan_text("test.pipe", text, take_census(scene).spawnable);
    if (!r.plan) throw std::runtime_error("pipeline does not plan: " + (r.diagnostics.empty() ? "" : r.diagnostics[0].message));
    return *r.plan;
}

}  // namespace crex::testing
