#include "runtime/api/run_inputs.h"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <chrono>
#include <filesystem>

#include "base/input_file.h"
#include "base/render_json.h"
#include "base/render_text.h"
#include "compiler/pipeline/stdlib_pipelines.h"
#include "runtime/io/image_io.h"
#include "runtime/report/reference_cache.h"
#include "runtime/scene/camera_path_file.h"
#include "runtime/scene/census.h"
#include "runtime/scene/gltf/gltf_camera_path.h"
#include "runtime/scene/load_scene.h"
#include "runtime/scene/model_defaults.h"
#include "runtime/scene/radiance_view.h"
#include "runtime/base/file_extension.h"

namespace crex {

std::optional<std::string> read_input(const std::string& path, std::string& error) { return read_input_file(path, error, kMaxTextInputBytes); }

CameraPathInput read_camera_path_input(const std::string& path, const std::string& camera, double fps) {
    CameraPathInput out;
    std::optional<std::string> read = read_input(path, out.error);
    if (!read) return out;
    DiagnosticSink sink;
    SceneSources sources;  // a glTF's, quoted by its diagnostics
    if (is_gltf_path(path)) read = gltf_camera_path_json(path, camera, sources, sink);  // its camera's animation, as a path of keys
    std::optional<SourceFile> file;  // alive until its diagnostics are rendered
    if (read) {
        out.text = *read;
        file.emplace(path, std::move(*read));
        out.path = read_camera_path(*file, fps, sink);
    }
    out.diagnostics = render_text(sink.sorted());
    out.errors = sink.error_count();
    if (out.errors > 0) out.path.reset();
    return out;
}

std::optional<std::string> read_input_or_stdlib(const std::string& arg, std::string& path, std::string& error) {
    const pipeline::PipelineArgument argument = pipeline::pipeline_argument(arg);
    path = argument.path;
    auto text = read_input(path, error);
    if (!text && !argument.hint.empty()) error += "; " + argument.hint;
    return text;
}

std::string input_kind(const std::string& path, const std::string& text) {
    const std::string ext = lower_extension(path);
    if (ext == ".rad" || ext == ".obj" || ext == ".mtl") return "a scene";
    if (ext == ".vf") return "a RADIANCE view file";
    const size_t first = text.find_first_not_of(" \t\r\n");
    if (first == std::string::npos || text[first] != '{') return "";
    const auto j = nlohmann::json::parse(text, nullptr, false);
    if (!j.is_object()) return "";
    if (j.contains("format") && j["format"] == "crex-plan") return "a plan";
    if (j.contains("format") && j["format"] == "crex-profile") return "a profile";
    if (j.contains("shapes") || j.contains("materials")) return "a scene";
    return "";
}

std::unique_ptr<SceneInput> load_scene_input(const std::string& spec, DiagnosticSink& sink) {
    auto in = std::make_unique<SceneInput>();
    SceneLoadFailure failure;
    in->scene = load_scene(spec, in->sources, sink, failure);
    in->failure = failure.message;
    return in;
}

SceneFacts scene_facts(const std::string& spec, const Scene& scene) {
    const Census census = take_census(scene);
    return {spec, census_hash_hex(census.hash), census.spawnable, census.tags, census.has_medium};
}

std::unique_ptr<PipelineInput> load_pipeline_input(const std::string& file, const std::string& pipeline_name,
                                                   const std::string& scene_override, DiagnosticSink& sink) {
    std::string path, error;
    auto text = read_input_or_stdlib(file, path, error);
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
    in->compiled = compile_pipeline_front_end(*in->source, pipeline_name, sink);
    if (!in->compiled.resolved) return in;
    in->scene_spec = scene_override;
    std::optional<NamedScene> named;  // where the pipeline names its scene
    if (in->scene_spec.empty())
        if ((named = pipeline_scene(*in->compiled.resolved, path))) in->scene_spec = named->spec;
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
    plan_for_scene(in->compiled, facts ? &*facts : nullptr, sink);
    return in;
}

std::string read_profile(const std::string& json_text, ProfileInput& out, const std::string& path) {
    out.path = path;
    return Profile::from_json_text(json_text, out.profile, &out.full_render_seconds, path.empty() ? "<profile>" : path, &out.stages);
}

namespace {

bool is_pipeline_file(const std::string& path) { return path.size() > 5 && path.substr(path.size() - 5) == ".pipe"; }

RunInputs read_run_inputs(const InputSpec& spec, DiagnosticSink& sink) {
    RunInputs in;
    std::string expected_census;
    in.scene_spec = spec.scene;
    const pipeline::PipelineArgument argument = pipeline::pipeline_argument(spec.file);  // a stdlib pipeline by name too
    if (is_pipeline_file(argument.path)) {
        auto pipe = load_pipeline_input(argument.path, "", spec.scene, sink);
        in.source = std::move(pipe->source);
        in.scene = std::move(pipe->scene);
        if (!pipe->failure.empty()) {
            in.failure = pipe->failure;
            return in;
        }
        if (pipe->compiled.plan) {
            in.plan = std::move(*pipe->compiled.plan);
            in.planned = true;
            in.scene_spec = pipe->scene_spec;
        }
    } else if (!spec.file.empty()) {
        std::string path, read_error;
        auto text = read_input_or_stdlib(spec.file, path, read_error);  // a name that is no file: what the stdlib has
        if (!text) {
            in.failure = read_error;
            return in;
        }
        // A scene given as the plan (`crex run scene.rad`) was read as a plan: "E401 malformed JSON".
        if (const std::string kind = input_kind(spec.file, *text); !kind.empty() && kind != "a plan") {
            in.failure = fmt::format("{} is {}, not a plan or a pipeline: {}", spec.file, kind,
                                     kind == "a scene"     ? fmt::format("render it with --scene {} (and -e CREX or a pipeline file)", spec.file)
                                     : kind == "a profile" ? fmt::format("pass it as --profile {}", spec.file)
                                                           : fmt::format("pass it as --view {}", spec.file));
            in.failure_is_usage = true;
            return in;
        }
        in.source = std::make_unique<SourceFile>(spec.file, std::move(*text));
        if (auto kept = read_plan(*in.source, sink)) {
            in.planned = true;
            in.plan.program = kept->program;
            if (kept->pipeline) in.plan = std::move(*kept->pipeline);
            if (in.scene_spec.empty()) in.scene_spec = kept->scene;
            expected_census = kept->census_hash;
        }
    } else {
        in.source = std::make_unique<SourceFile>("<crex>", spec.crex);
        LowerOptions lower;
        lower.star_cap = spec.star_cap;
        if (auto program = compile_crex(*in.source, sink, lower).program) in.plan.program = *program, in.planned = true;
    }
    if (in.scene_spec.empty()) in.scene_spec = "builtin:cornell";

    const auto t_load = std::chrono::steady_clock::now();
    if (!in.scene) in.scene = load_scene_input(in.scene_spec, sink);
    in.load_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_load).count();
    if (!in.scene->failure.empty()) {
        in.failure = in.scene->failure;
        return in;
    }
    std::optional<Scene>& scene = in.scene->scene;
    // Another of the scene's cameras (a view file may still replace it).
    if (!spec.camera.empty() && scene)
        if (std::string error = select_camera(*scene, spec.camera); !error.empty()) {
            in.failure = error;
            in.failure_is_usage = true;
            return in;
        }
    // A view file: RADIANCE's view options replace the scene's camera (rpict -vf).
    if (!spec.view.empty() && scene) {
        std::string view_error;
        auto text = read_input(spec.view, view_error);
        if (!text) {
            in.failure = "the view file: " + view_error;
            return in;
        }
        in.view_source = std::make_unique<SourceFile>(spec.view, std::move(*text));
        sink.withdraw("W305");  // the scene's missing view: this one replaces it
        apply_radiance_view(*in.view_source, view_file_words(*in.view_source), scene->camera, true, sink);
    }
    if ((!spec.camera.empty() || in.view_source) && scene) aim_studio_key(*scene);
    // The loader checked the scene's own camera; one chosen or given here is checked alike.
    if ((!spec.camera.empty() || in.view_source) && scene)
        if (std::string problem = camera_problem(scene->camera, scene_box(*scene)); !problem.empty()) {
            if (in.view_source) {
                const SourceSpan first_line{in.view_source.get(), 0, static_cast<uint32_t>(in.view_source->line_text(1).size())};
                sink.report("E303", first_line, "view: the camera is " + problem);
            } else {
                in.failure = fmt::format("--camera {}: the camera is {}", spec.camera, problem);
                in.failure_in_content = true;
                return in;
            }
        }
    if (!spec.profile.empty()) {
        std::string error;
        auto text = read_input(spec.profile, error);
        if (!text) {
            in.failure = "--profile: " + error;
            return in;
        }
        ProfileInput profile;
        if (error = read_profile(*text, profile, spec.profile); !error.empty()) {
            in.failure = "profile " + error;  // located in the file: "profile p.json:3:26: ..."
            in.failure_in_content = true;
            return in;
        }
        in.profile = std::move(profile);
    }
    if (std::error_code ec; !spec.ic_file.empty() && std::filesystem::exists(spec.ic_file, ec)) {
        std::string error;
        in.ic_file_bytes = read_input_file(spec.ic_file, error, kMaxDataInputBytes);
        if (!in.ic_file_bytes) {
            // A directory or a device there is said now, not as "basic_filebuf::underflow error
            // reading the file" after the render.
            in.failure = fmt::format("--ic-file: {}{}", error,
                                     std::filesystem::is_directory(spec.ic_file, ec)
                                         ? fmt::format("; it names the cache's file (made if missing), e.g. {}/scene.ic", spec.ic_file)
                                         : "");
            return in;
        }
    }
    // A plan is only valid for a scene with the census it was made for (spec 5).
    if (scene && !expected_census.empty()) {
        const std::string actual = census_hash_hex(take_census(*scene).hash);
        if (actual != expected_census)
            sink.report("E402", {in.source.get(), 0, 0},
                        fmt::format("the plan was made for a scene with census {}, but {} has census {}", expected_census,
                                    in.scene_spec, actual))
                .help = "plan again for this scene: crex plan -e '...' --scene " + in.scene_spec;
    }
    return in;
}

}  // namespace

