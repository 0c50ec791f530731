/// \file run_inputs.h
/// What a run (or `crex check`, `crex plan`) reads: files or standard input, scenes, pipeline
/// files compiled for their scene, and a run's plan with its scene: a crex, a pipeline file or a
/// plan kept by `crex plan`, always as one PipelinePlan (a crex is a plan without guidance).
/// Diagnostics go to the caller's sink; what could not be read at all (a missing file: I/O, not
/// content) is said in `failure`.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "base/diagnostic.h"
#include "compiler/compiler.h"
#include "runtime/api/run_options.h"
#include "runtime/metrics/metrics.h"
#include "runtime/scene/camera_path.h"
#include "runtime/scene/load_scene.h"

namespace crex {

/// The whole file as bytes (`-`: standard input); nullopt with `error` set if it cannot be read.
/// Bounded as base/input_file.h says (kMaxTextInputBytes).
std::optional<std::string> read_input(const std::string& path, std::string& error);
/// A pipeline argument's text: the file `arg`, or the stdlib pipeline a bare name names
/// (`sel_quiet`: compiler/pipeline/stdlib_pipelines.h), its path in `path`. A name that is
/// neither says in `error` what the stdlib has.
std::optional<std::string> read_input_or_stdlib(const std::string& arg, std::string& path, std::string& error);

/// The camera path in a file (`crex run --camera-path`): a JSON path of keys or a view file
/// (runtime/scene/camera_path_file.h), or a glTF file's camera animation.
struct CameraPathInput {
    std::optional<CameraPath> path;  ///< nullopt when the file cannot be read or has errors
    std::string text;                ///< the path as JSON or view lines, which other processes read again
    std::string error;               ///< why the file cannot be read
    std::string diagnostics;         ///< its errors and warnings, rendered (render_text)
    size_t errors = 0;
};
/// `camera` names which of a glTF file's cameras, as --camera does. The diagnostics are rendered
/// here, while the text they quote is alive.
CameraPathInput read_camera_path_input(const std::string& path, const std::string& camera, double fps);

/// What a file holds when it is not what the command reads, from its name and text: "a plan"
/// (the JSON of 'crex plan --format json'), "a profile", "a scene" (.rad, .obj, .mtl, or JSON
/// with shapes), "a RADIANCE view file", or "" when it is none of these (then the command's own
/// reader says what is wrong).
std::string input_kind(const std::string& path, const std::string& text);

/// A scene as loaded, with the texts its diagnostics point into.
struct SceneInput {
    SceneSources sources;
    std::optional<Scene> scene;
    std::string failure;  ///< set when the scene could not be read at all
};

std::unique_ptr<SceneInput> load_scene_input(const std::string& spec, DiagnosticSink& sink);

/// What the compiler plans a scene by: its census, named `spec`.
SceneFacts scene_facts(const std::string& spec, const Scene& scene);

/// A pipeline file compiled for its scene: compile_pipeline()'s passes, the scene (the
/// pipeline's, or `scene_override`) loaded between the front end and the planner.
struct PipelineInput {
    std::unique_ptr<SourceFile> source;
    PipelineCompilation compiled;
    std::unique_ptr<SceneInput> scene;  ///< null when the pipeline names no scene and none was given
    std::string scene_spec;
    std::string failure;                ///< the file or scene could not be read
};

/// A pipeline file (or a stdlib pipeline by its name alone, read_input_or_stdlib), checked,
/// resolved and planned for its scene or `scene_override`.
std::unique_ptr<PipelineInput> load_pipeline_input(const std::string& file, const std::string& pipeline_name,
                                                   const std::string& scene_override, DiagnosticSink& sink);
/// The same for a pipeline already read (`crex check` reads its files first, stdin too).
std::unique_ptr<PipelineInput> load_pipeline_input(std::unique_ptr<SourceFile> source, const std::string& pipeline_name,
                                                   const std::string& scene_override, DiagnosticSink& sink);

/// Reads a profile as `crex run --save-profile` writes it; "" or what is wrong with it.
/// `path` names it in what is said ("" : "<profile>").
std::string read_profile(const std::string& json_text, ProfileInput& out, const std::string& path = "");

inline constexpr const char* kDefaultCrex = "(TTMRSGD)*";

/// Where a run's plan and scene come from.
struct InputSpec {
    std::string file;                 ///< a pipeline (.pipe) or a kept plan (JSON); "": `crex`
    std::string crex = kDefaultCrex;  ///< without a file ("" is the empty crex: camera rays only)
    std::string scene;                ///< instead of the plan's scene (default builtin:cornell)
    std::string camera;               ///< another of the scene's named cameras (NAME or INDEX)
    std::string view;                 ///< a RADIANCE view file replacing the scene's camera (rpict -vf)
    std::string profile;              ///< a profile of cost per ray (`--save-profile`'s) to predict a budget from
    std::string ic_file;              ///< an irradiance cache file, read if it exists
    uint32_t star_cap = sched::kDefaultStarCap;  ///< a crex's `*` iteration cap
};

struct RunInputs {
    std::unique_ptr<SourceFile> source;  ///< the crex, pipeline or plan text diagnostics point into
    PipelinePlan plan;                   ///< `plan.staged`: a pipeline (file or kept plan), not a bare crex
    std::string scene_spec;
    std::unique_ptr<SceneInput> scene;
    std::unique_ptr<SourceFile> view_source;  ///< the view file (diagnostics point into it)
    double load_seconds = 0;                  ///< reading the scene
    std::string failure;                      ///< what could not be read at all ("": nothing)
    bool failure_in_content = false;          ///< `failure` is what a file says (a malformed profile), not reading it
    bool failure_is_usage = false;            ///< `failure` is a file given in the wrong place (a scene as the plan)
    bool planned = false;                     ///< the plan compiled (or read) without errors
    std::optional<ProfileInput> profile;      ///< the cost per ray a budget is predicted from
    std::optional<std::string> ic_file_bytes; ///< the cache file as read (the driver loads these bytes)
    /// The warnings said while reading them (the scene's, the plan's, the view's), as JSON made
    /// while the files their places point into were still there: a run's JSON summary lists
    /// them before the run's own.
    nlohmann::json load_warnings = nlohmann::json::array();
    /// The caller's verdict on them: 0, the run goes on; else why not, in the caller's terms (an
    /// exit status), said already. shared_inputs.h gives every process the lead's.
    int status = 0;
    /// The run can go: a plan and a scene, nothing failed (the sink's errors aside).
    bool ready() const { return failure.empty() && planned && scene && scene->scene; }
};

/// Reads the plan and its scene: the pipeline's scene, `spec.scene`, a kept plan's, or
/// builtin:cornell; the view applied; a kept plan checked against the scene's census (E402).
RunInputs load_run_inputs(const InputSpec& spec, DiagnosticSink& sink);

/// The reference image an error curve is measured against.
struct ReferenceInput {
    std::optional<metrics::Image> image;
    std::string path;           ///< the file it was read from
    std::string error;          ///< why there is none when one was asked for
    bool wrong_size = false;    ///< `error` says the image is not the render's size (the input's fault)
    bool not_finite = false;    ///< `error` says it holds NaN or Inf (the input's fault)
};

/// `spec` a path, or "auto" for the cached `crex reference` of `scene` at this size
/// (runtime/report/reference_cache.h); "" too, but then no cached one is no error.
ReferenceInput load_reference(const std::string& spec, const Scene& scene, const std::string& scene_spec, int width, int height);

}  // namespace crex
