// `crex plan`: what a crex will execute on a scene, with what the scene does not need pruned.
#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "apps/crex/commands.h"
#include "base/exit_codes.h"
#include "runtime/api/run_inputs.h"
#include "base/render_text.h"
#include "compiler/compiler.h"
#include "compiler/pipeline/print.h"
#include "compiler/sched/print.h"
#include "runtime/base/atomic_file.h"
#include "runtime/base/output_folder.h"
#include "runtime/report/graphviz.h"

namespace crex::app {
namespace {

struct PlanOptions {
    std::string file;
    std::string pipeline_name;
    std::string crex;
    bool crex_given = false;  // -e '' is a valid (empty) crex
    std::string scene;
    std::string format;  // "": -o's extension says, else text
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

nlohmann::json to_json(const PipelinePlan& p) { return pipeline_plan_to_json(p); }
std::string to_dot(const PipelinePlan& p) { return pipeline_plan_to_dot(p); }
std::string to_text(const PipelinePlan& p) { return pipeline_plan_to_text(p); }
nlohmann::json to_json(const CrexPlan& p) { return plan_to_json(p); }
std::string to_dot(const CrexPlan& p) { return plan_to_dot(p); }
std::string to_text(const CrexPlan& p) { return plan_to_text(p); }

// A plan in the chosen format: its JSON, its DOT graph, the graph drawn by Graphviz (svg,
// png), or text.
template <typename Plan>
int write_plan(const PlanOptions& opt, const Plan& plan) {
    if (opt.format == "svg" || opt.format == "png") {
        if (std::string error = draw_graph(to_dot(plan), opt.format, opt.output); !error.empty()) {
            std::cerr << (opt.output.empty() ? fmt::format("crex plan: error: {}\n", error)
                                             : fmt::format("crex plan: error: cannot write '{}': {}\n", opt.output, error));
            return kExitFailure;
        }
        return kExitOk;
    }
    return write_output(opt, opt.format == "json" ? to_json(plan).dump(2) + "\n" : opt.format == "dot" ? to_dot(plan) : to_text(plan));
}

// The format of the plan: --format as given, else what -o's extension names (.json, .dot or
// .gv, .svg, .png; any other is text). A --format that an extension contradicts is a usage
// error: `-o plan.svg --format text` would write text into a file every viewer reads as SVG.
std::optional<std::string> plan_format(const std::string& given, const std::string& output, std::string& error) {
    std::string ext = std::filesystem::path(output).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const std::string named = ext == ".json" ? "json" : ext == ".dot" || ext == ".gv" ? "dot" : ext == ".svg" ? "svg" : ext == ".png" ? "png" : "";
    if (given.empty()) return named.empty() ? "text" : named;
    if (!named.empty() && named != given) {
        error = fmt::format("--format {} and -o {} disagree: the extension '{}' says {}; drop --format, or name the file for {}", given,
                            output, ext, named, given);
        return std::nullopt;
    }
    return given;
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
    if (pass == "parse" || pass == "check" || pass == "resolve" || pass == "compile")
        if (opt.format == "svg" || opt.format == "png") {
            std::cerr << fmt::format("crex plan: error: --dump-after {} prints text; {} draws a plan only (--dump-after plan or "
                                     "prune){}\n",
                                     pass, opt.format, opt.output.empty() ? "" : ": name the output for text, e.g. -o dump.txt");
            return kExitUsage;
        }
    if (pass == "parse" || pass == "check") {
        if (!in.compiled.ast || (pass == "check" && sink.has_errors())) return failed();
        int status = write_output(opt, pipeline::print_file(*in.compiled.ast));
        return status == kExitOk && sink.has_errors() ? kExitInputErrors : status;
    }
    if (!in.compiled.resolved) return failed();
    if (pass == "resolve") return write_output(opt, pipeline::print_resolved(*in.compiled.resolved));
    if (pass == "prune") {
        if (!in.compiled.plan) return failed();
        return write_plan(opt, *in.compiled.plan);
    }
    DiagnosticSink again;  // compile and plan without the scene; their diagnostics are reported above
    auto unpruned = plan_pipeline(*in.compiled.resolved, std::nullopt, "", "", again);
    if (!unpruned) return failed();
    if (pass == "compile")
        return write_output(opt, fmt::format("preselective: {}\nselective:    {}\n", sched::to_crex(unpruned->program.preselective),
                                             sched::to_crex(unpruned->program.selective)));
    return write_plan(opt, *unpruned);
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
    return write_plan(opt, *in->compiled.plan);
}

int run_plan(PlanOptions opt) {
    std::string format_error;
    if (auto format = plan_format(opt.format, opt.output, format_error)) opt.format = *format;
    else {
        std::cerr << "crex plan: error: " << format_error << "\n";
        return kExitUsage;
    }
    if (opt.format == "png" && opt.output.empty() && ::isatty(STDOUT_FILENO)) {
        std::cerr << "crex plan: error: a PNG is not for the terminal: write it to a file with -o plan.png\n";
        return kExitUsage;
    }
    if (std::string missing = opt.output.empty() ? "" : missing_output_folder(opt.output); !missing.empty()) {
        std::cerr << "crex plan: error: " << missing << "\n";
        return kExitFailure;
    }
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
    return write_plan(opt, plan);
}

}  // namespace

Runner add_plan_command(CLI::App& app) {
    auto opt = std::make_shared<PlanOptions>();
    CLI::App* cmd = app.add_subcommand("plan", "Show what a crex executes on a scene, pruned of what the scene cannot need");
    cmd->add_option("pipeline", opt->file, "A pipeline file (.pipe) to plan");
    cmd->add_option("--pipeline", opt->pipeline_name, "Which pipeline of the file (default: the last)");
    CLI::Option* crex = cmd->add_option("-e,--crex", opt->crex, "A crex to plan (instead of a pipeline file)")->allow_extra_args(false);
    cmd->add_option("--scene", opt->scene, "Scene to plan for (default: the pipeline's 'scene'): what it cannot need is pruned");
    cmd->add_option("--format", opt->format, "text, json (versioned, byte-stable), dot (Graphviz's language), or svg or png (the "
                                             "graph drawn; needs Graphviz's 'dot' program). Default: -o's extension (.json, .dot, "
                                             ".svg, .png), else text")
        ->check(CLI::IsMember({"text", "json", "dot", "svg", "png"}));
    cmd->add_option("-o,--output", opt->output, "Write the plan to FILE (atomically; its folder must exist) instead of stdout");
    cmd->add_option("--dump-after", opt->dump_after, "Pipeline files: print the pipeline after this front-end pass: parse, check, "
                                                     "resolve (extends applied), compile (lowered crex), plan (before pruning), prune")
        ->check(CLI::IsMember({"parse", "check", "resolve", "compile", "plan", "prune"}));
    cmd->footer(R"(
The planner follows the scene's spawn graph: a step whose bin no material in use can fill
never has work, so it is removed, and the plan says why.

Examples:
  crex plan -e '(TTMRSGD)*' --scene builtin:cornell_diffuse        executes D*
  crex plan -e 'TT{TTMRSGD}2' --scene builtin:cornell --format json
  crex plan -e '(TT[RS]G)*D' -o plan.png                           a picture of the plan (Graphviz)
  crex plan examples/pipelines/cornell_prog.pipe -o plan.svg         a pipeline's execution graph
  crex plan examples/pipelines/cornell_prog.pipe --format dot        ... as DOT text on stdout
  crex plan gold --scene builtin:cornell_diffuse                     the stdlib's gold pipeline, by name

Exit status: 0 ok or warnings only, 1 errors in the crex or scene, 2 usage, 3 I/O failure (or no Graphviz for svg, png).)");
    return [opt, crex] {
        opt->crex_given = crex->count() > 0;
        return run_plan(*opt);
    };
}

}  // namespace crex::app