RunInputs load_run_inputs(const InputSpec& spec, DiagnosticSink& sink) {
    RunInputs in = read_run_inputs(spec, sink);
    for (const Diagnostic& d : sink.sorted())
        if (d.severity == Severity::kWarning) in.load_warnings.push_back(to_json(d));
    return in;
}

ReferenceInput load_reference(const std::string& spec, const Scene& scene, const std::string& scene_spec, int width, int height) {
    ReferenceInput ref;
    const bool automatic = spec.empty() || spec == "auto";
    ref.path = spec;
    if (automatic) {
        ReferenceSettings settings;
        settings.width = width, settings.height = height;
        ref.path = find_cached_reference(scene, settings);
        if (ref.path.empty()) {
            if (spec == "auto")
                ref.error = fmt::format("no cached reference of {} at {}x{}: make one with 'crex reference {} --size {}x{}'", scene_spec, width,
                                        height, scene_spec, width, height);
            return ref;
        }
    }
    metrics::Image img;
    if (std::string error = read_image(ref.path, img.width, img.height, img.rgb); !error.empty()) {
        ref.error = "reference: " + error;
        return ref;
    }
    // NaN or Inf would make the error curve 'nan' and perr 100 % with exit 0, where `crex
    // compare` refuses the same image.
    size_t bad = 0;
    for (float v : img.rgb) bad += !std::isfinite(v);
    if (bad > 0) {
        ref.error = fmt::format("the reference {} holds {} non-finite value{} (NaN or Inf): no error can be measured against it{}", ref.path,
                                bad, bad == 1 ? "" : "s",
                                automatic ? fmt::format("; render it again with 'crex reference {} --size {}x{} --force'", scene_spec, width,
                                                        height)
                                          : "");
        ref.not_finite = true;
        return ref;
    }
    if (img.width != width || img.height != height) {
        ref.error = fmt::format("the reference {} is {}x{} but the render is {}x{}", ref.path, img.width, img.height, width, height);
        ref.wrong_size = true;
        return ref;
    }
    ref.image = std::move(img);
    return ref;
}

}  // namespace crex
