#include "runtime/api/run_summary.h"

#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <filesystem>
#include <optional>

#include "base/render_json.h"
#include "compiler/pipeline/settings_table.h"
#include "compiler/sched/print.h"

namespace crex {

nlohmann::json curve_json(const std::vector<CurvePoint>& curve) {
    nlohmann::json cj = nlohmann::json::array();
    for (const auto& c : curve)
        cj.push_back({{"seconds", c.seconds}, {"stage", c.stage}, {"event", c.event}, {"rmse", c.rmse}, {"flip", c.flip}, {"perr", c.perr}});
    return cj;
}

std::vector<Diagnostic> light_left_out_warnings(const RunResult& r, const ShadeParams& shade, const IcSettings* ic,
                                                 const LimitOrigins& origins) {
    std::vector<Diagnostic> out;
    auto say = [&](double share, const std::string& origin, const std::string& what, const std::string& fix) {
        if (!(share > kLightLeftOutWarning)) return;
        out.push_back(run_diagnostic("W404", origin.empty() ? "crex run" : origin,
                                     fmt::format("{} left out about {:.3g} % of the image's light (estimated; more than {:g} %): "
                                                 "the image is darker than the scene; {}",
                                                 what, 100 * share, 100 * kLightLeftOutWarning, fix)));
    };
    say(r.light_cut_by_depth, origins.max_depth, fmt::format("paths ended at max-depth {}", shade.max_depth),
        shade.max_depth < 65535 ? fmt::format("raise --max-depth (e.g. --max-depth {}; at most 65535)", std::min<uint32_t>(65535, shade.max_depth * 4 + 4))
                                : std::string("the scene traps light beyond what any depth limit renders"));
    say(r.light_cut_by_weight, origins.lw, fmt::format("rays dropped below lw {:g} without Russian roulette", shade.weight_limit),
        "leave out --no-roulette (roulette keeps the image unbiased) or lower --lw");
    if (ic)
        say(r.light_cut_by_cache, origins.ab, fmt::format("the irradiance cache's {} ambient bounces", ic->bounces),
            ic->bounces < 64 ? fmt::format("raise --ab (e.g. --ab {}; at most 64), or give --ambient a value for the rest",
                                           std::min<uint32_t>(64, ic->bounces * 2))
                             : std::string("give --ambient a value for the rest"));
    return out;
}

namespace {

// Where a pipeline's samples went (issue 38): the mean samples per pixel in the tenth of
// pixels where the map that varies spp is highest, and in the tenth where it is lowest.
struct SamplesByMap {
    std::string map;
    double highest_tenth = 0, lowest_tenth = 0;
};

std::optional<SamplesByMap> samples_by_map(const RunResult& r, const PipelinePlan& plan) {
    const PlanVariable* spp = nullptr;
    for (const PlanVariable& v : plan.variables)
        if (v.variable == pipeline::SelectiveVariable::kSpp) spp = &v;
    if (!spp) return std::nullopt;
    std::string shown = spp->map;  // the map's name as RunResult::maps holds it
    for (const PlanMap& m : plan.maps)
        if (m.id == spp->map) shown = !m.defines.empty() ? m.defines : (!m.name.empty() ? m.name : m.id);
    const guidance::Raster* map = nullptr;
    for (const auto& [name, raster] : r.maps)
        if (name == shown) map = &raster;
    const size_t pixels = r.film.pixel_count();
    if (!map || map->channels != 1 || map->pixels() != pixels || pixels < 10) return std::nullopt;
    std::vector<std::pair<float, uint32_t>> by_value(pixels);
    for (size_t p = 0; p < pixels; ++p) by_value[p] = {map->v[p], r.film.samples(static_cast<uint32_t>(p))};
    std::stable_sort(by_value.begin(), by_value.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    const size_t tenth = pixels / 10;
    auto mean = [&](size_t from, size_t to) {
        double sum = 0;
        for (size_t k = from; k < to; ++k) sum += by_value[k].second;
        return sum / static_cast<double>(to - from);
    };
    return SamplesByMap{shown, mean(pixels - tenth, pixels), mean(0, tenth)};
}

}  // namespace

nlohmann::json run_summary_json(const RunFacts& f) {
    const RunResult& r = *f.result;
    const ExecutorStats& st = r.stats;
    nlohmann::json j;
    j["scene"] = f.scene;
    j["crex"] = sched::to_crex(*f.program);
    j["size"] = {f.width, f.height};
    j["spp"] = f.spp;
    j["load_seconds"] = f.load_seconds;
    j["setup_seconds"] = r.setup_seconds;
    j["render_seconds"] = r.render_seconds;
    j["rays"] = total_rays(st);
    j["outputs"] = f.outputs;
    nlohmann::json comps;
    comps["camera"] = {{"rays", st.camera.rays}, {"shadow_rays", st.camera.shadow_rays}, {"seconds", st.camera.seconds}};
    for (size_t c = 0; c < kComponentCount; ++c) {
        const auto& s = st.components[c];
        comps[std::string(1, kComponentTable[c].letter)] = {{"executions", s.executions}, {"rays", s.rays},
                                                            {"shadow_rays", s.shadow_rays}, {"seconds", s.seconds},
                                                            {"rays_left", r.rays_left[c]}};
    }
    j["components"] = comps;
    j["warnings"] = f.load_warnings ? *f.load_warnings : nlohmann::json::array();
    for (auto& w : to_json(r.warnings)) j["warnings"].push_back(std::move(w));
    // Estimated shares of the image's light the limits left out (run_plan.h).
    j["light_left_out"] = {{"max_depth", r.light_cut_by_depth}, {"lw", r.light_cut_by_weight}, {"ab", r.light_cut_by_cache}};
    j["passes"] = r.passes;
    if (f.piped) {
        j["pipeline"] = f.plan->name;
        j["stages"] = {{"preview_seconds", f.piped->preview_seconds},
                       {"guidance_seconds", f.piped->guidance_seconds},
                       {"selective_seconds", f.piped->selective_seconds},
                       {"end_seconds", r.end_seconds},
                       {"preview_rays", f.piped->preview_rays},
                       {"selective_rays", f.piped->selective_rays}};
        j["preview_percent_of_time"] = r.render_seconds > 0 ? 100 * f.piped->preview_seconds / r.render_seconds : 0.0;
        j["preview_stride"] = f.preview_stride;
        j["preview_samples"] = f.piped->preview_samples;
        nlohmann::json maps = nlohmann::json::array();
        for (const auto& m : f.piped->maps) maps.push_back(m.first);
        j["maps"] = maps;
        j["notes"] = f.piped->notes;
        if (auto by = samples_by_map(*f.piped, *f.plan))
            j["samples_by_map"] = {{"map", by->map}, {"highest_tenth_spp", by->highest_tenth}, {"lowest_tenth_spp", by->lowest_tenth}};
        if (f.piped->direct_light_redone)  // progressive direct light: preview samples given their pixel's shadow_rays
            j["preview_direct_light_redone"] = {{"samples", f.piped->direct_light_redone},
                                                {"shadow_rays", f.piped->direct_light_redone_shadow_rays}};
        if (f.piped->subsample) j["subsampled_pixels_rendered"] = f.piped->subsample->rendered_count();
        if (f.piped->component_subsample.any()) {  // capict: per component, the pixels its first bounces ran in
            nlohmann::json corners = nlohmann::json::object();
            for (size_t c = 0; c < kComponentCount; ++c)
                if (const auto& g = f.piped->component_subsample.grid(static_cast<Component>(c)))
                    corners[std::string(1, kComponentTable[c].letter)] = g->rendered_count();
            j["component_subsampled_pixels_rendered"] = corners;
            j["component_subsample_refinements"] = f.piped->refinements;
        }
    }
    if (f.recorder) j["checkpoint_seconds"] = f.recorder->paused_seconds();
    if (r.textures) j["textures"] = to_json(*r.textures, r.render_thread_seconds, r.render_cpu_seconds);
    if (f.ic) {
        const IcStats& ic = r.ic_stats;
        j["irradiance_cache"] = {{"aa", f.ic->accuracy}, {"ad", f.ic->divisions}, {"ab", f.ic->bounces}, {"records", r.ic_records.size()},
                                 {"records_made", ic.records}, {"records_loaded", f.ic_loaded},
                                 {"lookups", ic.lookups}, {"interpolated_at_first_lookup", ic.interpolated},
                                 {"hemisphere_rays", ic.hemisphere_rays}, {"rounds", ic.rounds},
                                 {"caustic_photons", ic.caustic_photons}, {"caustic_map_seconds", r.caustic_map_seconds + ic.caustic_seconds},
                                 {"lookup_seconds", ic.lookup_seconds}, {"record_seconds", ic.record_seconds},
                                 {"caustic_lookup_seconds", ic.caustic_lookup_seconds}, {"over_limit", ic.over_limit},
                                 {"hot_surface_triangles", ic.hot_triangles}, {"hot_surface_points", ic.hot_points}};
        if (f.piped) {
            j["irradiance_cache"]["preview_records"] = f.piped->ic_preview_records;
            j["irradiance_cache"]["reprocessed_preview_samples"] = f.piped->ic_reprocessed;
            j["irradiance_cache"]["selective_records"] = f.piped->ic_selective_records;
        }
    }
    if (!f.maps_dir.empty() && f.pictures) {
        j["pictures"] = f.pictures->written;
        j["rays_per_pixel"] = {{"mean", f.pictures->mean_rays_per_pixel}, {"max", f.pictures->max_rays_per_pixel}};
    }
    if (f.budget > 0) {
        j["budget_seconds"] = f.budget;
        j["overshoot_percent"] = (r.render_seconds - f.budget) / f.budget * 100;
        j["policy"] = std::string(pipeline::name_of(r.policy));
        j["camera_samples_left_out"] = r.budget_stopped_samples;
        if (f.budget_floor > 0) j["budget_floor_seconds"] = f.budget_floor;  // at least this (fixed_costs.h)
        j["budget_below_floor"] = f.below_floor;  // rendered anyway: the budget is broken
        nlohmann::json skipped = nlohmann::json::array();
        for (const auto& sk : st.skipped)
            skipped.push_back({{"task", sk.what}, {"predicted_seconds", sk.predicted}, {"remaining_seconds", sk.remaining}});
        j["skipped_tasks"] = skipped;
    }
    if (f.predicted) {
        nlohmann::json e = nlohmann::json::object();
        for (const auto& [what, percent] : profile_errors(*f.predicted, st)) e[what] = percent;
        j["profile_error_percent"] = e;
    }
    return j;
}

std::vector<std::pair<std::string, double>> profile_errors(const Profile& predicted, const ExecutorStats& measured) {
    std::vector<std::pair<std::string, double>> out;
    auto add = [&](const std::string& what, std::optional<double> cost, const ComponentStats& s) {
        if (!cost || s.rays == 0 || !(s.seconds > 0)) return;
        const double actual = s.seconds / static_cast<double>(s.rays);
        out.push_back({what, (*cost - actual) / actual * 100});
    };
    add("camera", predicted.camera_cost(), measured.camera);
    for (size_t c = 0; c < kComponentCount; ++c)
        add(std::string(1, kComponentTable[c].letter), predicted.cost(static_cast<Component>(c)), measured.components[c]);
    return out;
}

void print_run_summary(const RunFacts& f, std::ostream& out) {
    const RunResult& r = *f.result;
    const ExecutorStats& st = r.stats;
    if (f.piped) {
        uint32_t lo = UINT32_MAX, hi = 0;
        for (uint32_t p = 0; p < r.film.pixel_count(); ++p)
            lo = std::min(lo, r.film.samples(p)), hi = std::max(hi, r.film.samples(p));
        std::string pre = sched::to_crex(f.program->preselective), sel = sched::to_crex(f.program->selective);
        out << fmt::format("rendered {} with pipeline {} (pre-selective {}, selective {}) at {}x{}, {} spp\n", f.scene,
                           f.plan->name, pre.empty() ? "camera rays" : pre, sel.empty() ? "no crex" : sel, f.width,
                           f.height, lo == hi ? std::to_string(lo) : fmt::format("{}..{}", lo, hi));
    } else {
        out << fmt::format("rendered {} with {} at {}x{}, {} spp\n", f.scene, sched::to_crex(*f.program), f.width,
                           f.height, f.spp);
    }
    out << fmt::format("  scene load {:.3f} s, setup (BVH, caustic map) {:.3f} s, render {:.3f} s ({:.2f} M rays/s) in {} sample pass{}\n",
                       f.load_seconds, r.setup_seconds, r.render_seconds,
                       r.render_seconds > 0 ? total_rays(st) / 1e6 / r.render_seconds : 0.0, r.passes, r.passes == 1 ? "" : "es");
    if (f.piped) {
        double total = std::max(r.render_seconds, 1e-12);
        out << fmt::format("  pipeline {}: preview {:.3f} s ({:.0f} % of the render), guidance {:.3f} s, selective {:.3f} s\n",
                           f.plan->name, f.piped->preview_seconds, 100 * f.piped->preview_seconds / total,
                           f.piped->guidance_seconds, f.piped->selective_seconds);
        if (!f.piped->maps.empty()) {
            std::string names;
            for (const auto& m : f.piped->maps) names += (names.empty() ? "" : ", ") + m.first;
            out << "  maps: " << names << "\n";
        }
        if (auto by = samples_by_map(*f.piped, *f.plan))
            out << fmt::format("  samples follow {}: {:.1f} spp in the tenth of pixels where it is highest, {:.1f} where it is lowest\n",
                               by->map, by->highest_tenth, by->lowest_tenth);
    }
    out << "  bin       steps        rays  shadow rays   seconds   M rays/s   left at end\n";
    auto row = [&](const std::string& name, const ComponentStats& s, const std::string& steps, size_t left) {
        out << fmt::format("  {:<8} {:>6} {:>11} {:>12} {:>9.3f} {:>10.2f} {:>13}\n", name, steps, s.rays, s.shadow_rays,
                           s.seconds, s.seconds > 0 ? s.rays / 1e6 / s.seconds : 0.0, left);
    };
    row("camera", st.camera, "-", 0);
    for (size_t c = 0; c < kComponentCount; ++c)
        if (st.components[c].rays > 0 || r.rays_left[c] > 0)
            row(std::string(1, kComponentTable[c].letter), st.components[c], std::to_string(st.components[c].executions),
                r.rays_left[c]);
    if (f.budget > 0) {
        out << fmt::format("  budget {:.3f} s ({}), actual {:.3f} s, overshoot {:+.1f} %, {} task{} skipped, {} camera sample{} left out\n",
                           f.budget, pipeline::name_of(r.policy), r.render_seconds, (r.render_seconds - f.budget) / f.budget * 100,
                           st.skipped.size(), st.skipped.size() == 1 ? "" : "s", r.budget_stopped_samples,
                           r.budget_stopped_samples == 1 ? "" : "s");
        for (const auto& sk : st.skipped)
            out << fmt::format("    skipped {} (predicted {:.3f} s, {:.3f} s left)\n", sk.what, sk.predicted, sk.remaining);
        if (f.piped && f.preview_stride > 1)
            out << fmt::format("  the preview stopped at every {}{} pixel (finer levels only within {:.0f} % of the budget; the "
                               "coarsest always runs); the selective stage renders the rest\n",
                               f.preview_stride, f.preview_stride == 2 ? "nd" : "th", 100 * kPreviewShare);
        if (f.below_floor)
            out << fmt::format("  budget BROKEN: {:.3f} s is below this pipeline's floor of {:.3f} s (--budget-floor ok)\n", f.budget,
                               f.budget_floor);
    }
    if (f.predicted) {
        std::string line;
        for (const auto& [what, percent] : profile_errors(*f.predicted, st)) line += fmt::format("{}{} {:+.1f} %", line.empty() ? "" : ", ", what, percent);
        if (!line.empty()) out << "  profile's cost per ray against this run's: " << line << "\n";
    }
    if (r.textures) {
        // What crex answered itself, beside the TextureSystem's timed lookups.
        std::string own;
        if (r.textures->coarse_lookups > 0) own = fmt::format("{} from coarse copies", r.textures->coarse_lookups);
        if (r.textures->mask_lookups > 0)
            own += fmt::format("{}{} cut-out tests from opacity masks", own.empty() ? "" : ", ", r.textures->mask_lookups);
        out << fmt::format("  textures: {} image{}, {} lookups{}, {:.1f} % of the render's thread time; cache {:.1f} of {:.0f} MiB, {:.1f} MiB read\n",
                           r.textures->images.size(), r.textures->images.size() == 1 ? "" : "s", r.textures->lookups,
                           own.empty() ? "" : " (and " + own + ")",
                           r.render_thread_seconds > 0 ? 100 * r.textures->lookup_seconds / r.render_thread_seconds : 0.0,
                           r.textures->cache.memory_bytes / double(1 << 20), r.textures->cache.memory_limit / double(1 << 20),
                           r.textures->cache.bytes_read / double(1 << 20));
    }
    if (!f.ic_file.empty())
        out << fmt::format("  irradiance cache {}: {} records loaded, {} made, {} saved\n", f.ic_file, f.ic_loaded,
                           r.ic_stats.records, r.ic_records.size());
    for (const auto& p : f.outputs) out << "  wrote " << p << "\n";
    if (f.curve && !f.curve->empty())
        out << fmt::format("  error against {}: RMSE {:.4g} -> {:.4g}, FLIP {:.4f} -> {:.4f} over {} checkpoints\n", f.reference,
                           f.curve->front().rmse, f.curve->back().rmse, f.curve->front().flip, f.curve->back().flip, f.curve->size());
    if (!f.report_dir.empty()) out << "  wrote the report " << (std::filesystem::path(f.report_dir) / "index.html").string() << "\n";
    if (!f.maps_dir.empty() && f.pictures)
        out << fmt::format("  wrote {} pictures to {} (rays per pixel: mean {:.1f}, max {:.0f})\n", f.pictures->written.size(),
                           f.maps_dir, f.pictures->mean_rays_per_pixel, f.pictures->max_rays_per_pixel);
}

}  // namespace crex
