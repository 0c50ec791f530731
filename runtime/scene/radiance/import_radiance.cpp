// RADIANCE scene description (.rad) -> Scene: the text read as RADIANCE reads it
// (scene_text), its commands carried out natively (expand), and the primitives turned into
// crex's model (scene_builder); then the camera from the view file and the checks every
// format's scenes get.
#include <fmt/format.h>

#include "runtime/scene/load_scene.h"
#include "runtime/scene/radiance/expand.h"
#include <filesystem>
#include <fstream>
#include <sstream>

#include "runtime/scene/radiance/rif.h"
#include "runtime/scene/radiance/scene_builder.h"
#include "runtime/scene/radiance_view.h"

namespace crex {
namespace {

// What every RADIANCE scene gets once it is read: the checks of every format.
std::optional<Scene> checked(Scene scene, const radiance::SceneBuilder& builder, const SourceFile& file, size_t errors_before,
                             DiagnosticSink& sink) {
    if (sink.error_count() != errors_before) return std::nullopt;
    const auto& spans = builder.shape_spans();
    validate_scene(scene, sink, [&](size_t i) { return i < spans.size() ? spans[i] : SourceSpan{&file, 0, 0}; });
    if (sink.error_count() != errors_before) return std::nullopt;
    scene.source = file.name();
    return scene;
}

}  // namespace

std::optional<Scene> import_radiance(const SourceFile& file, const SourceFile* view_file, SceneSources& sources,
                                     const RadianceOptions& options, DiagnosticSink& sink) {
    const size_t errors_before = sink.error_count();
    Scene scene;
    radiance::SceneBuilder builder(scene, options.library_dirs, sink);
    radiance::expand_scene(file, sources, {options.library_dirs}, builder, sink);
    builder.finish();
    if (view_file) apply_radiance_view(*view_file, view_file_words(*view_file), scene.camera, !builder.view_seen(), sink);
    return checked(std::move(scene), builder, file, errors_before, sink);
}

std::optional<Scene> import_radiance_project(const SourceFile& rif, SceneSources& sources, const RadianceOptions& options,
                                             DiagnosticSink& sink) {
    const size_t errors_before = sink.error_count();
    radiance::RifProject project = radiance::read_rif(rif, sink);
    Scene scene;
    radiance::SceneBuilder builder(scene, options.library_dirs, sink);
    radiance::expand_project(project, rif, sources, {options.library_dirs}, builder, sink);
    builder.finish();
    // The first view: `-vf FILE` reads the file (from the project's directory) first, the
    // options around it then apply on top, as rad composes them.
    bool fresh = !builder.view_seen();
    std::vector<ViewWord> rest;
    for (size_t i = 0; i < project.view.size(); ++i) {
        if (project.view[i].text != "-vf" || i + 1 >= project.view.size()) {
            rest.push_back(project.view[i]);
            continue;
        }
        const ViewWord& name = project.view[++i];
        std::filesystem::path path = std::filesystem::path(rif.name()).parent_path() / name.text;
        std::ifstream in(path);
        if (!in) {
            sink.report("E308", {&rif, name.begin, name.end}, fmt::format("view: cannot read the view file '{}'", name.text));
            continue;
        }
        std::stringstream text;
        text << in.rdbuf();
        const SourceFile& vf = sources.add(path.string(), text.str());
        apply_radiance_view(vf, view_file_words(vf), scene.camera, fresh, sink);
        fresh = false;
    }
    if (!rest.empty()) apply_radiance_view(rif, rest, scene.camera, fresh, sink);
    scene.back_faces_visible = project.back_faces_visible;
    return checked(std::move(scene), builder, rif, errors_before, sink);
}

std::optional<Scene> import_radiance(const SourceFile& file, SceneSources& sources, DiagnosticSink& sink) {
    return import_radiance(file, nullptr, sources, {}, sink);
}

}  // namespace crex
