// `crex plan`: what a crex will execute on a scene, with what the scene does not need pruned.
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "apps/crex/commands.h"
#include "base/exit_codes.h"
#include "runtime/api/run_inputs.h"
#include "base/render_text.h"
#include "compiler/compiler.h"
#include "compiler/pipeline/print.h"
#include "compiler/sched/print.h"
#include "runtime/base/atomic_file.h"

namespace crex::app {
namespace {

struct PlanOptions {
    std::string file;
    std::string pipeline_name;
    std::string crex;
    bool crex_given = false;  // -e '' is a valid (empty) crex
    std::string scene;
    std::string format = "text";
    std::string output;
    std::string dump_after;  // a front-end pass: print the pipeline as it leaves it
};

int write_output(const PlanOptions& opt, const std::string& text) {
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

// `--dump-after PASS`: the pipeline as the front end's pass PASS leaves it. parse and check
// print the file back (check only when it passed), resolve the pipeline with its bases applied,
// compile the two stages' lowered crex, plan the plan before scene pruning, prune the plan.
int dump_after(const PlanOptions& opt, const PipelineInput& in, const DiagnosticSink& sink) {
    const std::string& pass = opt.dump_after;
    auto failed = [&] {
        std::cerr << fmt::format("crex plan: {} error{} before the end of '{}'; nothing to dump\n", sink.error_count(),
                                 sink.error_count() == 1 ? "" : "s", pass);
        return kExitInputErrors;
    };
    if (pass == "parse" || pass == "check") {
        if (!in.compiled.ast || (pass == "check" && sink.has_errors())) return failed();
        int status = write_output(opt, pipeline::print_file(*in.compiled.ast));
        return status == kExitOk && sink.has_errors() ? kExitInputErrors : status;
    }
    if (!in.compiled.resolved) return failed();
    if (pass == "resolve") return write_output(opt, pipeline::print_resolved(*in.compiled.resolved));
    if (pass == "prune") {
        if (!in.compiled.plan) return failed();
        return write_output(opt, opt.format == "json" ? pipeline_plan_to_json(*in.compiled.plan).dump(2) + "\n"
                                 : opt.format == "dot" ? pipeline_plan_to_dot(*in.compiled.plan)
                                                        : pipeline_plan_to_text(*in.compiled.plan));
    }
    DiagnosticSink again;  // compile and plan without the scene; their diagnostics are reported above
    auto unpruned = plan_pipeline(*in.compiled.resolved, std::nullopt, "", "", again);
    if (!unpruned) return failed();
    if (pass == "compile")
        return write_output(opt, fmt::format("preselective: {}\nselective:    {}\n", sched::to_crex(unpruned->program.preselective),
                                             sched::to_crex(unpruned->program.selective)));
    return write_output(opt, opt.format == "json" ? pipeline_plan_to_json(*unpruned).dump(2) + "\n"
                             : opt.format == "dot" ? pipeline_plan_to_dot(*unpruned)
                                                    : pipeline_plan_to_text(*unpruned));
}

// A pipeline file: check, resolve `extends`, plan for its scene (or --scene).
int plan_pipeline_file(const PlanOptions& opt) {
    DiagnosticSink sink;
    auto in = load_pipeline_input(opt.file, opt.pipeline_name, opt.scene, sink);
    std::cerr << render_text(sink.sorted());
    if (!in->failure.empty()) {
        std::cerr << "crex plan: error: " << in->failure << "\n";
        return kExitFailure;
    }
    if (!opt.dump_after.empty()) return dump_after(opt, *in, sink);
    if (!in->compiled.plan) {
        std::cerr << fmt::format("crex plan: {} error{}; no plan\n", sink.error_count(), sink.error_count() == 1 ? "" : "s");
        return kExitInputErrors;
    }
    return write_output(opt, opt.format == "json" ? pipeline_plan_to_json(*in->compiled.plan).dump(2) + "\n"
                             : opt.format == "dot" ? pipeline_plan_to_dot(*in->compiled.plan)
                                                    : pipeline_plan_to_text(*in->compiled.plan));
}

int run_plan(const PlanOptions& opt) {
    if (opt.file.empty() != opt.crex_given) {
        std::cerr << "crex plan: give a pipeline file or -e CREX (one of them; see 'crex plan --help')\n";
        return kExitUsage;
    }
    if (!opt.dump_after.empty() && opt.file.empty()) {
        std::cerr << "crex plan: --dump-after needs a pipeline file (a crex's lowered form: 'crex check --print-ir')\n";
        return kExitUsage;
    }
    if (!opt.file.empty()) {
        // A plan, a scene, ...: said as such, not as "E201 unexpected '{'" of the pipeline parser.
        const bool pipe = opt.file.size() > 5 && opt.file.substr(opt.file.size() - 5) == ".pipe";
        std::string error;
        if (auto text = pipe || opt.file == "-" ? std::nullopt : read_input(opt.file, error)) {
            const std::string kind = input_kind(opt.file, *text);
            if (kind == "a plan") {
                std::cerr << fmt::format("crex plan: error: {} is a plan already (crex plan --format json made it): run it with "
                                         "'crex run {}', or give crex plan a pipeline file (.pipe) or -e CREX\n",
                                         opt.file, opt.file);
                return kExitUsage;
            }
            if (!kind.empty()) {
                std::cerr << fmt::format("crex plan: error: {} is {}, not a pipeline: plan a pipeline file (.pipe) or -e CREX for it "
                                         "with --scene {}\n",
                                         opt.file, kind, opt.file);
                return kExitUsage;
            }
        }
        return plan_pipeline_file(opt);
    }
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
    std::optional<SceneFacts> facts;
    if (scene) facts = scene_facts(opt.scene, *scene->scene);
    const CrexPlan plan = plan_crex(opt.crex, compiled, facts ? &*facts : nullptr);
    return write_output(opt, opt.format == "json" ? plan_to_json(plan).dump(2) + "\n"
                             : opt.format == "dot" ? plan_to_dot(plan)
                                                    : plan_to_text(plan));
}

}  // namespace

Runner add_plan_command(CLI::App& app) {
    auto opt = std::make_shared<PlanOptions>();
    CLI::App* cmd = app.add_subcommand("plan", "Show what a crex executes on a scene, pruned of what the scene cannot need");
    cmd->add_option("pipeline", opt->file, "A pipeline file (.pipe) to plan");
    cmd->add_option("--pipeline", opt->pipeline_name, "Which pipeline of the file (default: the last)");
    CLI::Option* crex = cmd->add_option("-e,--crex", opt->crex, "A crex to plan (instead of a pipeline file)")->allow_extra_args(false);
    cmd->add_option("--scene", opt->scene, "Scene to plan for (default: the pipeline's 'scene'): what it cannot need is pruned");
    cmd->add_option("--format", opt->format, "text, json (versioned, byte-stable) or dot (Graphviz)")
        ->check(CLI::IsMember({"text", "json", "dot"}));
    cmd->add_option("-o,--output", opt->output, "Write the plan to FILE (atomically) instead of stdout");
    cmd->add_option("--dump-after", opt->dump_after, "Pipeline files: print the pipeline after this front-end pass: parse, check, "
                                                     "resolve (extends applied), compile (lowered crex), plan (before pruning), prune")
        ->check(CLI::IsMember({"parse", "check", "resolve", "compile", "plan", "prune"}));
    cmd->footer(R"(
The planner follows the scene's spawn graph: a step whose bin no material in use can fill
never has work, so it is removed, and the plan says why.

Examples:
  crex plan -e '(TTMRSGD)*' --scene builtin:cornell_diffuse        executes D*
  crex plan -e 'TT{TTMRSGD}2' --scene builtin:cornell --format json
  crex plan -e '(TT[RS]G)*D' --format dot | dot -Tpng -o plan.png   a picture of the plan
  crex plan examples/pipelines/cornell_prog.pipe --format dot        a pipeline's execution graph
  crex plan stdlib/pipelines/gold.pipe --scene builtin:cornell_diffuse

Exit status: 0 ok or warnings only, 1 errors in the crex or scene, 2 usage, 3 I/O failure.)");
    return [opt, crex] {
        opt->crex_given = crex->count() > 0;
        return run_plan(*opt);
    };
}

}  // namespace crex::app
