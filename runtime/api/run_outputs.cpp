#include "runtime/api/run_outputs.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstring>
#include <filesystem>
#include <map>

#include "base/fnv1a.h"
#include "base/image_formats.h"
#include "compiler/plan/emit_plan.h"
#include "compiler/plan/plan_pipeline.h"
#include "compiler/sched/print.h"
#include "runtime/base/atomic_file.h"
#include "runtime/base/output_folder.h"
#include "runtime/base/output_set.h"
#include "runtime/io/image_io.h"
#include "runtime/render/render_scene.h"
#include "runtime/report/run_report.h"

namespace crex {

std::string check_output_path(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::is_directory(path, ec)) return fmt::format("-o {}: is a directory; give a file name such as {}/render.exr", path, path);
    if (!is_image_file_name(path)) {
        const std::string ext = image_extension(path);
        return fmt::format("-o {}: unknown image format '{}'; crex writes {}", path, ext.empty() ? "(no extension)" : ext, image_formats_text());
    }
    if (std::string missing = missing_output_folder(path); !missing.empty()) return missing;
    fs::path dir = fs::path(path).parent_path();
    if (dir.empty()) dir = ".";
    // Writable: a file can be made (and is removed) where the image will go.
    std::string probe = (dir / ".crex-write-check-XXXXXX").string();
    int fd = ::mkstemp(probe.data());
    if (fd < 0) return fmt::format("-o {}: cannot write in {}: {}", path, dir.string(), std::strerror(errno));
    ::close(fd);
    ::unlink(probe.c_str());
    return {};
}

std::vector<float> final_image(const RunRecord& record) {
    const RunResult& result = *record.outcome->result;
    std::vector<float> rgb = result.image();
    if (record.resumed) take_resumed_rows(*record.resumed, rgb, result.film.width());
    return rgb;
}

RunFacts run_facts(const RunFiles& files, const RunRecord& record, const WrittenRun* written) {
    const RunInputs& in = *record.inputs;
    const RunSettings& rs = record.outcome->run.settings;
    const RunResult& result = *record.outcome->result;
    RunFacts facts;
    facts.scene = in.scene->scene->source;
    facts.program = &in.plan.program;
    facts.width = rs.width, facts.height = rs.height;
    facts.spp = rs.spp;
    facts.load_seconds = in.load_seconds;
    facts.result = &result;
    facts.piped = result.staged ? &result : nullptr;
    facts.plan = in.plan.staged ? &in.plan : nullptr;
    facts.outputs = files.images;
    facts.budget = record.outcome->run.budget_seconds;
    facts.recorder = record.checkpoints;
    facts.ic = rs.irradiance_cache ? &*rs.irradiance_cache : nullptr;
    facts.ic_loaded = result.ic_loaded + rs.ic_records.size() + (rs.ic_grids ? rs.ic_grids->handed : 0);
    facts.ic_file = rs.ic_file;
    facts.maps_dir = files.maps_dir;
    facts.report_dir = files.report_dir;
    facts.predicted = record.outcome->run.predicted ? &record.outcome->run.predicted->profile : nullptr;
    facts.preview_stride = result.preview_stride;
    facts.budget_floor = record.outcome->run.fixed_costs ? record.outcome->run.fixed_costs->floor_seconds : 0;
    facts.below_floor = record.outcome->run.below_floor;
    facts.load_warnings = &in.load_warnings;
    if (written) {
        facts.pictures = &written->pictures;
        facts.curve = &written->curve;
        facts.reference = record.reference_path;
    }
    return facts;
}

