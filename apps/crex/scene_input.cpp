#include "apps/crex/scene_input.h"

namespace crex::app {

std::unique_ptr<SceneInput> load_scene_input(const std::string& spec, DiagnosticSink& sink) {
    auto in = std::make_unique<SceneInput>();
    SceneLoadFailure failure;
    in->scene = load_scene(spec, in->sources, sink, failure);
    in->failure = failure.message;
    return in;
}

}  // namespace crex::app
