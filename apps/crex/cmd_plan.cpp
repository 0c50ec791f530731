// `crex plan`: what a crex will execute on a scene, with what the scene does not need pruned.
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "apps/crex/commands.h"
#include "apps/crex/exit_codes.h"
#include "apps/crex/scene_input.h"
#include "compiler/base/render_text.h"
#include "compiler/crex/compile.h"
#include "compiler/plan/emit_plan.h"
#include "runtime/base/atomic_file.h"
#include "runtime/scene/census.h"

namespace crex::app {
namespace {

struct PlanOptions {
    std::string crex;
    std::string scene;
    std::string format = "text";
    std::string output;
};

int run_plan(const PlanOptions& opt) {
    SourceFile file("<expr>", opt.crex);
    DiagnosticSink sink;
    CompiledCrex compiled = compile_crex(file, sink);
    std::unique_ptr<SceneInput> scene;
    if (!opt.scene.empty()) scene = load_scene_input(opt.scene, sink);
    std::cerr << render_text(sink.sorted());
    if (scene && !scene->failure.empty()) {
        std::cerr << "crex plan: error: " << scene->failure << "\n";
        return kExitFailure;
    }
    if (sink.has_errors() || !compiled.program || (scene && !scene->scene)) {
        std::cerr << fmt::format("crex plan: {} error{}; no plan\n", sink.error_count(), sink.error_count() == 1 ? "" : "s");
        return kExitInputErrors;
    }
    CrexPlan plan;
    plan.source = opt.crex;
    plan.where = SourceLocation::of(compiled.span);
    plan.program = *compiled.program;
    if (scene) {
        Census census = take_census(*scene->scene);
        plan.pruned = find_dead_steps(plan.program, census.spawnable);
        plan.program = prune_dead_steps(plan.program, census.spawnable);
        plan.scene = opt.scene;
        plan.census_hash = census_hash_hex(census.hash);
    }
    std::string text = opt.format == "json" ? plan_to_json(plan).dump(2) + "\n"
                       : opt.format == "dot" ? plan_to_dot(plan)
                                              : plan_to_text(plan);
    if (opt.output.empty()) {
        std::cout << text;
        return kExitOk;
    }
    std::string error = write_file_atomically(opt.output, text);
    if (!error.empty()) {
        std::cerr << fmt::format("crex plan: error: cannot write '{}': {}\n", opt.output, error);
        return kExitFailure;
    }
    return kExitOk;
}

}  // namespace

Runner add_plan_command(CLI::App& app) {
    auto opt = std::make_shared<PlanOptions>();
    CLI::App* cmd = app.add_subcommand("plan", "Show what a crex executes on a scene, pruned of what the scene cannot need");
    cmd->add_option("-e,--crex", opt->crex, "The crex")->required()->allow_extra_args(false);
    cmd->add_option("--scene", opt->scene, "Scene to plan for: steps whose bins it can never fill are pruned");
    cmd->add_option("--format", opt->format, "text, json (versioned, byte-stable) or dot (Graphviz)")
        ->check(CLI::IsMember({"text", "json", "dot"}));
    cmd->add_option("-o,--output", opt->output, "Write the plan to FILE (atomically) instead of stdout");
    cmd->footer(R"(
The planner follows the scene's spawn graph: a step whose bin no material in use can fill
never has work, so it is removed, and the plan says why.

Examples:
  crex plan -e '(TTMRSGD)*' --scene builtin:cornell_diffuse        executes D*
  crex plan -e 'TT{TTMRSGD}2' --scene builtin:cornell --format json
  crex plan -e '(TT[RS]G)*D' --format dot | dot -Tpng -o plan.png   a picture of the plan

Exit status: 0 ok or warnings only, 1 errors in the crex or scene, 2 usage, 3 I/O failure.)");
    return [opt] { return run_plan(*opt); };
}

}  // namespace crex::app