namespace {

// What made the image, in its header (EXR, typed: numbers as ints and floats, the view as
// matrices), so a file found later says how to make it again and where its camera stood.
ImageMetadata image_header(const RunRecord& record) {
    const RunInputs& in = *record.inputs;
    const RunOutcome& outcome = *record.outcome;
    const RunSettings& rs = outcome.run.settings;
    const RunResult& result = *outcome.result;
    const int width = rs.width;
    int min_spp = INT_MAX, max_spp = 0;
    for (uint32_t p = 0; p < result.film.pixel_count(); ++p)
        if (!record.resumed || !record.resumed->final_rows[p / static_cast<uint32_t>(width)]) {  // those rows' samples are not in this film
            const int spp = static_cast<int>(std::min<uint32_t>(result.film.samples(p), INT_MAX));
            min_spp = std::min(min_spp, spp), max_spp = std::max(max_spp, spp);
        }
    if (min_spp > max_spp) min_spp = max_spp;
    ImageMetadata metadata = {
        {"Software", std::string("crex ") + CREX_VERSION},
        {"crex:version", CREX_VERSION},
        {"crex:scene", in.scene_spec},
        {"crex:crex", sched::to_crex(in.plan.program)},
        {"crex:spp_min", min_spp},
        {"crex:spp_max", max_spp},
        {"crex:render_seconds", static_cast<float>(result.render_seconds)},
        {"chromaticities", kRec709Chromaticities},
    };
    // An int where it fits; OpenEXR has no 64-bit integer, so a larger seed is kept as its digits.
    if (rs.seed <= static_cast<uint64_t>(INT_MAX)) metadata.push_back({"crex:seed", static_cast<int>(rs.seed)});
    else metadata.push_back({"crex:seed", std::to_string(rs.seed)});
    if (in.plan.staged) {
        metadata.push_back({"crex:pipeline", in.plan.name});
        if (!record.plan_file.empty()) metadata.push_back({"crex:pipeline_file", record.plan_file});
        // The compiled plan's identity: the same hash means the same steps, maps and settings.
        metadata.push_back({"crex:pipeline_hash", hex16(fnv1a64(pipeline_plan_to_json(in.plan).dump()))});
    }
    if (outcome.run.budget_seconds > 0) metadata.push_back({"crex:budget_seconds", static_cast<float>(outcome.run.budget_seconds)});
    const Camera& c = in.scene->scene->camera;
    const CameraRays view(c, rs.width, rs.height, Vec3{});
    std::array<double, 16> m;
    auto matrix = [](const std::array<double, 16>& d) {
        Matrix44 f;
        std::transform(d.begin(), d.end(), f.m.begin(), [](double v) { return static_cast<float>(v); });
        return f;
    };
    if (view.world_to_camera(m)) metadata.push_back({"worldToCamera", matrix(m)});
    if (view.world_to_ndc(m)) metadata.push_back({"worldToNDC", matrix(m)});
    if (record.frame >= 0) {  // which frame of a sequence, and the camera its path gave it (as a RADIANCE view)
        metadata.push_back({"crex:frame", static_cast<int>(record.frame)});
        // With the path's field of view (crex compare --flicker traces each frame from this).
        std::string fov = c.vfov_deg > 0 ? fmt::format(" -vv {:.9g}", c.vfov_deg) : "";
        if (c.hfov_deg > 0) fov += fmt::format(" -vh {:.9g}", c.hfov_deg);
        metadata.push_back({"crex:view", fmt::format("-vp {:.9g} {:.9g} {:.9g} -vd {:.9g} {:.9g} {:.9g} -vu {:.9g} {:.9g} {:.9g}{}",
                                                     c.position.x, c.position.y, c.position.z, c.direction.x, c.direction.y,
                                                     c.direction.z, c.up.x, c.up.y, c.up.z, fov)});
    }
    if (record.resumed) metadata.push_back({"crex:resumed", fmt::format("rows {} from {}", record.resumed->rows, record.resumed->path)});
    // A biased render says so: indirect light clamped at this value.
    if (const double clamp = rs.executor.clamp_indirect; clamp > 0) metadata.push_back({"crex:clamp_indirect", static_cast<float>(clamp)});
    return metadata;
}

// `-o X -o X` once wrote the second over the first, and the commit then failed after the old X
// was gone: outputs are compared as absolute, normalised paths, before rendering.
std::string same_output_twice(const RunFiles& files, const std::string& ic_file) {
    std::vector<std::pair<std::string, std::string>> named;  // (flag, path)
    for (const auto& o : files.images) named.push_back({"-o", o});
    if (!files.profile.empty()) named.push_back({"--save-profile", files.profile});
    if (!ic_file.empty()) named.push_back({"--ic-file", ic_file});
    if (!files.maps_dir.empty()) named.push_back({"--maps", files.maps_dir});
    if (!files.report_dir.empty()) named.push_back({"--report", files.report_dir});
    std::map<std::string, size_t> seen;
    for (size_t i = 0; i < named.size(); ++i) {
        std::error_code ec;
        std::filesystem::path p = std::filesystem::weakly_canonical(std::filesystem::absolute(named[i].second, ec), ec);
        std::string key = (p.filename().empty() ? p.parent_path() : p).lexically_normal().string();
        auto [it, fresh] = seen.try_emplace(key, i);
        if (fresh) continue;
        const auto& first = named[it->second];
        return fmt::format("{} {} and {} {} name the same path: each output needs its own", first.first, first.second, named[i].first,
                           named[i].second);
    }
    return "";
}

}  // namespace

