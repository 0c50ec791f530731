#include "apps/crex/run_input.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <map>

#include "apps/crex/exit_codes.h"
#include "apps/crex/input_files.h"
#include "apps/crex/pipeline_input.h"
#include "compiler/base/render_text.h"
#include "compiler/crex/compile.h"
#include "compiler/plan/read_plan.h"
#include "runtime/scene/census.h"

namespace crex::app {
namespace {

std::string without_spaces(std::string s) {
    s.erase(std::remove(s.begin(), s.end(), ' '), s.end());
    return s;
}

std::string unquoted(std::string s) {
    if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
    return s;
}

// A pipeline's settings apply unless a flag says otherwise (spec/pipeline.md §7).
bool apply_settings(const std::map<std::string, std::string>& settings, RunOptions& opt) {
    auto has = [&](const char* k) { return settings.count(k) > 0; };
    if (!opt.size_given && has("image")) opt.size = without_spaces(settings.at("image"));
    if (opt.budget.empty() && has("budget")) opt.budget = without_spaces(settings.at("budget"));
    if (opt.outputs.empty() && has("output_image")) opt.outputs = {unquoted(settings.at("output_image"))};
    if (opt.report_dir.empty() && has("output_report")) opt.report_dir = unquoted(settings.at("output_report"));
    if (opt.reference.empty() && has("reference")) opt.reference = unquoted(settings.at("reference"));
    if (opt.maps_dir.empty() && has("output_maps") && settings.at("output_maps") == "true") opt.maps_beside_output = true;
    try {
        if (!opt.spp_given && has("spp")) opt.spp = static_cast<uint32_t>(std::stoul(settings.at("spp")));
        if (!opt.seed_given && has("seed")) opt.seed = std::stoull(settings.at("seed"));
        if (!opt.lw_given && has("lw")) opt.lw = std::stod(settings.at("lw"));
        if (!opt.max_depth_given && has("max_depth")) opt.max_depth = static_cast<uint32_t>(std::stoul(settings.at("max_depth")));
        if (!opt.aa_given && has("aa")) opt.aa = std::stod(settings.at("aa"));
        if (!opt.ab_given && has("ab")) opt.ab = static_cast<uint32_t>(std::stoul(settings.at("ab")));
        if (!opt.ambient_given && has("av")) opt.ambient = std::stod(settings.at("av")), opt.ambient_given = true;
    } catch (const std::exception&) {
        return false;
    }
    return true;
}

}  // namespace

std::optional<int> read_run_input(RunOptions& opt, RunInput& in) {
    if (!opt.plan.empty() && opt.crex_given) {
        std::cerr << "crex run: error: give either a plan file or -e/--crex, not both\n";
        return kExitUsage;
    }
    DiagnosticSink sink;
    std::map<std::string, std::string> settings;
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
            in.plan = *pipe->plan;
            in.pipeline = planned = true;
            in.scene_spec = pipe->scene_spec;
            for (const auto& [k, v] : pipe->plan->settings.items()) settings[k] = v.get<std::string>();
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
        in.source = std::make_unique<SourceFile>(opt.plan, std::move(*text));
        if (auto kept = read_plan(*in.source, sink)) {
            planned = true;
            in.plan.program = kept->program;
            if (kept->pipeline) in.plan = std::move(*kept->pipeline), in.pipeline = true;
            if (in.scene_spec.empty()) in.scene_spec = kept->scene;
            expected_census = kept->census_hash;
            settings = kept->settings;
        }
    } else {
        // An empty -e is an empty crex (camera rays only), as `check` and `plan` take it.
        in.source = std::make_unique<SourceFile>("<crex>", opt.crex_given ? opt.crex : kDefaultCrex);
        LowerOptions lower;
        lower.star_cap = opt.star_cap;
        if (auto program = compile_crex(*in.source, sink, lower).program) in.plan.program = *program, planned = true;
    }
    if (in.scene_spec.empty()) in.scene_spec = "builtin:cornell";
    if (!apply_settings(settings, opt)) {
        std::cerr << "crex run: error: the plan's settings hold a malformed number\n";
        return kExitInputErrors;
    }

    auto t_load = std::chrono::steady_clock::now();
    if (!in.scene) in.scene = load_scene_input(in.scene_spec, sink);
    in.load_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_load).count();
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

}  // namespace crex::app
