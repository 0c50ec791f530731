#include "runtime/api/shared_inputs.h"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "base/exit_codes.h"
#include "base/render_text.h"
#include "compiler/sched/print.h"

namespace crex {
namespace {

// JSON text of `j`. A name read from a file may hold bytes that are not UTF-8 (a RADIANCE
// identifier in Latin-1), which dump() refuses by default: they become U+FFFD, the same bytes
// alike, so a shape still names its material.
std::string text_of(const nlohmann::json& j) { return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace); }

const char* kWhat = "the plan, scene and settings (rank 0 reads, checks and plans the inputs)";

// The lead: what the others need of `in`, as data; the cache file's bytes (binary: sent apart
// from the JSON) into `ic_bytes`.
nlohmann::json inputs_as_data(const RunInputs& in, std::string& ic_bytes) {
    nlohmann::json data;
    if (in.plan.staged) {
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
    if (in.profile)  // as read: the others parse it alike
        data["profile"] = profile_json_text(in.profile->profile, in.profile->full_render_seconds, in.profile->stages);
    if (in.ic_file_bytes) {
        ic_bytes = *in.ic_file_bytes;
        data["ic_file_bytes"] = true;
    }
    return data;
}

// Any other process: the lead's inputs from their data. A failure here is a bug (the lead made
// the data from inputs it checked): it ends every process rather than leaving them waiting.
RunInputs inputs_from_data(ProcessGroup& group, const nlohmann::json& data, const std::string& ic_bytes) {
    auto fail = [&](const std::string& what) {
        group.fail(ProcessFailure::kInternal, "cannot use the inputs rank 0 sent: " + what);
        throw std::logic_error("cannot use the inputs the lead process sent: " + what);
    };
    RunInputs in;
    in.scene = std::make_unique<SceneInput>();
    const SourceFile& file = in.scene->sources.add("<the scene from rank 0>", data.at("scene").get<std::string>());
    DiagnosticSink sink;
    in.scene->scene = load_scene_json(file, ".", in.scene->sources, sink);
    if (!in.scene->scene || sink.has_errors()) fail("the scene: " + render_text(sink.sorted()));
    in.scene->scene->source = data.at("scene_source").get<std::string>();
    in.scene_spec = data.at("scene_spec").get<std::string>();
    in.source = std::make_unique<SourceFile>("<the plan from rank 0>", data.at("plan").get<std::string>());
    auto kept = read_plan(*in.source, sink);
    if (!kept) fail("the plan: " + render_text(sink.sorted()));
    in.plan.program = kept->program;
    if (kept->pipeline) in.plan = std::move(*kept->pipeline);
    in.planned = true;
    if (data.contains("profile")) {
        ProfileInput profile;
        if (std::string error = read_profile(data["profile"].get<std::string>(), profile); !error.empty()) fail("the profile: " + error);
        in.profile = std::move(profile);
    }
    if (data.value("ic_file_bytes", false)) in.ic_file_bytes = ic_bytes;
    return in;
}

}  // namespace

RunInputs share_run_inputs(ProcessGroup& group, const std::function<RunInputs()>& read) {
    if (!group.distributed()) return read();
    if (group.leads()) {
        RunInputs in;
        nlohmann::json data;
        std::string ic_bytes;
        try {
            in = read();
            if (in.status == 0) data = inputs_as_data(in, ic_bytes);
        } catch (...) {  // a bug or an I/O failure: the others still learn that nothing runs
            group.share_from_lead(nlohmann::json{{"status", kExitFailure}}.dump(), kWhat);
            throw;
        }
        if (in.status != 0) data = {{"status", in.status}};
        group.share_from_lead(text_of(data), kWhat);
        if (in.status == 0) group.share_from_lead(std::move(ic_bytes), "the irradiance cache file's records");
        return in;
    }
    const nlohmann::json data = nlohmann::json::parse(group.share_from_lead("", kWhat));
    if (data.contains("status")) {  // the lead said why; this process stops with the same status
        RunInputs none;
        none.status = data["status"].get<int>();
        return none;
    }
    const std::string ic_bytes = group.share_from_lead("", "the irradiance cache file's records");
    return inputs_from_data(group, data, ic_bytes);
}

}  // namespace crex
