#include "apps/crex/scene_input.h"

#include "runtime/scene/census.h"

namespace crex::app {

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

}  // namespace crex::app
