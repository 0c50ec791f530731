// `crex check`: validate crex expressions and crex files; explain what they do.
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "apps/crex/commands.h"
#include "base/exit_codes.h"
#include "base/render_json.h"
#include "base/render_text.h"
#include "runtime/api/run_inputs.h"
#include "compiler/crex/compile.h"
#include "compiler/plan/bin_occupancy.h"
#include "runtime/scene/census.h"
#include "compiler/sched/print.h"

namespace crex::app {
namespace {

struct CheckOptions {
    std::vector<std::string> expressions;
    std::vector<std::string> files;
    std::string format = "text";
    bool explain = false;
    bool print_ir = false;
    bool quiet = false;
    std::string scene;
};

nlohmann::json program_json(const CompiledCrex& c) {
    nlohmann::json j;
    LineCol at = c.span.file->position(c.span.begin);
    j["file"] = c.span.file->name();
    j["line"] = at.line;
    j["source"] = std::string(c.span.text());
    j["ok"] = c.program.has_value();
    if (c.program) {
        j["canonical"] = sched::to_crex(*c.program);
        j["preselective"] = sched::to_crex(c.program->preselective);
        j["selective"] = sched::to_crex(c.program->selective);
    }
    return j;
}

int run_check(const CheckOptions& opt) {
    if (opt.expressions.empty() && opt.files.empty()) {
        std::cerr << "crex check: nothing to check: give -e EXPR or one or more files "
                     "(see 'crex check --help')\n";
        return kExitUsage;
    }
    std::vector<std::unique_ptr<SourceFile>> sources;
    for (const auto& e : opt.expressions) sources.push_back(std::make_unique<SourceFile>("<expr>", e));
    for (const auto& given : opt.files) {
        std::string path, error;
        auto text = read_input_or_stdlib(given, path, error);  // a file, or a stdlib pipeline by name
        if (!text) {
            std::cerr << "crex check: error: " << error << "\n";
            return kExitFailure;
        }
        const bool pipe = path.size() > 5 && path.substr(path.size() - 5) == ".pipe";
        if (const std::string kind = pipe ? "" : input_kind(path, *text); !kind.empty()) {
            std::cerr << fmt::format("crex check: error: {} is {}, not a crex or pipeline file: {}\n", path, kind,
                                     kind == "a scene" ? fmt::format("check a crex against it with --scene {}", path)
                                     : kind == "a plan" ? fmt::format("crex run {} reads it (and checks it)", path)
                                                        : std::string("crex check reads crex files and pipeline files (.pipe)"));
            return kExitUsage;
        }
        sources.push_back(std::make_unique<SourceFile>(path == "-" ? "<stdin>" : path, std::move(*text)));
    }

    DiagnosticSink sink;
    std::vector<CompiledCrex> compiled;
    std::vector<std::unique_ptr<PipelineInput>> kept_inputs;  // the sources their diagnostics point into
    for (size_t i = 0; i < sources.size(); ++i) {
        if (i < opt.expressions.size()) {
            compiled.push_back(compile_crex(*sources[i], sink));
        } else if (sources[i]->name().size() > 5 && sources[i]->name().substr(sources[i]->name().size() - 5) == ".pipe") {
            // A pipeline file: the front end's passes as `crex plan` runs them (parse, check with
            // the stdlib bases it extends, resolve, plan against its scene or --scene), so that
            // what check passes plan does too. Its crex literals are compiled by the checker.
            size_t errors = sink.error_count();
            auto in = load_pipeline_input(std::move(sources[i]), "", opt.scene, sink);
            if (!in->failure.empty()) {
                std::cerr << render_text(sink.sorted()) << "crex check: error: " << in->failure << "\n";
                return kExitFailure;
            }
            if (in->compiled.ast && sink.error_count() == errors && !opt.quiet && opt.format == "text")
                for (const auto& p : in->compiled.ast->pipelines)
                    std::cout << fmt::format("{}: ok: pipeline {}\n", format_location(p.name_span), p.name);
            kept_inputs.push_back(std::move(in));
        } else {
            for (auto& c : compile_crex_file(*sources[i], sink)) compiled.push_back(std::move(c));
        }
    }
    // With a scene: W103 for every step that can never have work (spec §5).
    std::unique_ptr<SceneInput> scene;
    if (!opt.scene.empty()) {
        scene = load_scene_input(opt.scene, sink);
        if (!scene->failure.empty()) {
            std::cerr << "crex check: error: " << scene->failure << "\n";
            return kExitFailure;
        }
        if (scene->scene) {
            BinSet spawnable = take_census(*scene->scene).spawnable;
            for (const auto& c : compiled) {
                if (!c.program) continue;
                for (const auto& d : find_dead_steps(*c.program, spawnable))
                    sink.report("W103", d.where.in(*c.span.file),
                                fmt::format("step {} can never have work in {}", component_letter(d.component), opt.scene))
                        .notes.push_back({{}, d.reason});
            }
        }
    }
    std::vector<Diagnostic> diagnostics = sink.sorted();

    if (opt.format == "json") {
        nlohmann::json out;
        out["diagnostics"] = to_json(diagnostics);
        out["errors"] = sink.error_count();
        out["warnings"] = sink.warning_count();
        out["crexes"] = nlohmann::json::array();
        for (const auto& c : compiled) out["crexes"].push_back(program_json(c));
        std::cout << out.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
    } else {
        std::cerr << render_text(diagnostics);
        if (sink.dropped() > 0)
            std::cerr << fmt::format("crex check: {} more diagnostics not shown\n", sink.dropped());
        for (const auto& c : compiled) {
            if (!c.program) continue;
            if (!opt.quiet) {
                std::string pre = sched::to_crex(c.program->preselective);
                std::string sel = sched::to_crex(c.program->selective);
                std::cout << fmt::format("{}: ok: {}  (pre-selective: {}; selective: {})\n",
                                         format_location(c.span), sched::to_crex(*c.program),
                                         pre.empty() ? "camera rays only" : pre,
                                         sel.empty() ? "none" : sel);
            }
            if (opt.explain) std::cout << sched::explain(*c.program);
            if (opt.print_ir) std::cout << sched::dump(*c.program);
        }
        if (sink.error_count() + sink.warning_count() > 0)
            std::cerr << fmt::format("{} error{}, {} warning{}\n", sink.error_count(),
                                     sink.error_count() == 1 ? "" : "s", sink.warning_count(),
                                     sink.warning_count() == 1 ? "" : "s");
    }
    return sink.has_errors() ? kExitInputErrors : kExitOk;
}

}  // namespace

Runner add_check_command(CLI::App& app) {
    auto opt = std::make_shared<CheckOptions>();
    CLI::App* cmd = app.add_subcommand("check", "Check crex expressions and crex files for errors");
    cmd->add_option("-e,--crex", opt->expressions, "A crex to check (repeatable), e.g. -e 'TT{TTMRSGD}2'")
        ->allow_extra_args(false);  // else CLI11 reads '[RS]' as a list literal
    cmd->add_option("files", opt->files, "Pipeline files (.pipe), stdlib pipelines by name (sel_quiet), or crex files (one crex per line, '#' comments); '-' reads stdin");
    cmd->add_option("--format", opt->format, "Diagnostics as text (stderr) or json (stdout)")
        ->check(CLI::IsMember({"text", "json"}));
    cmd->add_flag("--explain", opt->explain, "Print the steps each valid crex executes, in words");
    cmd->add_option("--scene", opt->scene, "Also report steps that can never have work in this scene (W103)");
    cmd->add_flag("--print-ir", opt->print_ir, "Print the lowered schedule IR as a tree");
    cmd->add_flag("-q,--quiet", opt->quiet, "Print only diagnostics");
    cmd->footer(R"(
A crex says in which order the renderer executes its component-ray bins:
  components  D diffuse  G glossy  S specular  T transmitted  R reflected (glass)  M mirror
  ( )  group              < >  deferred: spawned rays wait until the group ends
  { }  importance-modulated (occurrence i runs where I(p) > i/n)
  [ ]  time-constrained task (deferred; admitted under a budget only if it fits)
  k    repeat k times     *    repeat while there is work

Examples:
  crex check -e 'TT{TTMRSGD}2'              validate one expression
  crex check --explain -e '(TT[RS]G)*D'     what it executes, step by step
  crex check stdlib/crex/thesis.crex        a file, one crex per line
  crex check examples/pipelines/cornell_prog.pipe   a pipeline file
  crex check --format json -e '{D*}'        diagnostics for tools
  crex check --scene builtin:cornell_diffuse -e '(TTMRSGD)*'   W103: T, M, R, S, G never have work

Exit status: 0 ok or warnings only, 1 errors in the input, 2 usage, 3 I/O failure.)");
    return [opt] { return run_check(*opt); };
}

}  // namespace crex::app
