/// \file executor.h
/// Runs a lowered crex (sched::Program) over the component bins (spec/crex.md §3):
///  - Exec X takes the rays in bin X when the step starts (after `{ }` filtering), executes
///    them chunk by chunk and routes their children;
///  - inside the outermost owning Defer/Budgeted, children are held back and merged into the
///    bins when that execution ends;
///  - inside a Modulate with n occurrences, occurrence i executes a ray of pixel p only if
///    i < ceil(I(p) n) (computed in double); skipped rays stay in their bin;
///  - RepeatUntilEmpty runs at least once, again while the last execution took at least one
///    ray, at most `cap` times per entry (warning W401 names the crex position).
/// Without a time budget, `[ ]` behaves as `< >`. Under a budget (spec §3, thesis 5.4) every
/// component occurrence outside a `[ ]` and every outermost `[ ]` is a task, admitted afresh
/// at each execution only if the profile predicts it finishes in the remaining time (a `[ ]`
/// from the current sizes of the bins its members read); a task predicted to overrun is
/// skipped, its rays stay in their bins, and the next task is considered. A component with no
/// profile yet runs a pilot of its first 1 % of rays (at least one chunk), whose results are
/// kept, then the rest if predicted to fit. A `[ ]` whose members have no profile is admitted.
#pragma once

#include <array>
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "compiler/sched/program.h"
#include "runtime/render/film.h"
#include "runtime/render/profile.h"
#include "runtime/render/shade.h"

