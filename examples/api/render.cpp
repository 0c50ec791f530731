// The library in a program of its own: compile a pipeline for a scene, run it, write the image.
// Usage: crex_api_example PIPELINE.pipe SCENE OUT.png   (e.g. stdlib/pipelines/sel_rp.pipe builtin:cornell)
#include <iostream>

#include "runtime/runtime.h"

int main(int argc, char** argv) {
    if (argc != 4) {
        std::cerr << "usage: crex_api_example PIPELINE.pipe SCENE OUT.png\n";
        return 2;
    }
    crex::DiagnosticSink sink;
    std::string error;
    auto scene = crex::load_scene_input(argv[2], sink);
    auto text = crex::read_input(argv[1], error);
    if (!text || !scene->scene) {
        std::cerr << crex::render_text(sink.sorted()) << error << scene->failure << "\n";
        return 1;
    }
    // The pipeline planned for the scene's census: what the scene can never need is pruned.
    const crex::SourceFile source(argv[1], *text);
    const crex::SceneFacts facts = crex::scene_facts(argv[2], *scene->scene);
    const crex::PipelineCompilation compiled = crex::compile_pipeline(source, &facts, sink);
    std::cerr << crex::render_text(sink.sorted());
    if (!compiled.plan) return 1;
    // Options override the plan's settings; one process; nobody watching the progress.
    crex::RunOptions options;
    options.width = 64, options.height = 48;
    crex::LocalGroup one;
    crex::RunObserver nobody;
    const crex::RunOutcome out = crex::run_plan(*compiled.plan, *scene->scene, options, one, nobody);
    const crex::RunResult& result = *out.result;
    error = crex::write_image(argv[3], options.width.value(), options.height.value(), {{"", result.image()}}, {});
    if (!error.empty()) std::cerr << error << "\n";
    else std::cout << "wrote " << argv[3] << ": " << crex::total_rays(result.stats) << " rays\n";
    return error.empty() ? 0 : 3;
}
