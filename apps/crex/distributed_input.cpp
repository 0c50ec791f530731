#include "apps/crex/distributed_input.h"

#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "apps/crex/distributed.h"
#include "apps/crex/exit_codes.h"
#include "apps/crex/input_files.h"
#include "base/render_text.h"
#include "compiler/plan/emit_plan.h"
#include "compiler/plan/plan_pipeline.h"
#include "compiler/sched/print.h"
#include "runtime/scene/load_scene.h"

namespace crex::app {
namespace {

// JSON text of `j`. A name read from a file may hold bytes that are not UTF-8 (a RADIANCE
// identifier in Latin-1), which dump() refuses by default: they become U+FFFD, the same bytes
// alike, so a shape still names its material.
std::string text_of(const nlohmann::json& j) { return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace); }

// Said by rank 0 before anything is sent, so every rank exits with its code.
std::optional<int> unsupported_under_mpirun(const RunOptions& opt) {
    if (opt.compare_policies) {
        std::cerr << "crex run: error: under mpirun, --compare-policies is not supported yet\n";
        return kExitUsage;
    }
    if (!opt.resume.empty()) {
        std::cerr << "crex run: error: under mpirun, --resume is not supported yet: resume in one process (the same command "
                     "without mpirun)\n";
        return kExitUsage;
    }
    return std::nullopt;
}

// Rank 0: read, check and plan as one process does, then put what the others need into
// `data`, and the --ic-file's bytes (binary: sent apart from the JSON) into `ic_bytes`.
std::optional<int> read_as_rank0(RunOptions& opt, RunInput& in, RunSetup& setup, nlohmann::json& data, std::string& ic_bytes) {
    if (auto exit = read_run_input(opt, in)) return exit;
    if (auto exit = make_run_setup(opt, in, setup)) return exit;
    if (auto exit = unsupported_under_mpirun(opt)) return exit;
    if (in.pipeline) {
        data["plan"] = text_of(pipeline_plan_to_json(in.plan));
    } else {  // a crex (-e, or a kept crex plan): its program, as `crex plan` keeps it
        CrexPlan plan;
        plan.source = sched::to_crex(in.plan.program);
        plan.program = in.plan.program;
        data["plan"] = text_of(plan_to_json(plan));
    }
    data["scene"] = text_of(scene_to_json(*in.scene->scene));
    data["scene_spec"] = in.scene_spec;
    data["scene_source"] = in.scene->scene->source;
    if (!opt.profile_in.empty()) {
        // As read (the profile's own JSON with the full render's time): the others parse it alike.
        auto profile = nlohmann::json::parse(setup.profile.to_json_text());
        profile["full_render_seconds"] = setup.full_render_seconds;
        data["profile"] = text_of(profile);
    }
    RunSettings& s = setup.settings;
    std::error_code ec;
    if (s.irradiance_cache && !s.ic_file.empty() && std::filesystem::exists(s.ic_file, ec)) {
        std::string error;
        auto bytes = read_input(s.ic_file, error);
        if (!bytes) {
            std::cerr << "crex run: error: --ic-file: " << error << "\n";
            return kExitFailure;
        }
        ic_bytes = std::move(*bytes);
        data["ic_file_bytes"] = true;
        s.ic_file_bytes = ic_bytes;  // rank 0 loads what it sent, not the file again
    }
    return std::nullopt;
}

// Any other rank: the same as rank 0 from its data. A failure here is a bug (rank 0 made the
// data from inputs it checked): it ends every rank rather than leaving them waiting.
void read_from_rank0(RunOptions& opt, RunInput& in, RunSetup& setup, const nlohmann::json& data, const std::string& ic_bytes) {
    const int rank = distribution().rank;
    auto fail = [&](const std::string& what) {
        abort_all_ranks(fmt::format("crex run: internal error: rank {} cannot use the inputs rank 0 sent: {}\n", rank, what), kExitFailure);
    };
    auto scene = std::make_unique<SceneInput>();
    const SourceFile& file = scene->sources.add("<the scene from rank 0>", data.at("scene").get<std::string>());
    DiagnosticSink sink;
    scene->scene = load_scene_json(file, ".", scene->sources, sink);
    if (!scene->scene || sink.has_errors()) return fail("the scene: " + render_text(sink.sorted()));
    scene->scene->source = data.at("scene_source").get<std::string>();
    opt.view.clear();  // rank 0 applied it to the scene's camera
    if (data.contains("profile")) opt.profile_text = data["profile"].get<std::string>();
    opt.writes_outputs = false;
    if (read_run_input_from_rank0(opt, in, data.at("plan").get<std::string>(), std::move(scene), data.at("scene_spec").get<std::string>()))
        return fail("the plan");
    // Rank 0 checked every option and file; nothing here can fail unless the two disagree.
    if (make_run_setup(opt, in, setup)) return fail("the settings");
    if (data.value("ic_file_bytes", false)) setup.settings.ic_file_bytes = ic_bytes;
}

}  // namespace

std::optional<int> read_run_input_on_rank0(RunOptions& opt, RunInput& in, RunSetup& setup) {
    const Distribution ranks = distribution();
    if (!ranks.active()) {
        if (auto exit = read_run_input(opt, in)) return exit;
        return make_run_setup(opt, in, setup);
    }
    const std::string what = "the plan, scene and settings (rank 0 reads, checks and plans the inputs)";
    if (ranks.rank == 0) {
        nlohmann::json data;
        std::string ic_bytes;
        std::optional<int> exit;
        try {
            exit = read_as_rank0(opt, in, setup, data, ic_bytes);
        } catch (...) {  // a bug or an I/O failure: the others still learn that nothing runs
            share_from_rank0(nlohmann::json{{"exit", kExitFailure}}.dump(), what);
            throw;
        }
        if (exit) data = {{"exit", *exit}};
        share_from_rank0(text_of(data), what);
        if (!exit) share_from_rank0(std::move(ic_bytes), "the --ic-file records");
        return exit;
    }
    const nlohmann::json data = nlohmann::json::parse(share_from_rank0("", what));
    // Rank 0 printed why; this rank exits with the same code, saying nothing more.
    if (data.contains("exit")) return data["exit"].get<int>();
    const std::string ic_bytes = share_from_rank0("", "the --ic-file records");
    read_from_rank0(opt, in, setup, data, ic_bytes);
    return std::nullopt;
}

}  // namespace crex::app
