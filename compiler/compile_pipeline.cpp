#include <fmt/format.h>

#include <filesystem>

#include "compiler/compiler.h"
#include "compiler/pipeline/check.h"
#include "compiler/pipeline/parse.h"
#include "compiler/plan/pipeline_warnings.h"

namespace crex {

PipelineCompilation compile_pipeline_front_end(const SourceFile& source, const std::string& pipeline_name, DiagnosticSink& sink) {
    PipelineCompilation c;
    c.ast = pipeline::parse_pipeline_file(source, sink);
    if (c.ast) pipeline::check_pipeline_file(*c.ast, sink);
    if (!c.ast || sink.has_errors()) return c;
    c.resolved = pipeline::resolve_pipeline(*c.ast, pipeline_name, sink);
    if (!c.resolved && !sink.has_errors())
        sink.report("E210", {&source, 0, 0},
                    pipeline_name.empty() ? "the file holds no pipeline" : fmt::format("no pipeline named '{}'", pipeline_name));
    return c;
}

std::optional<NamedScene> pipeline_scene(const pipeline::ResolvedPipeline& pipeline, const std::string& pipeline_path) {
    auto it = pipeline.top.find("scene");
    if (it == pipeline.top.end() || it->second.empty()) return std::nullopt;
    namespace fs = std::filesystem;
    const std::string& scene = it->second[0].text;
    NamedScene named{scene, it->second[0].span};
    std::error_code ec;
    if (scene.rfind("builtin:", 0) == 0 || fs::path(scene).is_absolute() || fs::exists(scene, ec)) return named;
    // The spec's example names a path from the project root: look in the pipeline's folder and above.
    for (fs::path dir = fs::absolute(pipeline_path, ec).parent_path(); !dir.empty(); dir = dir.parent_path()) {
        if (fs::exists(dir / scene, ec)) {
            named.spec = (dir / scene).lexically_normal().string();
            break;
        }
        if (dir == dir.root_path()) break;
    }
    return named;  // not found: the loader says so, naming the path as written
}

void plan_for_scene(PipelineCompilation& c, const SceneFacts* scene, DiagnosticSink& sink) {
    if (!c.resolved) return;
    std::optional<BinSet> spawnable;
    if (scene) spawnable = scene->spawnable;
    c.plan = plan_pipeline(*c.resolved, spawnable, scene ? scene->spec : "", scene ? scene->census_hash : "", sink);
    if (!c.plan) return;
    warn_scene_mismatches(*c.resolved, *c.plan, scene ? &scene->tags : nullptr, sink);
    warn_unreachable_modulated_steps(*c.resolved, *c.plan, sink);
    warn_noise_of_one_sample(*c.resolved, *c.plan, sink);
    if (scene) warn_media_without_medium(*c.resolved, scene->has_medium, sink);
}

PipelineCompilation compile_pipeline(const SourceFile& source, const SceneFacts* scene, DiagnosticSink& sink,
                                     const std::string& pipeline_name) {
    PipelineCompilation c = compile_pipeline_front_end(source, pipeline_name, sink);
    plan_for_scene(c, scene, sink);
    return c;
}

CrexPlan plan_crex(const std::string& source, const CompiledCrex& compiled, const SceneFacts* scene) {
    CrexPlan plan;
    plan.source = source;
    plan.where = SourceLocation::of(compiled.span);
    if (compiled.program) plan.program = *compiled.program;
    if (scene) {
        plan.pruned = find_dead_steps(plan.program, scene->spawnable);
        plan.program = prune_dead_steps(plan.program, scene->spawnable);
        plan.scene = scene->spec;
        plan.census_hash = scene->census_hash;
    }
    return plan;
}

}  // namespace crex
