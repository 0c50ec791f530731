#include "apps/crex/run_input.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <iostream>

#include "apps/crex/exit_codes.h"
#include "apps/crex/input_files.h"
#include "apps/crex/pipeline_input.h"
#include "base/render_text.h"
#include "compiler/crex/compile.h"
#include "compiler/plan/read_plan.h"
#include "runtime/scene/census.h"
#include "runtime/scene/radiance_view.h"

namespace crex::app {
namespace {

// A pipeline's settings apply unless a flag says otherwise (spec/pipeline.md §7). They are
// typed and range-checked already (compiler/pipeline/settings_table.h).
void apply_settings(const PipelinePlan& plan, RunOptions& opt) {
    const PlanSettings& s = plan.settings;
    if (!opt.size_given && s.width && s.height) opt.size = fmt::format("{}x{}", *s.width, *s.height);
    if (!opt.spp_given) opt.spp = s.spp;
    if (opt.budget.empty() && s.budget) opt.budget = fmt::format("{}{}", s.budget->amount, s.budget->percent ? "%" : "s");
    if (opt.outputs.empty()) opt.outputs = plan.outputs.images;
    if (opt.report_dir.empty()) opt.report_dir = plan.outputs.report;
    if (opt.reference.empty()) opt.reference = s.reference;
    if (opt.maps_dir.empty() && plan.outputs.maps) opt.maps_beside_output = true;
    if (!opt.seed_given && s.seed) opt.seed = *s.seed;
    if (!opt.lw_given && s.lw) opt.lw = *s.lw;
    if (!opt.max_depth_given && s.max_depth) opt.max_depth = *s.max_depth;
    if (!opt.aa_given && s.aa) opt.aa = *s.aa;
    if (!opt.ab_given && s.ab) opt.ab = *s.ab;
    if (!opt.ad_given && s.ad) opt.ad = *s.ad;
    if (!opt.ambient_given && s.av) opt.ambient = *s.av, opt.ambient_given = true;
}

}  // namespace

std::optional<int> read_run_input(RunOptions& opt, RunInput& in) {
    if (!opt.plan.empty() && opt.crex_given) {
        std::cerr << "crex run: error: give either a plan file or -e/--crex, not both\n";
        return kExitUsage;
    }
    DiagnosticSink sink;
    std::string expected_census;
    bool planned = false;
    in.scene_spec = opt.scene;
    const bool is_pipe = opt.plan.size() > 5 && opt.plan.substr(opt.plan.size() - 5) == ".pipe";
    if (is_pipe) {
        auto pipe = load_pipeline_input(opt.plan, "", opt.scene, sink);
        if (!pipe->failure.empty()) {
            std::cerr << render_text(sink.sorted()) << "crex run: error: " << pipe->failure << "\n";
            return kExitFailure;
        }
        if (pipe->plan) {
            if (const auto& budget = pipe->plan->settings.budget; opt.budget.empty() && budget && budget->where.known())
                opt.budget_origin = budget->where.to_string();
            // Where the pipeline sets a limit, for W404 (a flag given overrides it: said as the flag's).
            for (auto [key, given, origin] : {std::tuple{"max_depth", opt.max_depth_given, &opt.max_depth_origin},
                                              std::tuple{"lw", opt.lw_given, &opt.lw_origin}, std::tuple{"ab", opt.ab_given, &opt.ab_origin}})
                if (auto it = pipe->resolved->top.find(key); !given && it != pipe->resolved->top.end() && !it->second.empty())
                    *origin = format_location(it->second[0].span);
            in.plan = *pipe->plan;
            in.pipeline = planned = true;
            in.scene_spec = pipe->scene_spec;
        }
        in.scene = std::move(pipe->scene);
        in.source = std::move(pipe->source);
    } else if (!opt.plan.empty()) {
        std::string read_error;
        auto text = read_input(opt.plan, read_error);
        if (!text) {
            std::cerr << "crex run: error: " << read_error << "\n";
            return kExitFailure;
        }
        // A scene given as the plan (`crex run scene.rad`) was read as a plan: "E401 malformed JSON".
        if (const std::string kind = input_kind(opt.plan, *text); !kind.empty() && kind != "a plan") {
            std::cerr << fmt::format("crex run: error: {} is {}, not a plan or a pipeline: {}\n", opt.plan, kind,
                                     kind == "a scene" ? fmt::format("render it with --scene {} (and -e CREX or a pipeline file)", opt.plan)
                                     : kind == "a profile" ? fmt::format("pass it as --profile {}", opt.plan)
                                                           : fmt::format("pass it as --view {}", opt.plan));
            return kExitUsage;
        }
        in.source = std::make_unique<SourceFile>(opt.plan, std::move(*text));
        if (auto kept = read_plan(*in.source, sink)) {
            planned = true;
            in.plan.program = kept->program;
            if (kept->pipeline) in.plan = std::move(*kept->pipeline), in.pipeline = true;
            if (in.scene_spec.empty()) in.scene_spec = kept->scene;
            expected_census = kept->census_hash;
        }
    } else {
        // An empty -e is an empty crex (camera rays only), as `check` and `plan` take it.
        in.source = std::make_unique<SourceFile>("<crex>", opt.crex_given ? opt.crex : kDefaultCrex);
        LowerOptions lower;
        lower.star_cap = opt.star_cap;
        if (auto program = compile_crex(*in.source, sink, lower).program) in.plan.program = *program, planned = true;
    }
    if (in.scene_spec.empty()) in.scene_spec = "builtin:cornell";
    if (in.pipeline) apply_settings(in.plan, opt);

    auto t_load = std::chrono::steady_clock::now();
    if (!in.scene) in.scene = load_scene_input(in.scene_spec, sink);
    in.load_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_load).count();
    // --camera NAME|INDEX: another of the scene's cameras (then --view may still replace it).
    if (!opt.camera.empty() && in.scene->scene) {
        if (std::string error = select_camera(*in.scene->scene, opt.camera); !error.empty()) {
            std::cerr << "crex run: error: " << error << "\n";
            return kExitUsage;
        }
    }
    // --view FILE.vf: RADIANCE's view options replace the scene's camera (rpict -vf).
    if (!opt.view.empty() && in.scene->scene) {
        std::string view_error;
        auto text = read_input(opt.view, view_error);
        if (!text) {
            std::cerr << "crex run: error: --view: " << view_error << "\n";
            return kExitFailure;
        }
        in.view_source = std::make_unique<SourceFile>(opt.view, std::move(*text));
        sink.withdraw("W305");  // the scene's missing view: this one replaces it
        apply_radiance_view(*in.view_source, view_file_words(*in.view_source), in.scene->scene->camera, true, sink);
    }
    const std::optional<Scene>& scene = in.scene->scene;
    // A plan is only valid for a scene with the census it was made for (spec 5).
    if (scene && !expected_census.empty()) {
        std::string actual = census_hash_hex(take_census(*scene).hash);
        if (actual != expected_census)
            sink.report("E402", {in.source.get(), 0, 0},
                        fmt::format("the plan was made for a scene with census {}, but {} has census {}", expected_census,
                                    in.scene_spec, actual))
                .help = "plan again for this scene: crex plan -e '...' --scene " + in.scene_spec;
    }
    std::cerr << render_text(sink.sorted());
    if (!in.scene->failure.empty()) {
        std::cerr << "crex run: error: " << in.scene->failure << "\n";
        return kExitFailure;
    }
    if (sink.has_errors() || !planned || !scene) {
        std::cerr << fmt::format("crex run: {} error{}; nothing rendered\n", sink.error_count(), sink.error_count() == 1 ? "" : "s");
        return kExitInputErrors;
    }
    return std::nullopt;
}

std::optional<int> read_run_input_from_rank0(RunOptions& opt, RunInput& in, const std::string& plan_json,
                                             std::unique_ptr<SceneInput> scene, const std::string& scene_spec) {
    DiagnosticSink sink;
    in.source = std::make_unique<SourceFile>("<the plan from rank 0>", plan_json);
    auto kept = read_plan(*in.source, sink);
    if (!kept) {
        std::cerr << render_text(sink.sorted()) << "crex run: internal error: the plan rank 0 sent cannot be read\n";
        return kExitFailure;
    }
    in.plan.program = kept->program;
    if (kept->pipeline) in.plan = std::move(*kept->pipeline), in.pipeline = true;
    // Rank 0 checked the plan against the scene (its census); this is the scene it loaded.
    in.scene_spec = scene_spec;
    in.scene = std::move(scene);
    if (in.pipeline) apply_settings(in.plan, opt);
    return std::nullopt;
}

}  // namespace crex::app
