/// \file scene_input.h
/// `--scene S` for every subcommand: load it, its diagnostics into the command's sink.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "compiler/compiler.h"
#include "runtime/scene/load_scene.h"

namespace crex::app {

struct SceneInput {
    SceneSources sources;  ///< keeps the texts diagnostics point into
    std::optional<Scene> scene;
    std::string failure;   ///< set when the scene could not be read at all (exit 3)
};

std::unique_ptr<SceneInput> load_scene_input(const std::string& spec, DiagnosticSink& sink);

/// What the compiler plans a scene by: its census, named `spec`.
SceneFacts scene_facts(const std::string& spec, const Scene& scene);

}  // namespace crex::app