namespace crex {

struct ComponentStats {
    uint64_t executions = 0;  ///< steps that took at least one ray
    uint64_t rays = 0;
    uint64_t shadow_rays = 0;
    double seconds = 0;
    /// Throughput of the rays executed, summed: with the component's AOV it says what a ray of
    /// this component brings back on average (the driver's automatic ambient stand-in).
    double beta[3] = {0, 0, 0};
    /// Luminance its rays brought to the image, summed (the queues policy's measure of what a
    /// ray of the component is worth).
    double luminance = 0;
};

/// One executed step, in execution order (for reports and semantics tests).
struct StepRecord {
    Component component;
    uint64_t rays = 0;
};

/// A task the budget left out.
struct SkippedTask {
    std::string what;       ///< "T at <crex>:1:2" or "[RS] at ..."
    double predicted = 0;   ///< seconds
    double remaining = 0;   ///< seconds left when it was considered
};

/// A component occurrence inside `{ }` (by its place in the crex): the rays it found in its bin
/// and took, and the highest importance among those found. One that found rays and never took
/// any is W405: its map never reached the importance it needs.
struct ModulatedStep {
    std::string where;
    Component component = Component::kD;
    double index = 0, occurrences = 0;  ///< 0-based occurrence i of n: runs where I > i / n
    uint64_t found = 0, taken = 0;
    double highest_importance = 0;
};

/// A choice of the queues policy: the batch it took and what each queue was worth then.
struct QueueChoice {
    Component component;
    uint64_t rays = 0;
    /// Luminance per second of every queue with rays when the choice was made (+inf: not
    /// measured yet, runs first); NaN: the queue was empty or not read by the crex.
    std::array<double, kComponentCount> value{};
};

struct ExecutorStats {
    std::array<ComponentStats, kComponentCount> components{};
    ComponentStats camera;
    /// Light left out by the path limits: the luminance of the throughput of the children not
    /// spawned past max_depth, and below lw without roulette, summed over every ray traced
    /// (ShadeParams). Per camera ray it estimates the share of the image lost (run_plan.h).
    double cut_by_depth = 0, cut_by_weight = 0;
    std::vector<StepRecord> steps;
    std::vector<SkippedTask> skipped;
    std::vector<QueueChoice> queue_choices;
    std::vector<ModulatedStep> modulated;
};

struct ExecutorOptions {
    ShadeParams shade;
    /// Rays traced and shaded at once; 0: 4096 per worker thread, so that a chunk's hits,
    /// shadow rays and children stay in cache (5-10 % faster than 65536, bench/render_bench).
    size_t chunk_rays = 0;
    /// Irradiance-cache queries handed over at once (the cache batches its new records).
    size_t query_chunk_rays = size_t{1} << 16;
    double constant_importance = 1.0;      ///< I(p) when no map is given
    /// > 0: every contribution of a component ray (not of camera rays) is scaled down so that
    /// its largest channel is at most this (crex run --clamp): fireflies traded for bias.
    double clamp_indirect = 0;
    const std::vector<float>* importance = nullptr;  ///< per pixel, row-major (clamped; NaN = 0)
    /// capict: per pixel, bit c set if the rays a camera hit spawns into component c are
    /// executed there (null: everywhere). Rays of components the film tracks branches of that
    /// are not executed are dropped, their throughput kept for the interpolation.
    const std::vector<uint8_t>* first_bounce_runs = nullptr;
    /// capict's refinement: camera samples traced again only to run the first bounces of these
    /// components (bit c) where first_bounce_runs says so. Their camera contributions, their
    /// samples and every other child are not counted again: the film already holds them.
    uint8_t replay_branches = 0;
    std::function<void(const std::string& what, uint64_t rays_done)> progress;
    double budget_seconds = 0;       ///< 0: no time budget
    /// Under a budget, how a component task is admitted: whole on the profile's prediction
    /// (thesis 5.4), or its rays in batches ordered by pixel importance while they fit (5.5);
    /// kNone: the caller admits whole passes and every task of an admitted pass runs.
    /// kQueues (thesis 8.3): every component the crex reads is a queue of its rays, most
    /// important pixels first; the next batch comes from the queue whose rays bring the most
    /// luminance per second, while batches fit (the crex's order is not kept under a budget).
    enum class TaskAdmission { kWhole, kBatches, kNone, kQueues } task_admission = TaskAdmission::kWhole;
    Profile* profile = nullptr;      ///< costs per ray; measured into as the render goes
    /// Seconds since the first camera ray (default: a steady clock). Tests inject a clock;
    /// reports give one that pauses while they copy snapshots.
    std::function<double()> clock;
    /// Called after every chunk (boundary = false) and after every step (boundary = true) with
    /// what just ran: where a report takes its checkpoints (issue 8).
    std::function<void(const std::string& event, bool boundary)> checkpoint;
    /// An irradiance cache: a D step hands its queries (rays flagged kRayIcQuery) over and
    /// adds beta E / pi to the D AOV; queries spawn nothing.
    std::function<void(const RayBatch& queries, size_t begin, size_t end, std::vector<Vec3>& irradiance)> irradiance;
};

/// Marks in `out` the components the Exec nodes of a subtree read (each bin is read once per
/// deferred execution).
void components_read(const sched::Node& n, std::array<bool, kComponentCount>& out);

class Executor {
public:
    Executor(const RenderScene& scene, Film& film, const ExecutorOptions& options);

    /// Traces camera rays (not a crex step): their hits shade into the camera AOV and their
    /// children fill the bins.
    void run_camera_rays(const RayBatch& camera_rays);
    /// Runs one stage's program over the current bins; returns true if any step had work.
    bool run(const sched::Node& node);
    /// Whether the budget is spent while cache queries run paced (their caller keeps what is
    /// not run): the irradiance cache's stop test (IrradianceCache::set_stop).
    bool paced_queries_out_of_time() const { return pacing_queries_ && now() >= options_.budget_seconds; }
    /// Runs a stage's whole program: as run(), or under a budget with kQueues as queues.
    bool run_stage(const sched::Node& program);

    /// Between stages (spec/pipeline.md: the svt applies to the selective stage).
    void set_shade_params(const ShadeParams& shade) { options_.shade = shade; }
    void set_importance(const std::vector<float>* importance) { options_.importance = importance; }
    void set_first_bounce_runs(const std::vector<uint8_t>* runs) { options_.first_bounce_runs = runs; }
    void set_replay_branches(uint8_t components) { options_.replay_branches = components; }
    void set_task_admission(ExecutorOptions::TaskAdmission admission) { options_.task_admission = admission; }
    void set_irradiance(std::function<void(const RayBatch&, size_t, size_t, std::vector<Vec3>&)> hook) {
        options_.irradiance = std::move(hook);
    }

