#include "apps/crex/pipeline_input.h"

#include <fmt/format.h>

#include <filesystem>

#include "base/render_text.h"
#include "apps/crex/input_files.h"
#include "compiler/pipeline/check.h"
#include "compiler/pipeline/parse.h"
#include "compiler/plan/pipeline_warnings.h"
#include "runtime/scene/census.h"

namespace crex::app {
namespace {

// A pipeline's `scene "..."` as written if it exists from here; else relative to the pipeline
// file's folder or any folder above it (the spec's example names a path from the project root).
std::string resolve_scene_path(const std::string& scene, const std::string& pipeline_path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (scene.rfind("builtin:", 0) == 0 || fs::path(scene).is_absolute() || fs::exists(scene, ec)) return scene;
    for (fs::path dir = fs::absolute(pipeline_path, ec).parent_path(); !dir.empty(); dir = dir.parent_path()) {
        if (fs::exists(dir / scene, ec)) return (dir / scene).lexically_normal().string();
        if (dir == dir.root_path()) break;
    }
    return scene;  // not found: the loader says so, naming the path as written
}

}  // namespace

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
    in->ast = pipeline::parse_pipeline_file(*in->source, sink);
    if (in->ast) pipeline::check_pipeline_file(*in->ast, sink);
    if (!in->ast || sink.has_errors()) return in;
    in->resolved = pipeline::resolve_pipeline(*in->ast, pipeline_name, sink);
    if (!in->resolved) {
        if (!sink.has_errors())
            sink.report("E210", {in->source.get(), 0, 0},
                        pipeline_name.empty() ? "the file holds no pipeline" : fmt::format("no pipeline named '{}'", pipeline_name));
        return in;
    }
    in->scene_spec = scene_override;
    std::optional<SourceSpan> scene_span;  // where the pipeline names its scene
    if (in->scene_spec.empty())
        if (auto it = in->resolved->top.find("scene"); it != in->resolved->top.end() && !it->second.empty()) {
            in->scene_spec = resolve_scene_path(it->second[0].text, path);
            scene_span = it->second[0].span;
        }
    std::optional<BinSet> spawnable;
    std::optional<std::vector<std::string>> tags;
    bool has_medium = false;
    std::string hash;
    if (!in->scene_spec.empty()) {
        in->scene = load_scene_input(in->scene_spec, sink);
        if (!in->scene->failure.empty()) {
            // Said at the pipeline's `scene` line when the scene came from there.
            in->failure = scene_span ? fmt::format("{}: {} (the pipeline's scene)", format_location(*scene_span), in->scene->failure)
                                     : in->scene->failure;
            return in;
        }
        if (!in->scene->scene) return in;
        Census census = take_census(*in->scene->scene);
        spawnable = census.spawnable;
        tags = census.tags;
        has_medium = census.has_medium;
        hash = census_hash_hex(census.hash);
    }
    in->plan = plan_pipeline(*in->resolved, spawnable, in->scene_spec, hash, sink);
    if (in->plan) {
        warn_scene_mismatches(*in->resolved, *in->plan, tags ? &*tags : nullptr, sink);
        warn_unreachable_modulated_steps(*in->resolved, *in->plan, sink);
        warn_noise_of_one_sample(*in->resolved, *in->plan, sink);
        if (tags) warn_media_without_medium(*in->resolved, has_medium, sink);
    }
    return in;
}

}  // namespace crex::app