std::string outputs_refusal(const RunFiles& files, const std::string& ic_file, bool& usage) {
    usage = false;
    for (const auto& path : files.images)
        if (std::string error = check_output_path(path); !error.empty()) return error;
    for (const auto& path : {files.maps_dir, files.report_dir, files.profile, ic_file})
        if (std::string error = path.empty() ? "" : missing_output_folder(path); !error.empty()) return error;
    std::error_code ec;
    if (!files.maps_dir.empty() && std::filesystem::exists(files.maps_dir, ec) && !std::filesystem::is_directory(files.maps_dir, ec))
        return fmt::format("--maps {}: is a file; give a directory", files.maps_dir);
    // The report replaces its folder whole, so that folder must be a report (or new, or empty).
    if (std::string refusal = files.report_dir.empty() ? "" : report_folder_refusal(files.report_dir); !refusal.empty()) return refusal;
    std::string clash = same_output_twice(files, ic_file);
    usage = !clash.empty();
    return clash;
}

StageCosts measured_stage_costs(const RunResult& result, int width, int height) {
    return {result.preview_seconds, result.preview_samples, result.guidance_seconds,
            static_cast<uint64_t>(width) * static_cast<uint64_t>(height), result.ic_stats.caustic_seconds,
            result.ic_preview_records, result.ic_preview_record_seconds,
            result.budgeted_end_seconds > 0 ? result.budgeted_end_seconds : result.end_seconds, result.strided_preview_seconds};
}

RunImages run_images(const RunFiles& files, const RunRecord& record) {
    const RunResult& result = *record.outcome->result;
    RunImages images;
    images.paths = files.images;
    images.width = record.outcome->run.settings.width, images.height = record.outcome->run.settings.height;
    images.layers = {{"", final_image(record)}};
    if (files.components)
        for (size_t a = 0; a < kAovCount; ++a) images.layers.push_back({aov_name(a), result.aov_image(a)});
    images.metadata = image_header(record);
    return images;
}

namespace {

// Each image of `images` written to its staged name in `files`: "" or what failed.
std::string stage_run_images(OutputSet& files, const RunImages& images) {
    for (const auto& path : images.paths)
        if (std::string error = write_image(files.stage_file(path), images.width, images.height, images.layers, images.metadata); !error.empty())
            return files.in_user_terms(error);
    return "";
}

}  // namespace

std::string write_run_images(const RunImages& images) {
    OutputSet files;
    if (std::string error = stage_run_images(files, images); !error.empty()) return error;
    return files.commit();
}

