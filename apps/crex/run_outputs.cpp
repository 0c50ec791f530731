#include "apps/crex/run_outputs.h"

#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <filesystem>
#include <iostream>

#include "apps/crex/exit_codes.h"
#include "apps/crex/run_pictures.h"
#include "apps/crex/run_report.h"
#include "apps/crex/run_resume.h"
#include "apps/crex/run_summary.h"
#include "compiler/plan/emit_plan.h"
#include "compiler/plan/plan_pipeline.h"
#include "compiler/sched/print.h"
#include "runtime/base/atomic_file.h"
#include "runtime/base/output_set.h"
#include "runtime/io/image_io.h"

namespace crex::app {

int write_run_outputs(const RunOptions& opt, const RunInput& in, const RunSetup& setup, const RunResult& result,
                      const CheckpointRecorder* recorder, const std::vector<PolicyRun>& other_policies) {
    const RunSettings& rs = setup.settings;
    const int width = rs.width, height = rs.height;
    const bool guided = result.staged;
    // Each note once, in first-said order: every round of the cyclic process may say the same thing.
    std::vector<std::pair<std::string, int>> said;
    for (const auto& note : result.notes) {
        auto it = std::find_if(said.begin(), said.end(), [&](const auto& s) { return s.first == note; });
        if (it == said.end()) said.emplace_back(note, 1);
        else ++it->second;
    }
    for (const auto& [note, times] : said)
        std::cerr << "crex run: note: " << note << (times > 1 ? fmt::format(" ({} times)", times) : "") << "\n";
    if (setup.resume) say_resumed(*setup.resume, rs, result, std::cerr);
    for (const auto& w : result.warnings) std::cerr << w << "\n";
    // All or none: every file goes to a staged name first and moves into place at the end, so
    // a failure at the report leaves the images the user had (issue 16).
    OutputSet files;
    if (!opt.profile_out.empty()) {
        auto j = nlohmann::json::parse(setup.profile.to_json_text());
        j["full_render_seconds"] = setup.budget > 0 ? setup.full_render_seconds : result.render_seconds;
        std::string error = write_file_atomically(files.stage_file(opt.profile_out), j.dump(2) + "\n");
        if (!error.empty()) {
            std::cerr << fmt::format("crex run: error: cannot write profile '{}': {}\n", opt.profile_out, files.in_user_terms(error));
            return kExitFailure;
        }
    }

    std::vector<ImageLayer> layers = {{"", result.image()}};
    if (setup.resume) take_resumed_rows(*setup.resume, layers.front().rgb, width);
    if (opt.components)
        for (size_t a = 0; a < kAovCount; ++a) layers.push_back({aov_name(a), result.aov_image(a)});
    // What made the image, in its header (EXR), so a file found later says how to make it again.
    uint32_t min_spp = UINT32_MAX, max_spp = 0;
    for (uint32_t p = 0; p < result.film.pixel_count(); ++p)
        if (!setup.resume || !setup.resume->final_rows[p / static_cast<uint32_t>(width)])  // those rows' samples are not in this film
            min_spp = std::min(min_spp, result.film.samples(p)), max_spp = std::max(max_spp, result.film.samples(p));
    ImageMetadata metadata = {
        {"Software", std::string("crex ") + CREX_VERSION},
        {"crex:version", CREX_VERSION},
        {"crex:scene", in.scene_spec},
        {"crex:crex", sched::to_crex(in.plan.program)},
        {"crex:spp", min_spp == max_spp ? std::to_string(max_spp) : fmt::format("{}..{}", min_spp, max_spp)},
        {"crex:seed", std::to_string(rs.seed)},
        {"crex:render_seconds", fmt::format("{:.6g}", result.render_seconds)},
    };
    if (in.pipeline) metadata.push_back({"crex:pipeline", in.plan.name + (opt.plan.empty() ? "" : " (" + opt.plan + ")")});
    if (setup.budget > 0) metadata.push_back({"crex:budget_seconds", fmt::format("{:.6g}", setup.budget)});
    if (setup.resume) metadata.push_back({"crex:resumed", fmt::format("rows {} from {}", setup.resume->rows, setup.resume->path)});
    if (opt.clamp > 0) metadata.push_back({"crex:clamp_indirect", fmt::format("{:.6g} (biased)", opt.clamp)});
    for (const auto& path : setup.outputs) {
        std::string error = write_image(files.stage_file(path), width, height, layers, metadata);
        if (!error.empty()) {
            std::cerr << "crex run: error: " << files.in_user_terms(error) << "\n";
            return kExitFailure;
        }
    }

    PictureSummary staged_pictures, pictures;  // paths where they are written, and where they will be
    if (!setup.maps_dir.empty()) {
        std::string error = write_run_pictures(files.stage_dir(setup.maps_dir), result.film, guided ? &result.preview : nullptr,
                                               result.maps, staged_pictures);
        if (!error.empty()) {
            std::cerr << "crex run: error: " << files.in_user_terms(error) << "\n";
            return kExitFailure;
        }
        pictures = staged_pictures;
        for (std::string& p : pictures.written) p = files.destination_of(p);
    }

    RunFacts facts;
    facts.scene = in.scene->scene->source;
    facts.program = &in.plan.program;
    facts.width = width, facts.height = height;
    facts.spp = rs.spp;
    facts.load_seconds = in.load_seconds;
    facts.result = &result;
    facts.piped = guided ? &result : nullptr;
    facts.plan = in.pipeline ? &in.plan : nullptr;
    facts.outputs = setup.outputs;
    facts.budget = setup.budget;
    facts.recorder = recorder;
    facts.ic = rs.irradiance_cache ? &*rs.irradiance_cache : nullptr;
    facts.ic_loaded = result.ic_loaded + rs.ic_records.size();
    facts.ic_file = rs.ic_file;
    facts.maps_dir = setup.maps_dir;
    facts.pictures = &pictures;
    facts.report_dir = opt.report_dir;
    facts.predicted = setup.predicted ? &*setup.predicted : nullptr;
    nlohmann::json j = run_summary_json(facts);  // printed with --format json, and the report's
    std::vector<CurvePoint> curve;
    if (recorder) {
        RunReport report;
        if (!opt.report_dir.empty()) report.dir = files.stage_dir(opt.report_dir);
        report.title = fmt::format("crex run: {} on {}", in.pipeline ? "pipeline " + in.plan.name : sched::to_crex(in.plan.program),
                                   in.scene->scene->source);
        report.width = width, report.height = height;
        report.checkpoints = &recorder->checkpoints();
        report.policy = std::string(pipeline::name_of(result.policy));
        for (const auto& [name, checkpoints] : other_policies) report.other_policies.push_back({name, &checkpoints});
        report.reference = setup.reference;
        report.reference_path = setup.reference_file;
        report.view = {true, setup.reference ? display_exposure(setup.reference->rgb) : 1.0};
        if (setup.budget > 0) report.budget_seconds = setup.budget;
        report.summary = j;
        report.images.push_back({"final image", layers.front().rgb});
        if (guided) report.images.push_back({"preview", result.preview});
        if (setup.reference) report.images.push_back({"reference", setup.reference->rgb});
        // Components no ray reached (a bin the scene or the crex never fills) would be black tiles.
        for (size_t a = 0; a < kAovCount; ++a) {
            std::vector<float> aov = result.aov_image(a);
            if (std::any_of(aov.begin(), aov.end(), [](float v) { return v != 0; }))
                report.images.push_back({"component " + aov_name(a), std::move(aov)});
        }
        report.maps = result.maps;
        report.pictures = staged_pictures.written;
        report.picture_scales = staged_pictures.heat_scale;
        if (in.pipeline) {
            report.plan_dot = pipeline_plan_to_dot(in.plan);
        } else {
            CrexPlan cp;
            cp.source = in.source->text();
            cp.program = in.plan.program;
            report.plan_dot = plan_to_dot(cp);
        }
        if (opt.report_dir.empty()) {  // a reference without a report: the curve only, in the summary
            curve = error_curve(recorder->checkpoints(), *setup.reference, report.view);
        } else if (std::string error = write_run_report(report, curve); !error.empty()) {
            std::cerr << "crex run: error: report: " << files.in_user_terms(error) << "\n";
            return kExitFailure;
        }
        if (!curve.empty()) {
            j["error_curve"] = curve_json(curve);
            j["reference"] = setup.reference_file;
        }
        if (!opt.report_dir.empty()) j["report"] = (std::filesystem::path(opt.report_dir) / "index.html").string();
    }
    if (std::string error = files.commit(); !error.empty()) {
        std::cerr << "crex run: error: " << error << "\n";
        return kExitFailure;
    }
    if (opt.format == "json") {
        std::cout << j.dump(2) << "\n";
        return kExitOk;
    }
    if (opt.quiet) return kExitOk;
    facts.curve = &curve;
    facts.reference = setup.reference_file;
    print_run_summary(facts, std::cout);
    return kExitOk;
}

}  // namespace crex::app
