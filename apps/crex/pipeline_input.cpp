#include "apps/crex/pipeline_input.h"

#include <fmt/format.h>

#include "apps/crex/input_files.h"
#include "base/render_text.h"
#include "compiler/compiler.h"

namespace crex::app {

std::unique_ptr<PipelineInput> load_pipeline_input(const std::string& path, const std::string& pipeline_name,
                                                   const std::string& scene_override, DiagnosticSink& sink) {
    std::string error;
    auto text = read_input(path, error);
    if (!text) {
        auto in = std::make_unique<PipelineInput>();
        in->failure = error;
        return in;
    }
    return load_pipeline_input(std::make_unique<SourceFile>(path, std::move(*text)), pipeline_name, scene_override, sink);
}

std::unique_ptr<PipelineInput> load_pipeline_input(std::unique_ptr<SourceFile> source, const std::string& pipeline_name,
                                                   const std::string& scene_override, DiagnosticSink& sink) {
    auto in = std::make_unique<PipelineInput>();
    in->source = std::move(source);
    const std::string& path = in->source->name();
    PipelineCompilation c = compile_pipeline_front_end(*in->source, pipeline_name, sink);
    in->ast = std::move(c.ast);
    in->resolved = std::move(c.resolved);
    if (!in->resolved) return in;
    in->scene_spec = scene_override;
    std::optional<NamedScene> named;  // where the pipeline names its scene
    if (in->scene_spec.empty())
        if ((named = pipeline_scene(*in->resolved, path))) in->scene_spec = named->spec;
    std::optional<SceneFacts> facts;
    if (!in->scene_spec.empty()) {
        in->scene = load_scene_input(in->scene_spec, sink);
        if (!in->scene->failure.empty()) {
            // Said at the pipeline's `scene` line when the scene came from there.
            in->failure = named ? fmt::format("{}: {} (the pipeline's scene)", format_location(named->where), in->scene->failure)
                                : in->scene->failure;
            return in;
        }
        if (!in->scene->scene) return in;
        facts = scene_facts(in->scene_spec, *in->scene->scene);
    }
    c.resolved = in->resolved;
    plan_for_scene(c, facts ? &*facts : nullptr, sink);
    in->plan = std::move(c.plan);
    return in;
}

}  // namespace crex::app
