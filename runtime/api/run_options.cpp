#include "runtime/api/run_options.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>

namespace crex {

std::string profile_json_text(const Profile& profile, double full_render_seconds, const StageCosts& stages) {
    auto j = nlohmann::json::parse(profile.to_json_text());
    j["full_render_seconds"] = full_render_seconds;
    if (stages.known())
        j["stages"] = {{"preview_seconds", stages.preview_seconds},
                       {"preview_samples", stages.preview_samples},
                       {"guidance_seconds", stages.guidance_seconds},
                       {"pixels", stages.pixels},
                       {"preview_fixed_seconds", stages.preview_fixed_seconds},
                       {"preview_records", stages.preview_records},
                       {"preview_record_seconds", stages.preview_record_seconds},
                       {"end_seconds", stages.end_seconds},
                       {"strided_preview_seconds", stages.strided_preview_seconds}};
    return j.dump(2) + "\n";
}

namespace {

// Where a budget was set, for what is said about it: "" for --budget, else the plan's line.
std::string budget_origin(const RunOptions& o, const PlanBudget& budget) {
    return o.budget ? "" : budget.where.known() ? budget.where.to_string() : "the plan";
}

// A budget below the pipeline's floor (fixed_costs.h) is refused, unless the caller says to
// render anyway.
void refuse_below_floor(ResolvedRun& run, const RunOptions& o, const std::string& where) {
    const RunSettings& rs = run.settings;
    run.fixed_costs = predict_fixed_costs(run.predicted->stages, rs.width, rs.height, rs.spp);
    if (!run.fixed_costs || run.budget_seconds >= run.fixed_costs->floor_seconds) return;
    const double floor = run.fixed_costs->floor_seconds, full = run.predicted->full_render_seconds;
    const std::string share = full > 0 ? fmt::format(" ({:.1f} % of the profiled full render)", 100 * floor / full) : "";
    if (!o.budget_floor_ok)
        throw BudgetBelowFloor(fmt::format("{:.3g} s is below the smallest budget this pipeline can meet, {:.3g} s{}: {}; give a "
                                           "budget of at least that, or --budget-floor ok to render anyway (the budget will be broken)",
                                           run.budget_seconds, floor, share, describe_fixed_costs(*run.fixed_costs)),
                               where, floor);
    run.below_floor = true;
}

}  // namespace

void resolve_budget(ResolvedRun& run, const PipelinePlan& plan, const RunOptions& o) {
    const PlanSettings& ps = plan.settings;
    RunSettings& rs = run.settings;
    // The budget, and the profile it is predicted from.
    run.predicted = o.profile;
    run.budget_seconds = 0;
    run.fixed_costs.reset();
    run.below_floor = false;
    const std::optional<PlanBudget> budget = o.no_budget ? std::nullopt : o.budget ? o.budget : ps.budget;
    if (budget) {
        run.budget_seconds = budget->amount;
        if (budget->percent) {
            const double full = run.predicted ? run.predicted->full_render_seconds : 0;
            const std::string where = budget_origin(o, *budget);
            if (!(full > 0) && !run.predicted)
                throw RunOptionError("a budget in % needs the time of a full render: render once without a budget with "
                                     "--save-profile FILE, then pass --profile FILE (or --no-budget)",
                                     where);
            if (!(full > 0))
                throw RunOptionError(fmt::format("the profile '{}' holds no full render time (\"full_render_seconds\" above 0): save it "
                                                 "again with --save-profile from a render without a budget, or give the budget in seconds",
                                                 run.predicted->path),
                                     where, true);
            run.budget_seconds = budget->amount / 100 * full;
        }
    }
    rs.executor.budget_seconds = run.budget_seconds;
    // A pipeline's preview: the caller's stride, else coarse to fine under a budget (0), else every pixel.
    rs.preview_stride = o.preview_stride ? std::max<uint32_t>(1, *o.preview_stride) : budget && plan.staged ? 0 : 1;
    rs.end_seconds = 0;
    rs.time_strided_preview = o.saves_profile && plan.staged && !budget;
    if (budget && plan.staged && run.predicted) {
        refuse_below_floor(run, o, budget_origin(o, *budget));
        if (run.fixed_costs) rs.end_seconds = std::min(run.fixed_costs->end_seconds, run.budget_seconds / 2);
    }
}

ResolvedRun resolve_run(const PipelinePlan& plan, const RunOptions& o) {
    const PlanSettings& ps = plan.settings;
    ResolvedRun run;
    RunSettings& rs = run.settings;
    // Each setting: the option, else the plan's, else the default.
    rs.width = o.width.value_or(ps.width.value_or(256));
    rs.height = o.height.value_or(ps.height.value_or(256));
    rs.spp = o.spp.value_or(plan.staged ? ps.spp : 16);
    rs.seed = o.seed.value_or(ps.seed.value_or(0));
    rs.filter = o.filter;
    // A pipeline never shows black for skipped work unless it asked for an av (spec §6).
    const AmbientStandIn ambient = o.ambient   ? *o.ambient
                                   : ps.av     ? AmbientStandIn{false, *ps.av}
                                               : AmbientStandIn{plan.staged, 0};
    rs.ambient = {ambient.value, ambient.value, ambient.value};
    rs.ambient_auto = ambient.automatic;
    ShadeParams& shade = rs.executor.shade;
    shade.shadow_rays = o.shadow_rays.value_or(ps.shadow_rays.value_or(1));
    shade.media_samples = o.media_samples;
    shade.weight_limit = o.lw.value_or(ps.lw.value_or(1e-3));
    shade.max_depth = o.max_depth.value_or(ps.max_depth.value_or(256));
    shade.roulette = o.roulette;
    rs.executor.clamp_indirect = o.clamp;
    rs.executor.constant_importance = o.importance;
    rs.max_memory = o.max_memory;
    rs.component_images = o.component_images;
    rs.pass_samples = o.pass_samples;
    rs.rounds = o.rounds.value_or(0);  // 0: the plan's rounds, else 1 (run_plan.h)
    rs.uniform = o.uniform;
    rs.final_rows = o.final_rows;
    rs.caustic_photons = o.caustic_photons;
    if (o.policy) rs.policy = *o.policy;

    // What `crex run`'s flags and Python's options are checked for, for every caller of the
    // library: spp 0 from C++ rendered a black image of 0 rays without a word.
    // The messages are written from the ranges, so the two cannot drift apart.
    auto need = [](bool ok, const std::string& what) {
        if (!ok) throw RunOptionError(what, "");
    };
    need(rs.width >= 1 && rs.height >= 1, "the image needs a width and a height of at least 1 pixel");
    need(kSppRange.holds(rs.spp), fmt::format("spp: at least {} camera sample a pixel, at most {}", kSppRange.lo, kSppRange.hi));
    need(kShadowRaysRange.holds(shade.shadow_rays), fmt::format("shadow_rays: {} to {} a hit", kShadowRaysRange.lo, kShadowRaysRange.hi));
    need(kShadowRaysRange.holds(shade.media_samples), fmt::format("media_samples: {} to {} a camera ray", kShadowRaysRange.lo, kShadowRaysRange.hi));
    need(kWeightLimitRange.holds(shade.weight_limit), fmt::format("lw: a weight limit from {} to {}", kWeightLimitRange.lo, kWeightLimitRange.hi));
    need(std::isfinite(rs.ambient.x) && rs.ambient.x >= 0, "ambient: a radiance of 0 or more");

    resolve_budget(run, plan, o);
    // Where the limits W404 names were set: the plan's line, unless an option overrides it.
    auto at = [](bool overridden, const SourceLocation& where) { return overridden || !where.known() ? std::string() : where.to_string(); };
    run.limits_set_at = {at(o.max_depth.has_value(), ps.max_depth_at), at(o.lw.has_value(), ps.lw_at), at(o.ab.has_value(), ps.ab_at)};

    // The irradiance cache: asked for, or the plan has one.
    if (o.irradiance_cache || !o.ic_file.empty() || plan.irradiance_cache) {
        IcSettings ics;
        ics.accuracy = o.aa.value_or(ps.aa.value_or(0.15));
        ics.divisions = o.ad.value_or(ps.ad.value_or(256));
        ics.bounces = o.ab.value_or(ps.ab.value_or(8));  // 8: at 4, interiors lost their light beyond the 4th bounce (issue 14)
        ics.resolution = o.ar;
        ics.ambient = rs.ambient;
        ics.seed = rs.seed;
        ics.caustic_photons = o.caustic_photons;
        rs.irradiance_cache = ics;
        rs.ic_file = o.ic_file;
        rs.ic_file_bytes = o.ic_file_bytes;
    }
    return run;
}

}  // namespace crex
