#include "runtime/scene/load_scene.h"

#include <fmt/format.h>

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "base/input_file.h"
#include "runtime/base/file_extension.h"
#include "runtime/scene/model_defaults.h"

namespace crex {
namespace {

// A scene file, bounded (base/input_file.h): "cannot read scene 'X': it is a character device".
std::optional<std::string> read_file(const std::string& path, std::string& error) {
    auto text = read_input_file(path, error, kMaxDataInputBytes);
    if (!text && error.rfind("cannot read '", 0) == 0) error = "cannot read scene" + error.substr(std::string("cannot read").size());
    return text;
}

// RADIANCE's library path (RAYPATH, ':'-separated), where files named without a directory
// are looked for after the naming file's own directory.
RadianceOptions radiance_options() {
    RadianceOptions options;
    if (const char* raypath = std::getenv("RAYPATH")) {
        std::string dirs = raypath;
        for (size_t b = 0; b <= dirs.size();) {
            size_t e = dirs.find(':', b);
            if (e == std::string::npos) e = dirs.size();
            if (e > b && dirs.compare(b, e - b, ".") != 0) options.library_dirs.push_back(dirs.substr(b, e - b));
            b = e + 1;
        }
    }
    return options;
}

}  // namespace

const SourceFile& SceneSources::add(std::string name, std::string text) {
    files.push_back(std::make_unique<SourceFile>(std::move(name), std::move(text)));
    return *files.back();
}

std::optional<Scene> load_scene(const std::string& spec, SceneSources& sources, DiagnosticSink& sink,
                                SceneLoadFailure& failure) {
    if (spec.rfind("builtin:", 0) == 0) {
        std::string name = spec.substr(8);
        if (auto s = builtin_scene(name)) return s;
        std::string known;
        for (const auto& n : builtin_scene_names()) known += (known.empty() ? "builtin:" : ", builtin:") + n;
        failure.message = fmt::format("unknown built-in scene '{}'; the built-in scenes are {}", spec, known);
        return std::nullopt;
    }
    std::string ext = lower_extension(spec);
    if (ext == ".obj") {
        if (!std::filesystem::exists(spec)) {
            failure.message = fmt::format("cannot read scene '{}': {}", spec, std::strerror(ENOENT));
            return std::nullopt;
        }
        return light_unlit_model(import_obj(spec, sink, sources), sink);
    }
    if (ext == ".gltf" || ext == ".glb") {
        // Not a regular file of at most 1 GiB (missing, a directory, a FIFO): an I/O failure.
        if (std::string why = check_input_file(spec, kMaxDataInputBytes); !why.empty()) {
            failure.message = why;
            return std::nullopt;
        }
        return light_unlit_model(import_gltf(spec, sink, sources), sink);
    }
    if (ext != ".json" && ext != ".rad" && ext != ".rif") {
        failure.message = fmt::format("cannot tell the format of scene '{}': use .json (crex scene), .rad or .rif (RADIANCE), "
                                      ".obj (Wavefront), .gltf or .glb (glTF 2.0) or builtin:cornell", spec);
        return std::nullopt;
    }
    std::string error;
    auto text = read_file(spec, error);
    if (!text) {
        failure.message = error;
        return std::nullopt;
    }
    const SourceFile& file = sources.add(spec, std::move(*text));
    std::string dir = std::filesystem::path(spec).parent_path().string();
    if (ext == ".json") return load_scene_json(file, dir, sources, sink);
    const RadianceOptions options = radiance_options();
    if (ext == ".rif") return import_radiance_project(file, sources, options, sink);
    // A RADIANCE scene takes its camera from a view file beside it with the same stem.
    std::filesystem::path vf = std::filesystem::path(spec).replace_extension(".vf");
    const SourceFile* view = nullptr;
    if (std::filesystem::exists(vf)) {
        auto vtext = read_file(vf.string(), error);
        if (!vtext) {
            failure.message = error;
            return std::nullopt;
        }
        view = &sources.add(vf.string(), std::move(*vtext));
    }
    auto scene = import_radiance(file, view, sources, options, sink);
    if (scene) scene->source = spec;
    // Neither a view file nor a `#@crex view` line set the camera (a view sets RADIANCE's
    // defaults first, so the camera is no longer crex's): say where it is (issue 37).
    const Camera none;
    if (scene && !view && scene->camera.position == none.position && scene->camera.direction == none.direction &&
        scene->camera.up == none.up && scene->camera.hfov_deg == none.hfov_deg)
        sink.report("W305", {&file, 0, 0},
                    fmt::format("no view: '{}' does not exist and no '#@crex view' line gives one, so the camera is crex's default, "
                                "at (0, 0, 5) looking along -z",
                                vf.string()))
            .help = fmt::format("write the view (rpict's -vp -vd -vu -vh -vv) into {}, or pass --view FILE.vf to crex run", vf.string());
    return scene;
}

std::string select_camera(Scene& scene, const std::string& spec) {
    std::string names;
    for (size_t i = 0; i < scene.cameras.size(); ++i) {
        if (scene.cameras[i].name == spec) {
            scene.camera = scene.cameras[i].camera;
            return "";
        }
        names += fmt::format("{}{} '{}'", i ? ", " : "", i, scene.cameras[i].name);
    }
    char* end = nullptr;
    const unsigned long index = std::strtoul(spec.c_str(), &end, 10);
    if (!spec.empty() && end && *end == '\0' && std::isdigit(static_cast<unsigned char>(spec[0])) && index < scene.cameras.size()) {
        scene.camera = scene.cameras[index].camera;
        return "";
    }
    if (scene.cameras.empty()) return fmt::format("--camera {}: the scene names no cameras (it has only its one camera)", spec);
    return fmt::format("--camera {}: no such camera; the scene's cameras are {}", spec, names);
}

}  // namespace crex
