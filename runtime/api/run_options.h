/// \file run_options.h
/// A run's options as typed overrides of its plan's settings (spec/pipeline.md §7: a plan's
/// settings apply unless the caller says otherwise), and what they resolve to against a plan:
/// the driver's RunSettings, the budget in seconds (a share of a profiled full render
/// resolved), the irradiance cache. Nothing here reads or parses text: `crex run` turns its
/// flags into these fields (apps/crex/cmd_run.cpp), Python its keyword arguments.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "compiler/plan/pipeline_plan.h"
#include "runtime/driver/run_plan.h"
#include "runtime/api/fixed_costs.h"
#include "runtime/render/profile.h"

namespace crex {

/// What stands in for unexecuted D work: a radiance `av`, or every unexecuted ray standing in
/// with what its component's rays brought back on average (`automatic`).
struct AmbientStandIn {
    bool automatic = false;
    double value = 0;
};

/// A profile of cost per ray, with the time of the full render it was measured on (what a
/// budget in % is a share of; 0 when unknown).
struct ProfileInput {
    Profile profile;
    double full_render_seconds = 0;
    StageCosts stages;  ///< a pipeline's preview and guidance in that render
    std::string path;  ///< the file it was read from, for what is said about it
};

/// Where the limits whose light left out W404 names were set: "file:line:col" of a plan's
/// setting; "" for an option or a default.
struct LimitOrigins {
    std::string max_depth, lw, ab;
};

/// The JSON text `--save-profile` writes (run_inputs.h's read_profile() reads it back).
std::string profile_json_text(const Profile& profile, double full_render_seconds, const StageCosts& stages = {});

/// The values a run's settings may take, inclusive: what `resolve_run` refuses outside them,
/// and what the CLI's flags and Python's options check, in their own words, before.
struct OptionRange {
    double lo, hi;
    bool holds(double v) const { return v >= lo && v <= hi; }
};
inline constexpr OptionRange kSppRange{1, 1 << 20};
inline constexpr OptionRange kShadowRaysRange{1, 1024};  ///< also media samples
inline constexpr OptionRange kWeightLimitRange{0, 1};
inline constexpr OptionRange kMaxDepthRange{0, 65535};
inline constexpr OptionRange kImageSideRange{1, 16384};

struct RunOptions {
    // The plan's settings, overridden; unset: the plan's own, else the default named.
    std::optional<int> width, height;           ///< 256 x 256
    std::optional<uint32_t> spp;                ///< a pipeline's preview spp, else 16
    std::optional<uint64_t> seed;               ///< 0
    std::optional<double> lw;                   ///< 1e-3
    std::optional<uint32_t> max_depth;          ///< 256
    std::optional<AmbientStandIn> ambient;      ///< the plan's av, else automatic for a pipeline, 0 for a crex
    std::optional<double> aa;                   ///< 0.15
    std::optional<uint32_t> ab, ad;             ///< 8, 256
    std::optional<PlanBudget> budget;           ///< none
    bool no_budget = false;                     ///< the plan's budget ignored too
    std::optional<pipeline::SchedulingPolicy> policy;  ///< the plan's, else RunSettings::policy's default
    std::optional<uint32_t> rounds;             ///< the plan's, else 1
    std::optional<uint32_t> shadow_rays;        ///< the plan's `preselective { shadow_rays N }`, else 1
    /// The preview at every k-th pixel; unset: every pixel, or under a budget coarse to fine
    /// within a share of it (runtime/driver/preview_levels.h).
    std::optional<uint32_t> preview_stride;
    /// Render a budget below the pipeline's floor anyway (it will be broken) instead of refusing it.
    bool budget_floor_ok = false;
    /// The run's profile will be saved (`--save-profile`): a pipeline's full render then also
    /// times what a strided preview does per pixel, for the floor (RunSettings::time_strided_preview).
    bool saves_profile = false;
    // Settings a plan does not have.
    uint32_t media_samples = 1;
    bool roulette = true;
    double clamp = 0;                           ///< indirect contributions at most this (0: off; biased)
    double importance = 1;                      ///< `{ }` of a crex without maps
    PixelFilter filter = PixelFilter::kBox;
    UniformQuality uniform = UniformQuality::kOff;
    size_t max_memory = kDefaultMaxMemory;
    bool component_images = true;               ///< RunSettings::component_images
    uint32_t pass_samples = 0;
    bool irradiance_cache = false;              ///< D through the cache even when the plan has none
    double ar = 128;
    uint32_t caustic_photons = 200000;         ///< the caustic map's (RunSettings::caustic_photons); 0: none
    std::string ic_file;                        ///< load the cache from it, save it there (implies the cache)
    std::optional<std::string> ic_file_bytes;   ///< `ic_file` read already (the lead process read it)
    std::optional<ProfileInput> profile;        ///< what a budget is predicted from
    std::vector<char> final_rows;               ///< rows final already (finishing a partial image)
};

/// The options resolved against a plan: what the driver runs.
struct ResolvedRun {
    RunSettings settings;                 ///< executor.profile is null: the run measures into its own
    double budget_seconds = 0;            ///< 0: none
    std::optional<ProfileInput> predicted;
    LimitOrigins limits_set_at;
    /// Under a budget with a profile of the pipeline's stages: its floor (fixed_costs.h).
    std::optional<FixedCosts> fixed_costs;
    bool below_floor = false;      ///< rendered under a budget below its floor (--budget-floor ok)
};

/// A setting that cannot be resolved (a budget in % without a profile's full render time):
/// the plan's own when `where` is its position, else an option's.
struct RunOptionError : std::invalid_argument {
    RunOptionError(const std::string& what, std::string at, bool in_file = false)
        : std::invalid_argument(what), where(std::move(at)), in_input_file(in_file) {}
    std::string where;           ///< "file:line:col" of the plan's setting; "" for an option
    bool in_input_file = false;  ///< what an input file (the profile) lacks, not the setting itself
};

/// A budget below what the pipeline can possibly do (its coarsest preview and guidance):
/// refused before rendering (exit 2), naming the smallest budget it can meet.
struct BudgetBelowFloor : RunOptionError {
    BudgetBelowFloor(const std::string& what, std::string at, double floor)
        : RunOptionError(what, std::move(at)), floor_seconds(floor) {}
    double floor_seconds;
};

/// Throws RunOptionError (a budget in % without a profile's full render time; BudgetBelowFloor).
ResolvedRun resolve_run(const PipelinePlan& plan, const RunOptions& options);

/// The budget part of resolve_run(): `run`'s budget, profile, floor and preview stride from
/// `options` (a sequence re-resolves it per frame from the profile it carries). Throws as
/// resolve_run().
void resolve_budget(ResolvedRun& run, const PipelinePlan& plan, const RunOptions& options);

}  // namespace crex