std::string write_run_files(const RunFiles& where, const RunRecord& record, WrittenRun& written) {
    const RunInputs& in = *record.inputs;
    const RunOutcome& outcome = *record.outcome;
    const RunSettings& rs = outcome.run.settings;
    const RunResult& result = *outcome.result;
    const int width = rs.width, height = rs.height;
    // All or none: every file goes to a staged name first and moves into place at the end, so
    // a failure at the report leaves the images the user had (issue 16).
    OutputSet files;
    if (!where.profile.empty()) {
        // A budgeted render is not a full one: the profile's own full render time is kept.
        const auto& predicted = outcome.run.predicted;
        const bool full_render = !(outcome.run.budget_seconds > 0);
        const double full = full_render ? result.render_seconds : predicted ? predicted->full_render_seconds : 0;
        // So are its stage costs (what a later budget sizes the preview from): this render's
        // when it is a full one of a pipeline, else the profile's own.
        StageCosts stages = predicted ? predicted->stages : StageCosts{};
        if (full_render && result.staged) stages = measured_stage_costs(result, width, height);
        std::string error = write_file_atomically(files.stage_file(where.profile), profile_json_text(outcome.measured, full, stages));
        if (!error.empty()) return fmt::format("cannot write profile '{}': {}", where.profile, files.in_user_terms(error));
    }

    const RunImages images = run_images(where, record);
    const std::vector<ImageLayer>& layers = images.layers;
    if (std::string error = stage_run_images(files, images); !error.empty()) return error;

    PictureSummary staged_pictures;  // paths where they are written; `written.pictures`: where they will be
    if (!where.maps_dir.empty()) {
        std::string error = write_run_pictures(files.stage_dir(where.maps_dir), result.film, result.staged ? &result.preview : nullptr,
                                               result.maps, staged_pictures);
        if (!error.empty()) return files.in_user_terms(error);
        written.pictures = staged_pictures;
        for (std::string& p : written.pictures.written) p = files.destination_of(p);
    }

    written.summary = run_summary_json(run_facts(where, record, &written));  // --format json's, and the report's
    std::optional<EqualTimeScore> equal;  // --equal-time: both images scored, as a viewer sees them
    if (record.equal_time && record.reference) {
        std::string attention;
        const metrics::DisplayView view{true, display_exposure(record.reference->rgb)};
        const std::vector<float> weights = equal_time_attention(in.plan, result.maps, *record.reference, view, attention);
        equal = score_equal_time(layers.front().rgb, *record.equal_time, *record.reference, weights, attention);
        written.summary["equal_time"] = equal_time_json(*record.equal_time, *equal);
    }
    if (record.checkpoints) {
        RunReport report;
        if (!where.report_dir.empty()) {  // replaced whole: no picture of an earlier run stays
            if (std::string refusal = report_folder_refusal(where.report_dir); !refusal.empty()) return refusal;
            report.dir = files.stage_replacement_dir(where.report_dir);
        }
        report.title = fmt::format("crex run: {} on {}", in.plan.staged ? "pipeline " + in.plan.name : sched::to_crex(in.plan.program),
                                   in.scene->scene->source);
        report.width = width, report.height = height;
        report.checkpoints = &record.checkpoints->checkpoints();
        report.policy = std::string(pipeline::name_of(result.policy));
        for (const auto& [name, checkpoints] : record.other_policies) report.other_policies.push_back({name, &checkpoints});
        report.reference = record.reference;
        report.reference_path = record.reference_path;
        report.view = report_view(record.reference ? &*record.reference : nullptr);
        if (outcome.run.budget_seconds > 0) report.budget_seconds = outcome.run.budget_seconds;
        report.summary = written.summary;
        report.images.push_back({"final image", layers.front().rgb});
        if (result.staged) report.images.push_back({"preview", result.preview});
        if (record.reference) report.images.push_back({"reference", record.reference->rgb});
        // Components no ray reached (a bin the scene or the crex never fills) would be black tiles.
        for (size_t a = 0; a < kAovCount; ++a) {
            std::vector<float> aov = result.aov_image(a);
            if (std::any_of(aov.begin(), aov.end(), [](float v) { return v != 0; }))
                report.images.push_back({"component " + aov_name(a), std::move(aov)});
        }
        report.maps = result.maps;
        if (equal)
            report.equal_time = RunReport::EqualTime{
                fmt::format("pipeline {}, {:.3f} s", in.plan.name, result.render_seconds),
                fmt::format("uniform {}, {:.3f} s, {:.1f} spp", record.equal_time->crex, record.equal_time->render_seconds,
                            record.equal_time->mean_spp),
                fmt::format("Uniform rendering (crex {}{}) had the pipeline's render time as its budget. aFLIP weighs each pixel's FLIP by {}.",
                            record.equal_time->crex, record.equal_time->irradiance_cache ? ", through the cache" : "", equal->attention),
                layers.front().rgb, record.equal_time->image, equal->pipeline.flip_map, equal->uniform.flip_map};
        report.pictures = staged_pictures.written;
        report.picture_scales = staged_pictures.heat_scale;
        report.plan_dot = plan_dot_of(in);
        if (where.report_dir.empty()) {  // a reference without a report: the curve only, in the summary
            if (record.reference) written.curve = error_curve(record.checkpoints->checkpoints(), *record.reference, report.view);
        } else if (std::string error = write_run_report(report, written.curve); !error.empty()) {
            return "report: " + files.in_user_terms(error);
        }
        if (!written.curve.empty()) {
            written.summary["error_curve"] = curve_json(written.curve);
            written.summary["reference"] = record.reference_path;
        }
        if (!where.report_dir.empty()) written.summary["report"] = (std::filesystem::path(where.report_dir) / "index.html").string();
    }
    return files.commit();
}

metrics::DisplayView report_view(const metrics::Image* reference) { return {true, reference ? display_exposure(reference->rgb) : 1.0}; }

std::string plan_dot_of(const RunInputs& in) {
    if (in.plan.staged) return pipeline_plan_to_dot(in.plan);
    CrexPlan cp;
    cp.source = in.source ? in.source->text() : sched::to_crex(in.plan.program);
    cp.program = in.plan.program;
    return plan_to_dot(cp);
}

}  // namespace crex