    const std::array<RayBatch, kComponentCount>& bins() const { return bins_; }
    /// Calls f(pixel) for every ray not executed yet: in a bin, held back by `< >`, or later
    /// in the step now running (from a checkpoint callback).
    template <typename F>
    void for_each_waiting_ray(F&& f) const {
        for (size_t c = 0; c < kComponentCount; ++c) {
            for (uint32_t p : bins_[c].pixel) f(p);
            for (uint32_t p : pending_[c].pixel) f(p);
        }
        if (running_)
            for (size_t i = running_next_; i < running_->size(); ++i) f(running_->pixel[i]);
    }
    std::array<RayBatch, kComponentCount>& bins() { return bins_; }
    const ExecutorStats& stats() const { return stats_; }
    uint64_t rays_done() const { return rays_done_; }
    /// The most rays waiting in the bins after any step since the last reset: what a pass of
    /// camera samples holds in flight (its memory), measured rather than modelled.
    size_t peak_rays_held() const { return peak_rays_held_; }
    void reset_peak_rays_held() { peak_rays_held_ = 0; }
    const std::vector<Diagnostic>& warnings() const { return warnings_; }

private:
    bool exec(const sched::Node& node);
    bool budgeted_group(const sched::Node& node, bool owns);
    bool run_deferred(const sched::Node& node, bool owns);
    double now() const;
    bool budget_active() const {
        return options_.budget_seconds > 0 && !in_admitted_group_ && options_.task_admission != ExecutorOptions::TaskAdmission::kNone;
    }
    bool run_queues(const sched::Node& program);
    /// Rays [first, end) of `rays`, most important pixels first (stable: ties keep their order).
    RayBatch by_importance(const RayBatch& rays, size_t first) const;
    /// The budget left `left` of a step's `of` rays, predicted at `cost` seconds a ray.
    void note_rays_skipped(const std::string& letter, const sched::Node& node, size_t left, size_t of, double cost);
    bool run_in_batches(RayBatch& take, size_t first, double cost, RayBatch& bin, ComponentStats& stats, const std::string& letter,
                        const sched::Node& node);
    size_t chunk_rays() const;
    /// Runs `rays` (all of them unless `paced`: then cache queries stop when the budget is
    /// spent); returns how many of them ran, from the first.
    size_t execute_rays(const RayBatch& rays, bool camera, size_t aov, ComponentStats& stats, const std::string& label,
                        std::optional<Component> profiled, bool paced = false);
    /// The first part of paced queries: their cost per query is not known yet.
    static constexpr size_t kFirstPacedQueries = 32;
    double importance(uint32_t pixel) const;
    void gate_first_bounce(ShadeOutput& out);
    /// Seconds per ray of component c that a budget admits rays on: the profile's, or what this
    /// render's latest rays of c cost when that is more (RecentCosts). None without a profile.
    std::optional<double> admission_cost(Component c) const;

    const RenderScene& scene_;
    Film& film_;
    ExecutorOptions options_;
    std::array<RayBatch, kComponentCount> bins_;
    std::array<RayBatch, kComponentCount> pending_;
    const RayBatch* running_ = nullptr;  // the rays execute_rays is running, from running_next_ on
    size_t running_next_ = 0;
    bool pacing_queries_ = false;  // execute_rays is handing paced queries to the cache
    // Per component, memory for its bin's next step (see exec()): each bin refills into memory
    // sized by its own last step, not by whichever bin ran before it.
    std::array<RayBatch, kComponentCount> spare_;
    bool deferring_ = false;
    // Inside a Modulate: its n, and the (stride, iteration) of the repeats between it and the step.
    void note_modulated(const sched::Node& node, double index, size_t found, size_t taken, double highest);
    double modulate_n_ = 0;
    bool in_modulate_ = false;
    std::vector<std::pair<double, uint64_t>> strides_;
    ExecutorStats stats_;
    std::vector<Diagnostic> warnings_;
    uint64_t rays_done_ = 0;
    ShadeOutput shade_;  // reused for every chunk
    RecentCosts recent_;
    bool in_admitted_group_ = false;
    size_t peak_rays_held_ = 0;
    void note_rays_held();
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace crex
