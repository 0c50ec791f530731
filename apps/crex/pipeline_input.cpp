#include "apps/crex/pipeline_input.h"

#include <fmt/format.h>

#include "apps/crex/input_files.h"
#include "compiler/pipeline/check.h"
#include "compiler/pipeline/parse.h"
#include "runtime/scene/census.h"

namespace crex::app {

std::unique_ptr<PipelineInput> load_pipeline_input(const std::string& path, const std::string& pipeline_name,
                                                   const std::string& scene_override, DiagnosticSink& sink) {
    auto in = std::make_unique<PipelineInput>();
    std::string error;
    auto text = read_input(path, error);
    if (!text) {
        in->failure = error;
        return in;
    }
    in->source = std::make_unique<SourceFile>(path, std::move(*text));
    auto ast = pipeline::parse_pipeline_file(*in->source, sink);
    if (ast) pipeline::check_pipeline_file(*ast, sink);
    if (!ast || sink.has_errors()) return in;
    in->resolved = pipeline::resolve_pipeline(*ast, pipeline_name, sink);
    if (!in->resolved) {
        if (!sink.has_errors())
            sink.report("E210", {in->source.get(), 0, 0},
                        pipeline_name.empty() ? "the file holds no pipeline" : fmt::format("no pipeline named '{}'", pipeline_name));
        return in;
    }
    in->scene_spec = scene_override;
    if (in->scene_spec.empty())
        if (auto it = in->resolved->top.find("scene"); it != in->resolved->top.end() && !it->second.empty())
            in->scene_spec = it->second[0].text;
    std::optional<BinSet> spawnable;
    std::string hash;
    if (!in->scene_spec.empty()) {
        in->scene = load_scene_input(in->scene_spec, sink);
        if (!in->scene->failure.empty()) {
            in->failure = in->scene->failure;
            return in;
        }
        if (!in->scene->scene) return in;
        Census census = take_census(*in->scene->scene);
        spawnable = census.spawnable;
        hash = census_hash_hex(census.hash);
    }
    in->plan = plan_pipeline(*in->resolved, spawnable, in->scene_spec, hash, sink);
    return in;
}

}  // namespace crex::app
