/// \file scene_helpers.h
/// Test helpers: load a scene from text and look at the diagnostics.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "runtime/scene/load_scene.h"
#include "tests/support/diagnostic_helpers.h"
#include "tests/support/scratch_folder.h"

namespace crex::testing {

/// The scene's shape called `name`, or null.
inline const Shape* shape_named(const Scene& s, const std::string& name) {
    for (const auto& shape : s.shapes)
        if (shape.name == name) return &shape;
    return nullptr;
}

struct SceneResult : Diagnosed {
    std::unique_ptr<SceneSources> sources = std::make_unique<SceneSources>();
    std::optional<Scene> scene;
};

inline SceneResult load_json_text(const std::string& text, const std::string& name = "scene.json") {
    SceneResult r;
    DiagnosticSink sink;
    const SourceFile& f = r.sources->add(name, text);
    r.scene = load_scene_json(f, ".", *r.sources, sink);
    r.diagnostics = sink.sorted();
    r.errors = sink.error_count();
    return r;
}

inline SceneResult load_rad_text(const std::string& text, const std::string& view = "") {
    SceneResult r;
    DiagnosticSink sink;
    const SourceFile& f = r.sources->add("scene.rad", text);
    const SourceFile* vf = view.empty() ? nullptr : &r.sources->add("scene.vf", view);
    r.scene = import_radiance(f, vf, *r.sources, {}, sink);
    r.diagnostics = sink.sorted();
    r.errors = sink.error_count();
    return r;
}

inline SceneResult load_path(const std::string& path) {
    SceneResult r;
    DiagnosticSink sink;
    SceneLoadFailure failure;
    r.scene = load_scene(path, *r.sources, sink, failure);
    r.diagnostics = sink.sorted();
    r.errors = sink.error_count() + (failure.message.empty() ? 0 : 1);
    return r;
}

}  // namespace crex::testing
