#include "runtime/driver/run_plan.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <set>

#include "base/check.h"
#include "runtime/base/cpu_time.h"
#include "runtime/base/sampling.h"
#include "runtime/cache/caustic_photons.h"
#include "runtime/driver/ambient_stand_ins.h"
#include "runtime/driver/budget_admission.h"
#include "runtime/driver/cache_file.h"
#include "runtime/driver/cache_scale_check.h"
#include "runtime/driver/capict_refinement.h"
#include "runtime/driver/guidance_phase.h"
#include "runtime/driver/film_layout.h"
#include "runtime/driver/pass_sizing.h"
#include "runtime/driver/preview_levels.h"
#include "runtime/driver/row_bands.h"
#include "runtime/driver/sample_passes.h"
#include "runtime/render/render_scene.h"

namespace crex {
namespace {

// Whether a crex program executes D rays anywhere (the caustic map stands for what they find).
bool executes_d(const sched::Node& n) {
    if (n.op == sched::Op::kExec && n.component == Component::kD) return true;
    return std::any_of(n.children.begin(), n.children.end(), [](const sched::Node& c) { return executes_d(c); });
}
bool executes_d(const sched::Program& p) { return executes_d(p.preselective) || executes_d(p.selective); }

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// When the stages must stop under a budget: early by the render's end as the profile predicts
// it (the stand-ins and warnings after the last stage), so the whole run ends on the budget.
// A fixed 3-6 ms there was most of a 0.05 s budget's overshoot. 0: no budget.
double stage_deadline(const RunSettings& s) {
    const double budget = s.executor.budget_seconds;
    return budget > 0 ? budget - std::clamp(s.end_seconds, 0.0, budget / 2) : 0;
}

// One render of a plan. execute() reads as its phases (run_plan.h lists the stages), the shape
// of pbrt-v4's WavefrontPathIntegrator::Render: set up, then each stage's loop over sample
// passes, then finish. What the phases need of memory, time, stand-ins, the cache file, guidance
// and capict's refinement is in units of their own (pass_sizing.h, budget_admission.h,
// ambient_stand_ins.h, cache_file.h, guidance_phase.h, capict_refinement.h).
class PlanRun {
public:
    PlanRun(const Scene& scene, const PipelinePlan& plan, const RunSettings& settings, ProcessGroup& group, RunObserver& observer)
        : scene_(scene), plan_(plan), s_(settings), group_(group), observer_(observer), recorder_(observer.checkpoints()),
          budget_(stage_deadline(settings)), out_(settings.width, settings.height, film_layout(plan, settings)) {}

    RunResult execute() {
        start();
        if (!plan_.staged) {
            render_interleaved();
        } else {
            preview();
            if (stopping()) {  // the preview is the image so far: its waiting rays stand in
                stand_ins_->flush(carried_, out_.rays_left);
                end_of_stages();
                return finish();
            }
            // 2-3. Guidance and selective rendering, `rounds` times (the cyclic process, spec
            // §1): each round computes the maps on the image so far and takes the samples its
            // svt asks for by then (a share r / rounds of the way from the preview's spp to the
            // target) beyond what each pixel has; the first round also runs the preview's
            // waiting rays.
            const uint32_t rounds = std::max<uint32_t>(1, s_.rounds ? s_.rounds : plan_rounds(plan_));
            for (uint32_t round = 1; round <= rounds && !stopping(); ++round) selective_round(round, rounds, guidance_round(round, rounds));
            if (out_.component_subsample.any() && !budget_.budgeted() && !stopping()) refine_components();
            end_of_stages();
        }
        return finish();
    }

private:
    // The phases.
    void start();               // Embree scene, clock, cache, executor, camera, the first split of rows
    void render_interleaved();  // a plain crex: every pass runs both programs
    void preview();             // 1. the pre-selective crex; the rays it leaves waiting are carried on
    SelectiveSetup guidance_round(uint32_t round, uint32_t rounds);                          // 2. maps and svt
    void selective_round(uint32_t round, uint32_t rounds, const SelectiveSetup& selective);  // 3. selective samples
    void refine_components();   // capict: corners that differ split, their branches rendered
    void end_of_stages();
    RunResult finish();         // stand-ins, the last exchange of rows, warnings, the cache saved
    double time_strided_preview() const;  // RunSettings::time_strided_preview
    double time_budgeted_end() const;     // RunResult::budgeted_end_seconds
    void measure_light_left_out();  // the share of light max_depth, lw and the cache's bounces cut (W404)

    // A stage's camera samples in passes; after each pass's camera rays, `after_camera_rays`
    // runs the programs over its bins.
    void run_samples(const std::string& stage, const SampleRanges& ranges, const std::function<void()>& after_camera_rays);
    void trace_camera_rays(const SamplePass& pass, const SampleRanges& ranges);
    // Rays left at the end of a pass: they stand in (ambient_stand_ins.h) and are dropped.
    void flush_bins() { stand_ins_->flush(ex_->bins(), out_.rays_left); }
    std::vector<float> snapshot() const;       // the image a checkpoint records
    std::vector<float> composite_now() const;  // film + what waiting rays stand in for
    void report_progress(const std::string& step);
    // The caustic map's share traced, as progress of the stage "setup": it is built before the
    // first camera ray (20 million photons took about a minute without a word).
    std::function<void(const char*, double)> caustic_progress(uint32_t photons) {
        return [this, photons, phase = std::string(), start = Clock::now()](const char* now_in, double done) mutable {
            if (phase != now_in) phase = now_in, start = Clock::now();  // each phase its own share and ETA
            progress_.stage = "setup";
            progress_.fraction = done;
            progress_.stage_seconds = seconds_since(start);
            progress_.step = fmt::format("caustic map of {} photons: {}", photons, phase);
            observer_.progress(progress_);
        };
    }
    // Has the observer asked to stop (Ctrl-C)? Then no pass, round or stage starts. Asked
    // once an image exists; a distributed render goes on (its processes must agree).
    bool stopping() {
        if (!out_.stopped && out_.passes > 0 && bands_.empty() && observer_.stop_requested()) out_.stopped = true;
        return out_.stopped;
    }
    void stage_end(const std::string& what, const std::string& next);
    double now() const { return clock_(); }
    // A batch of D queries answered here, or by another process of the group.
    IcAnswerFn answer_queries() {
        return [this](const std::vector<IcQuery>& q, std::vector<Vec3>& e) { group_.answer_queries(*cache_, q, e); };
    }
    void reanswer_preview_queries(const SelectiveSetup& sel);
    // A level of a strided preview (preview_levels.h): the corners of `grid` with no sample
    // yet, save the pixels a `subsample` variable interpolates; `samples` gets their count.
    SampleRanges unsampled_corners(const SubsampleGrid& grid, uint64_t& samples) const;
    SubsampleGrid preview_grid(uint32_t stride) const {
        return SubsampleGrid(s_.width, s_.height, std::vector<double>(out_.film.pixel_count(), static_cast<double>(stride)));
    }
    void redo_preview_direct_light(const SelectiveSetup& sel);
    // The seeds of pixel p's camera samples (RunSettings::position_seed).
    CameraSeeds camera_seeds(size_t p) const {
        const bool inherits = s_.history && s_.history->samples(p) > 0;
        return {s_.seed, s_.position_seed && !inherits ? *s_.position_seed : s_.seed};
    }
    // Samples [first, first + spp) of every pixel, less what it inherits from the frame before
    // (RunSettings::history): one sample of its own at least. A pixel new to the frame (seen
    // from behind an edge, or come in at the border) takes all of them, so it does not stand
    // out beside its neighbours' histories.
    SampleRanges own_samples_of_every_pixel(uint32_t first) const {
        SampleRanges r{first, first + s_.spp, {}, {}};
        if (!s_.history) return r;
        r.end_of.resize(out_.film.pixel_count());
        for (size_t p = 0; p < r.end_of.size(); ++p) r.end_of[p] = first + own_samples(s_.spp, s_.history->samples(p), s_.history->frames);
        return r;
    }
    // A pixel whose only samples of its own are the preview's, the rest inherited from the
    // frame before (RunSettings::history): the inherited samples have the quality its map
    // asks for; its preview sample, a small share of the pixel, keeps the preview's.
    bool inherits_its_quality(const SelectiveSetup& sel, size_t p) const {
        if (!s_.history || !(s_.history->samples(p) > 0)) return false;
        return own_samples(std::max(s_.spp, sel.spp_end[p]), s_.history->samples(p), s_.history->frames) <= s_.spp;
    }

    // Distributed rendering: rows (and the cache's records) exchanged with the other processes,
    // the work since the last exchange done in the bands of `bands_`; `ambient`: the stand-ins
    // that go with the film.
    void share_rows(RowExchange why, std::vector<double>& ambient) {
        if (bands_.empty()) return;
        SharedRows rows{out_.film, ambient, {}, bands_, why};
        // At the end the throughput left already stands in (finish_automatic): not sent.
        if (why != RowExchange::kEnd)
            for (auto& left : stand_ins_->throughput_left()) rows.throughput_left.push_back(&left);
        group_.share_rows(rows);
    }
    void share_with_other_processes(RowExchange why, std::vector<double>& ambient) {
        share_rows(why, ambient);
        if (cache_ && !bands_.empty()) group_.share_cache(*cache_);
    }
    // The rows this process renders: of its band, or all of them.
    int first_row() const { return bands_.empty() ? 0 : bands_[static_cast<size_t>(group_.band())]; }
    int end_row() const { return bands_.empty() ? s_.height : bands_[static_cast<size_t>(group_.band()) + 1]; }
    void balance_bands(const SampleRanges& all_rows, bool worked_since_exchange);

    const Scene& scene_;
    const PipelinePlan& plan_;
    const RunSettings& s_;
    ProcessGroup& group_;
    RunObserver& observer_;
    CheckpointRecorder* recorder_;  // reports: image snapshots during the render (null: none)
    BudgetAdmission budget_;
    RunResult out_;
    std::optional<RenderScene> own_scene_;  // built here unless RunSettings::render_scene
    RenderScene* rs_ = nullptr;
    TextureStats textures_before_;  // a shared scene's texture counters when this run began
    std::optional<CameraRays> camera_;
    std::optional<Executor> ex_;
    std::function<double()> clock_;
    Clock::time_point t0_;  // the first camera ray
    std::optional<AmbientStandIns> stand_ins_;
    std::vector<int> bands_;  // distributed rendering: the split of the stage running (row_bands.h)
    std::vector<double> preview_ambient_;  // the preview's stand-ins: for the D rays it carries
    std::array<RayBatch, kComponentCount> carried_;  // the preview's rays waiting for the selective crex
    // With a report: the image and sample counts when the running pass began (see snapshot()).
    std::vector<float> pass_start_image_;
    std::vector<uint32_t> pass_start_samples_;
    std::optional<IrradianceCache> cache_;
    // Path tracing without the cache: caustics from a photon map (RunSettings::caustic_photons).
    std::shared_ptr<const CausticPhotons> caustics_;
    // The map built or carried in (the cache's or path tracing's), empty when the scene has no
    // caustic paths: RunResult::caustic_map.
    std::shared_ptr<const CausticPhotons> caustic_map_;
    std::function<Vec3(const Vec3&, const Vec3&)> caustic_lookup_;  ///< empty: path traced
    IcAnswerLog preview_answers_;
    uint32_t preview_shadow_rays_ = 1;  ///< the base quality the preview's hits were shaded at
    std::optional<PixelProbe> surfaces_;      // what each pixel centre sees (task maps, capict)
    std::vector<float> replay_start_image_;   // capict, reports: the image before the refinement round running
    std::vector<uint8_t> first_bounce_runs_;  // capict: the executor's gate (bit c: c's first bounces run)
    double base_aa_ = 0;
    double cpu_at_start_ = 0;  // the process's CPU seconds when the render began
    bool last_stage_ = false;  // the render's last camera samples: not traced in RunSettings::final_rows
    ExecutorOptions::TaskAdmission policy_admission_ = ExecutorOptions::TaskAdmission::kWhole;  // the policy's
    // Progress within the running stage.
    RunProgress progress_;
    uint64_t stage_samples_ = 0, stage_samples_done_ = 0;
    // Within a pass: its samples and the rays done when it began; the rays a camera sample cost
    // in the passes before, so the percentage moves during a pass (one pass can be a whole stage).
    uint64_t pass_samples_ = 0, pass_rays_start_ = 0, samples_in_passes_ = 0, rays_in_passes_ = 0;
    Clock::time_point stage_start_ = Clock::now();
};

void PlanRun::start() {
    auto t_setup = Clock::now();
    // One texture cache for the render, its share of --max-memory (pass_bytes() counts it).
    if (s_.render_scene) {
        if (&s_.render_scene->scene != &scene_) throw std::logic_error("RunSettings::render_scene was built from another Scene");
        rs_ = s_.render_scene.get();
        if (rs_->textures) textures_before_ = rs_->textures->stats();
    } else {
        rs_ = &own_scene_.emplace(scene_, texture_cache_bytes(s_.max_memory), setup_progress(observer_, progress_));
    }
    rs_->set_view(s_.width, s_.height, s_.texture_filter_width);
    for (const auto& w : rs_->warnings) out_.warnings.push_back(w);
    out_.setup_seconds = seconds_since(t_setup);
    cpu_at_start_ = process_cpu_seconds();
    const size_t pixels = out_.film.pixel_count();
    stand_ins_.emplace(pixels, s_.ambient, s_.ambient_auto);
    if (s_.executor.budget_seconds > 0) {
        std::array<bool, kComponentCount> read{};
        components_read(plan_.program.preselective, read);
        components_read(plan_.program.selective, read);
        stand_ins_->keep(read);
    }
    // A pipeline runs in stages (its preview is kept and shown); a bare crex runs each pass
    // through both programs.
    out_.staged = plan_.staged;
    if (out_.staged && !s_.windows.empty())  // guidance reads the whole preview: a window has no meaning there
        throw RunInputError("only a plain crex renders windows of the frame, not a pipeline");
    if (s_.uniform != UniformQuality::kOff && !has_guidance(plan_))
        out_.notes.push_back("--uniform has no effect: the plan varies nothing");
    if (std::string note = memory_over_limit_note(plan_, s_); !note.empty()) out_.notes.push_back(note);

    // Path tracing's caustic map, built before the clock starts as the BVH is: a fixed cost of
    // the scene (0.35 s for 200,000 photons in the Cornell box) that no budget can trim.
    if (!s_.irradiance_cache && s_.caustic_photons > 0 && executes_d(plan_.program)) {
        const auto t_map = Clock::now();
        caustic_map_ = s_.caustic_map ? s_.caustic_map : build_caustic_photons(*rs_, s_.caustic_photons, s_.seed, caustic_progress(s_.caustic_photons));
        caustics_ = photons_in(caustic_map_);
        if (caustics_)  // else no mirror, glass or trans surface, no lamp, or no photon landed: no such paths
            caustic_lookup_ = [map = caustics_.get()](const Vec3& x, const Vec3& n) { return map->irradiance(x, n); };
        if (!s_.caustic_map) out_.caustic_map_seconds = seconds_since(t_map);
        out_.setup_seconds += seconds_since(t_map);
    }
    // The cache's map likewise (the same photons: they do not depend on the camera). On the
    // clock it was the largest fixed cost of a cached pipeline under a budget (prog_tc at
    // 384x288: 0.3-0.4 s of its 0.44-0.6 s floor) and varied by a third from run to run.
    if (s_.irradiance_cache && s_.irradiance_cache->caustic_photons > 0) caustic_map_ = s_.caustic_map;
    if (s_.irradiance_cache && s_.irradiance_cache->caustic_photons > 0 && !caustic_map_) {
        const auto t_map = Clock::now();
        caustic_map_ = build_caustic_photons(*rs_, s_.irradiance_cache->caustic_photons, s_.irradiance_cache->seed,
                                             caustic_progress(s_.irradiance_cache->caustic_photons));
        out_.caustic_map_seconds = seconds_since(t_map);
        out_.setup_seconds += out_.caustic_map_seconds;
    }
    // One clock from the first camera ray for every stage (spec §7); reports pause it while
    // they copy snapshots.
    t0_ = Clock::now();
    ExecutorOptions eo = s_.executor;
    eo.budget_seconds = stage_deadline(s_);
    preview_shadow_rays_ = eo.shade.shadow_rays;
    out_.policy = s_.policy ? *s_.policy
                  : plan_.settings.policy ? *plan_.settings.policy
                  : plan_.name.empty()    ? pipeline::SchedulingPolicy::kProgressive
                  : plan_.variables.empty() ? pipeline::SchedulingPolicy::kTasks
                                            : pipeline::SchedulingPolicy::kQueues;
    using P = pipeline::SchedulingPolicy;
    using A = ExecutorOptions::TaskAdmission;
    eo.task_admission = out_.policy == P::kTasks         ? A::kWhole
                        : out_.policy == P::kProgressive ? A::kNone
                        : out_.policy == P::kQueues      ? A::kQueues
                                                         : A::kBatches;
    if (recorder_) {
        recorder_->start(out_.film.pixel_count() * 3);
        clock_ = [rec = recorder_] { return rec->now(); };
    } else if (eo.clock) {
        clock_ = eo.clock;
    } else {
        clock_ = [t0 = t0_] { return seconds_since(t0); };
    }
    eo.clock = clock_;
    if (recorder_) eo.checkpoint = [this](const std::string& what, bool boundary) {
        recorder_->event(what, boundary, ex_->rays_done(), [this] { return snapshot(); });
    };
    eo.progress = [this](const std::string& what, uint64_t rays) {
        if (s_.executor.progress) s_.executor.progress(what, rays);
        report_progress(what);
    };
    if (s_.irradiance_cache) {
        // The store of D's irradiance: a plan varying ic_radius starts at its `from` accuracy.
        IcSettings ics = plan_cache_settings(plan_, *s_.irradiance_cache);
        ics.max_bytes = s_.max_memory;  // the records alone never outgrow the process's limit (W406)
        base_aa_ = ics.accuracy;
        cache_.emplace(*rs_, ics, caustic_map_);
        if (auto coarse = coarse_cache_warning(*rs_, cache_->file_settings(), s_.width, s_.height))
            out_.warnings.push_back(std::move(*coarse));
        cache_->set_progress([this](const IcStats& st) {
            report_progress(fmt::format("D: irradiance cache, {} records, {:.1f} M hemisphere rays", st.records, st.hemisphere_rays / 1e6));
        });
        // Under a budget, one query's records can outlast it: the cache stops between its steps
        // once paced queries find the budget spent (not across processes, which answer
        // each other's queries in step).
        if (!group_.distributed()) cache_->set_stop([this] { return ex_ && ex_->paced_queries_out_of_time(); });
        out_.ic_loaded = load_cache_file(*cache_, s_);
        eo.shade.ic_queries = true;
        // The preview's answers are kept only where a pixel may ask for them again, finer
        // (reanswer_preview_queries): at 960x540 they were 150 MB of edge_aa's 530 MB peak.
        eo.irradiance = executor_hook(answer_queries(), {base_aa_, nullptr, out_.staged ? nullptr : s_.executor.importance},
                                      out_.staged && may_refine_accuracy(plan_) ? &preview_answers_ : nullptr);
    }
    eo.shade.caustic_irradiance = caustic_lookup_;
    // capict: the branches of the components sub-sampled are tracked from the first camera
    // ray, so the preview's samples count in the interpolation too.
    if (const uint8_t branches = subsampled_components(plan_)) out_.film.track_branches(branches);
    ex_.emplace(*rs_, out_.film, eo);
    policy_admission_ = eo.task_admission;
    camera_.emplace(scene_.camera, s_.width, s_.height, rs_->embree->origin_offset());
    // Distributed: nothing is known of the first stage's cost yet: equal bands.
    if (group_.bands() > 0) {
        bands_ = equal_row_bands(s_.height, group_.bands());
        std::array<bool, kComponentCount> every;
        every.fill(true);
        stand_ins_->keep(every);
    }
}

void PlanRun::render_interleaved() {
    // A plain crex (or a pipeline that varies nothing): each pass runs both programs.
    const sched::Program& program = plan_.program;
    last_stage_ = true;
    const SampleRanges every_pixel = own_samples_of_every_pixel(s_.first_sample);
    run_samples("render", s_.windows.empty() ? every_pixel : only_windows(every_pixel, s_.width, s_.height, s_.windows), [&] {
        if (recorder_) recorder_->set_stage("preselective");
        ex_->run_stage(program.preselective);
        if (recorder_) {
            recorder_->event("end of the pre-selective crex", true, ex_->rays_done(), [this] { return snapshot(); }, true);
            recorder_->set_stage("selective");
        }
        ex_->run_stage(program.selective);
        flush_bins();
    });
    if (recorder_) {
        recorder_->set_stage("end");
        recorder_->event("end of render", true, ex_->rays_done(), [this] { return snapshot(); }, true);
    }
}

void PlanRun::preview() {
    // 1. Pre-selective: the rays each pass leaves waiting are carried to the selective stage.
    auto carry = [&] {
        ex_->run_stage(plan_.program.preselective);
        for (size_t c = 0; c < kComponentCount; ++c) {
            RayBatch& bin = ex_->bins()[c];
            carried_[c].append(bin, 0, bin.size());
            bin.clear();
        }
    };
    // A strided preview renders the corners of a grid only, the others interpolated (issue
    // 34). Under a budget (stride 0: automatic) it goes coarse to fine: every 8th pixel, which
    // always runs, then the corners of every 4th, 2nd and every pixel, each level admitted
    // while its cost, predicted from the level before, keeps the preview within kPreviewShare
    // of the budget (a cache's records make a sparse preview's cost per sample far higher than
    // a full one's, so no profile predicts it). capict tracks every pixel's branches from the
    // preview on, and processes sharing rows must agree on the grid: both render every pixel.
    const bool auto_stride = s_.preview_stride == 0 && budget_.budgeted() && bands_.empty();
    std::vector<uint32_t> levels = {auto_stride ? kCoarsestPreviewStride : std::max<uint32_t>(1, s_.preview_stride)};
    while (auto_stride && levels.back() > 1) levels.push_back(levels.back() / 2);
    if (subsampled_components(plan_) != 0) levels = {1};
    if (levels == std::vector<uint32_t>{1}) {  // every pixel
        run_samples("pre-selective", own_samples_of_every_pixel(0), carry);
    } else {
        double per_sample = 0;
        for (size_t i = 0; i < levels.size() && !stopping(); ++i) {
            // Admitted on the level's new corners counted, before its grid and ranges are made
            // (each a pass over every pixel: 1.5 ms at 384x288, wasted on a level refused).
            if (i > 0) {
                const uint64_t added = preview_samples_at(s_.width, s_.height, s_.spp, levels[i]) -
                                       preview_samples_at(s_.width, s_.height, s_.spp, levels[i - 1]);
                if (now() + per_sample * static_cast<double>(added) > kPreviewShare * stage_deadline(s_)) break;
            }
            SubsampleGrid grid = preview_grid(levels[i]);
            uint64_t samples = 0;
            const SampleRanges ranges = unsampled_corners(grid, samples);
            const double t = now();
            const uint64_t before = ex_->stats().camera.rays;
            run_samples("pre-selective", ranges, carry);
            const uint64_t traced = ex_->stats().camera.rays - before;
            if (traced > 0) per_sample = (now() - t) / static_cast<double>(traced);
            out_.preview_stride = levels[i];
            if (levels[i] > 1) out_.preview_grid = std::move(grid);
            else out_.preview_grid.reset();
        }
    }
    // The preview's image: the rays it carries to the selective stage stand in as av (D's)
    // until they run. The stand-ins are shared with the film's rows, so that guidance sees the
    // same preview on every process (the stand-ins are still zero: the preview drops no ray,
    // it carries them).
    const std::vector<double>& dropped = stand_ins_->ambient();
    CREX_CHECK(std::all_of(dropped.begin(), dropped.end(), [](double a) { return a == 0; }));
    preview_ambient_ = dropped;
    add_ambient(carried_[static_cast<size_t>(Component::kD)], s_.ambient, preview_ambient_);
    share_with_other_processes(RowExchange::kPreview, preview_ambient_);
    out_.preview = out_.film.composite(&preview_ambient_);
    out_.fill_unsampled_preview(out_.preview);
    out_.preview_seconds = now();  // on the budget's clock: a saved profile sizes later previews from it
    out_.preview_rays = total_rays(ex_->stats());
    out_.preview_samples = ex_->stats().camera.rays;
    if (cache_) {
        out_.ic_preview_records = cache_->records().size();
        out_.ic_preview_record_seconds = cache_->stats().record_seconds;
    }
    stage_end("end of the pre-selective stage", "guidance");
}

SelectiveSetup PlanRun::guidance_round(uint32_t round, uint32_t rounds) {
    const std::string label = rounds > 1 ? fmt::format(" (round {}/{})", round, rounds) : "";
    const double t_guidance = now();
    progress_ = {};
    progress_.stage = "guidance" + label;
    report_progress("maps");
    if (round > 1) share_with_other_processes(RowExchange::kRound, stand_ins_->ambient());  // the maps see every row as it is now
    // The image the maps see: the preview (with its carried D rays' stand-ins, shared with its
    // rows), or, in a later round, once the carried rays have run, the image so far.
    const GuidanceContext ctx{plan_, scene_, *rs_, s_, cache_.has_value()};
    const uint32_t grid_stride = out_.preview_grid ? out_.preview_stride : 1;  // the preview's pixels left out
    SelectiveSetup sel = round == 1 ? run_guidance(ctx, out_.preview, preview_ambient_, out_, surfaces_, grid_stride)
                                    : run_guidance(ctx, out_.film.composite(&stand_ins_->ambient()), stand_ins_->ambient(), out_, surfaces_);
    if (round == 1) preview_ambient_ = {};  // the maps have seen the preview
    out_.guidance_seconds += now() - t_guidance;
    stage_end("end of guidance" + label, "selective");
    return sel;
}

void PlanRun::selective_round(uint32_t round, uint32_t rounds, const SelectiveSetup& sel) {
    const std::string label = rounds > 1 ? fmt::format(" (round {}/{})", round, rounds) : "";
    const size_t pixels = out_.film.pixel_count();
    const double t_selective = now();  // the render's clock, as the other stages: paused while a report copies a snapshot
    ShadeParams shade = sel.shade;
    shade.caustic_irradiance = caustic_lookup_;
    if (!sel.shadow_rays.empty()) shade.shadow_rays_per_pixel = &sel.shadow_rays;
    if (!sel.media_samples.empty()) shade.media_samples_per_pixel = &sel.media_samples;
    if (!sel.specular_threshold.empty()) shade.specular_threshold_per_pixel = &sel.specular_threshold;
    ex_->set_shade_params(shade);
    if (round == 1) redo_preview_direct_light(sel);
    if (cache_) {
        if (round == 1) reanswer_preview_queries(sel);
        ex_->set_irradiance(executor_hook(answer_queries(), {base_aa_, sel.ic_accuracy.empty() ? nullptr : &sel.ic_accuracy,
                                                             sel.ic_priority.empty() ? nullptr : &sel.ic_priority,
                                                             sel.ic_divisions.empty() ? nullptr : &sel.ic_divisions}));
    }
    if (out_.component_subsample.any()) {  // capict: this round's grids gate the new samples' first bounces
        first_bounce_runs_ = out_.component_subsample.first_bounce_runs(pixels);
        ex_->set_first_bounce_runs(&first_bounce_runs_);
    }
    const std::vector<float>* base_importance = s_.executor.importance;
    const std::vector<float>* modulation = sel.modulation.empty() ? base_importance : &sel.modulation;
    auto run_selective = [&] {
        ex_->set_importance(modulation);
        ex_->run_stage(plan_.program.selective);
        ex_->set_importance(base_importance);
        flush_bins();
    };
    if (round == 1) {  // the preview's waiting rays first
        for (size_t c = 0; c < kComponentCount; ++c) std::swap(ex_->bins()[c], carried_[c]);
        run_selective();
        for (RayBatch& b : carried_) b = RayBatch();
        // A strided preview's pixels go on coarse to fine over the whole image (every 4th,
        // 2nd, then every pixel), so a budget that ends among them leaves a finer grid to
        // interpolate, not rows at the top rendered and the rest at the preview's grid.
        for (uint32_t filled = out_.preview_stride; out_.preview_grid && filled > 1 && !budget_.spent(now()) && !stopping();) {
            filled /= 2;
            SubsampleGrid grid = preview_grid(filled);
            uint64_t samples = 0;
            const uint64_t left_out = out_.budget_stopped_samples;
            run_samples("selective: the preview's pixels", unsampled_corners(grid, samples), [&] {
                ex_->run_stage(plan_.program.preselective);
                run_selective();
            });
            if (out_.budget_stopped_samples != left_out) {  // cut short: counted with the stage's own below
                out_.budget_stopped_samples = left_out;
                break;
            }
            if (filled > 1) out_.preview_grid = std::move(grid);
            else out_.preview_grid.reset();
        }
    }
    SampleRanges ranges;
    ranges.start_of.resize(pixels);
    ranges.end_of.resize(pixels);
    for (size_t p = 0; p < pixels; ++p) {
        ranges.start_of[p] = out_.film.samples(static_cast<uint32_t>(p));
        double target = sel.spp_end[p] <= s_.spp ? 0 : s_.spp + double(sel.spp_end[p] - s_.spp) * round / rounds;
        // Inherited samples count, up to the cap (own_samples); the preview's stay.
        if (s_.history && target > 0) target = own_samples(target, s_.history->samples(p), s_.history->frames);
        ranges.end_of[p] = static_cast<uint32_t>(std::max(0.0, std::ceil(target - 1e-9)));
    }
    last_stage_ = round == rounds;
    // Distributed: bands of about the same camera samples for this round. In round 1 the work
    // on the preview's samples above (carried rays, direct light redone, queries answered
    // again) was done in the preview's bands.
    balance_bands(ranges, round == 1);
    run_samples("selective" + label, ranges, [&] {
        ex_->run_stage(plan_.program.preselective);
        run_selective();
    });
    last_stage_ = false;
    out_.selective_seconds += now() - t_selective;
    if (round < rounds) stage_end("end of selective rendering" + label, "guidance");
}

void PlanRun::refine_components() {
    for (int round = 0; round < kMaxRefinementRounds; ++round) {
        std::vector<float> before;  // the image before the round, before its grids split
        if (recorder_) recorder_->paused([&] { before = composite_now(); });
        std::optional<Refinement> next = next_refinement(plan_, out_.component_subsample, out_.film, s_.spp);
        if (!next) return;
        replay_start_image_ = std::move(before);
        first_bounce_runs_ = std::move(next->runs);
        ex_->set_first_bounce_runs(&first_bounce_runs_);
        ex_->set_replay_branches(next->replay);
        run_samples(fmt::format("refinement {}", round + 1), next->ranges, [&] {
            ex_->run_stage(plan_.program.preselective);
            ex_->run_stage(plan_.program.selective);
            flush_bins();
        });
        ex_->set_replay_branches(0);
        replay_start_image_.clear();
        ++out_.refinements;
    }
}

void PlanRun::end_of_stages() {
    if (cache_) out_.ic_selective_records = cache_->records().size() - out_.ic_preview_records;
    out_.selective_rays = total_rays(ex_->stats()) - out_.preview_rays;
    stage_end("end of render", "end");
}

RunResult PlanRun::finish() {
    const double end_start = now();
    out_.stats = ex_->stats();
    if (s_.ambient_auto) {
        // Where no ray of a component ran, the mean radiance of the image stands in: the
        // preview's for a pipeline, else the composite so far.
        // The preview by reference: a copy of it made a fresh allocation after the budget's last
        // decision, and its page faults took 0.1 to 3.6 ms on this VM.
        std::vector<float> composite;
        if (out_.preview.empty()) composite = out_.film.composite(&stand_ins_->ambient());
        const std::vector<float>& image = out_.preview.empty() ? composite : out_.preview;
        const size_t w = static_cast<size_t>(s_.width);
        stand_ins_->finish_automatic(out_.film, out_.stats, image, static_cast<size_t>(first_row()) * w, static_cast<size_t>(end_row()) * w,
                                     bands_.empty() ? nullptr : &group_, out_.auto_ambient, out_.notes);
    }
    // Distributed: capict's refinement kept the last round's bands (no exchange since).
    share_rows(RowExchange::kEnd, stand_ins_->ambient());
    out_.row_bands = bands_;
    out_.ambient = std::move(stand_ins_->ambient());
    if (!bands_.empty()) group_.final_image(out_.image(), s_.width);
    // Passes repeat a step's warning (a '*' cap hit in every pass): the sink keeps each once.
    DiagnosticSink said;
    for (const Diagnostic& w : out_.warnings) said.add(w);  // the textures'
    for (const Diagnostic& w : ex_->warnings()) said.add(w);
    for (Diagnostic& w : modulation_warnings(out_.stats, plan_, s_.executor.constant_importance)) said.add(std::move(w));
    if (rs_->textures)
        for (const TextureImage& i : rs_->textures->stats().since(textures_before_).images) {
            if (i.failed_lookups > 0)
                said.add(run_diagnostic("W310", i.name,
                                        fmt::format("texture could not be read where {} lookup{} asked (a damaged or truncated file?): "
                                                    "there it rendered magenta where it gives a colour",
                                                    i.failed_lookups, i.failed_lookups == 1 ? "" : "s")));
            if (i.non_finite_lookups > 0)
                said.add(run_diagnostic("W314", i.name,
                                        fmt::format("texture holds texels that are not finite (NaN or infinite): {} filtered lookup{} "
                                                    "met them and took the nearest texel instead, 0 where that one is not finite; "
                                                    "repair the file, e.g. oiiotool FILE --fixnan box3 -o FIXED",
                                                    i.non_finite_lookups, i.non_finite_lookups == 1 ? "" : "s")));
        }
    if (cache_ && cache_->stats().over_limit > 0)
        said.add(run_diagnostic(
            "W406", "crex run",
            fmt::format("the irradiance cache filled --max-memory {:.0f} MiB ({} records): {} queries after that took the ambient "
                        "value (--ambient) instead of records, and the image lacks their indirect light; coarsen --aa or --ar, "
                        "lower --ad, or raise --max-memory",
                        static_cast<double>(s_.max_memory) / (1 << 20), cache_->records().size(), cache_->stats().over_limit)));
    out_.warnings = said.sorted();
    out_.render_seconds = clock_();
    out_.end_seconds = std::max(0.0, out_.render_seconds - end_start);
    out_.render_cpu_seconds = process_cpu_seconds() - cpu_at_start_;
    stand_ins_->release();
    out_.render_thread_seconds = out_.render_seconds * tbb::this_task_arena::max_concurrency();
    // After the render's wall and CPU time are taken: this is not part of the render.
    if (s_.time_strided_preview && out_.staged && !out_.preview.empty() && !budget_.budgeted())
        out_.strided_preview_seconds = time_strided_preview();
    if (s_.time_strided_preview && s_.ambient_auto && !budget_.budgeted() && bands_.empty()) out_.budgeted_end_seconds = time_budgeted_end();
    if (rs_->textures) out_.textures = rs_->textures->stats().since(textures_before_);
    out_.caustic_map = caustic_map_;  // empty too: a later frame need not trace its photons again
    out_.history = s_.history;
    if (cache_) {
        out_.ic_stats = cache_->stats();
        if (!s_.ic_file.empty() && group_.saves_cache_file()) save_cache_file(*cache_, s_.ic_file);
        // Moved, not copied: a walk's cache is 100k records and more (and its grids, for the next frame).
        out_.ic_records = cache_->take_records(s_.hand_on_ic_grids ? &out_.ic_grids : nullptr);
    }
    measure_light_left_out();
    return std::move(out_);
}

void PlanRun::measure_light_left_out() {
    const ExecutorStats& st = out_.stats;
    const double samples = static_cast<double>(st.camera.rays);
    if (samples > 0) {
        const double depth = st.cut_by_depth / samples, weight = st.cut_by_weight / samples;
        out_.light_cut_by_depth = depth / (1 + depth);
        out_.light_cut_by_weight = weight / (1 + weight);
    }
    if (!cache_ || max_component(s_.irradiance_cache->ambient) > 0 ||
        out_.ic_stats.albedo_rays.size() != s_.irradiance_cache->bounces)
        return;
    const double past = out_.ic_stats.throughput_past_last_bounce();
    double image = 0, d = 0;
    for (const float v : out_.image()) image += v;
    for (const float v : out_.aov_image(aov_of(Component::kD))) d += v;
    if (image + past * d > 0) out_.light_cut_by_cache = past * d / (image + past * d);
}

void PlanRun::report_progress(const std::string& step) {
    progress_.step = step;
    progress_.stage_seconds = seconds_since(stage_start_);
    double done = static_cast<double>(stage_samples_done_);
    if (pass_samples_ > 0 && samples_in_passes_ > 0 && rays_in_passes_ > 0 && ex_) {
        const double expected = static_cast<double>(rays_in_passes_) / static_cast<double>(samples_in_passes_) * static_cast<double>(pass_samples_);
        done += std::min(0.95, static_cast<double>(ex_->rays_done() - pass_rays_start_) / expected) * static_cast<double>(pass_samples_);
    }
    progress_.fraction = stage_samples_ ? done / static_cast<double>(stage_samples_) : 0;
    progress_.rays = ex_ ? ex_->rays_done() : 0;
    observer_.progress(progress_);
}

std::vector<float> PlanRun::snapshot() const {
    std::vector<float> rgb = composite_now();
    if (pass_start_image_.empty()) return rgb;
    // A pixel whose samples of the running pass still have rays waiting shows what it was when
    // the pass began (if it had samples then): its new samples are not done yet, and standing
    // their missing light in with a component's average made the error curve jump up at every
    // pass of a selective round (issue 17).
    std::vector<uint8_t> in_flight(out_.film.pixel_count(), 0);
    ex_->for_each_waiting_ray([&](uint32_t p) { in_flight[p] = 1; });
    for (size_t p = 0; p < in_flight.size(); ++p)
        if (in_flight[p] && pass_start_samples_[p] > 0)
            for (size_t k = 0; k < 3; ++k) rgb[3 * p + k] = pass_start_image_[3 * p + k];
    // capict's refinement: the image is the one before the round until the round ends. A new
    // corner's first bounces count as run when they are spawned, before their light arrives,
    // so mid-round it and every pixel interpolating from it looked too dark (the error curve
    // jumped at every round).
    if (!replay_start_image_.empty()) rgb = replay_start_image_;
    return rgb;
}

std::vector<float> PlanRun::composite_now() const {
    std::vector<double> ambient = stand_ins_->if_stopped_now(out_.film, ex_->stats(), ex_->bins(), carried_);
    out_.component_subsample.add_stand_ins(out_.film, ambient);
    std::vector<float> rgb = out_.film.composite(&ambient);
    out_.fill_unsampled_preview(rgb);
    if (out_.subsample) out_.subsample->fill(rgb);
    return rgb;
}

// What a preview at the coarsest stride does per pixel of the frame, not per sample, done again
// after the clock stopped on copies (the image is not touched): its grid and sample ranges, the
// composite and the fill of the pixels it skipped. 7 ms at 384x288, which a floor predicted
// from the cost per sample alone left out (it was 1.2-1.8x too low without a cache).
double PlanRun::time_strided_preview() const {
    const auto t = Clock::now();
    const SubsampleGrid grid = preview_grid(kCoarsestPreviewStride);
    uint64_t samples = 0;
    const SampleRanges ranges = unsampled_corners(grid, samples);
    std::vector<float> image = out_.film.composite(nullptr);
    std::vector<uint8_t> sampled(out_.film.pixel_count());
    for (uint32_t p = 0; p < sampled.size(); ++p) sampled[p] = grid.rendered(p);
    grid.fill_unsampled(image, sampled);
    CREX_CHECK_EQ(ranges.start_of.size(), sampled.size());
    return seconds_since(t);
}

// The end of a budgeted render, which a full render does not show: there every component's
// light left unexecuted in every pixel stands in (ambient_stand_ins.h), a few passes over
// per-pixel buffers, linear in the pixels. Done after the clock stopped, on copies over at most
// kEndProbePixels pixels, three times: the median, scaled to the frame. The one end a profile
// used to keep (a full render's, with nothing to stand in) ran from 8 to 31 ms for the same
// frame (cbtcr, room, 512x384), and a budget kept that much back.
double PlanRun::time_budgeted_end() const {
    constexpr size_t kEndProbePixels = size_t{1} << 18;
    const size_t pixels = out_.film.pixel_count(), n = std::min(pixels, kEndProbePixels);
    if (n == 0 || out_.preview.size() < 3 * n) return 0;  // a pipeline's: its preview is the image stand-ins start from
    std::array<double, 3> seconds{};
    for (double& t : seconds) {
        AmbientStandIns probe(n, stand_ins_->av(), true);
        probe.leave_everywhere(1.0f / 1024);
        std::array<Vec3, kComponentCount> ambient{};
        std::vector<std::string> notes;
        const auto start = Clock::now();
        probe.finish_automatic(out_.film, out_.stats, out_.preview, 0, n, nullptr, ambient, notes);
        t = seconds_since(start);
    }
    std::sort(seconds.begin(), seconds.end());
    return seconds[1] * static_cast<double>(pixels) / static_cast<double>(n);
}

void PlanRun::stage_end(const std::string& what, const std::string& next) {
    if (!recorder_) return;
    recorder_->event(what, true, ex_->rays_done(), [this] { return snapshot(); }, true);
    recorder_->set_stage(next);
}

void PlanRun::run_samples(const std::string& stage, const SampleRanges& all_rows, const std::function<void()>& after_camera_rays) {
    const bool some_rows = !bands_.empty(), resumed = last_stage_ && !s_.final_rows.empty();
    const SampleRanges unfinished = resumed ? without_rows(all_rows, s_.width, s_.height, s_.final_rows) : SampleRanges{};
    const SampleRanges& wanted = resumed ? unfinished : all_rows;
    const SampleRanges restricted = some_rows ? only_rows(wanted, s_.width, s_.height, first_row(), end_row()) : SampleRanges{};
    const SampleRanges& ranges = some_rows ? restricted : wanted;
    // What the process holds beside the passes' rays (scene, film, carried rays). Guidance's
    // buffers and the output images are made when no pass runs.
    size_t held = 0;
    for (const RayBatch& b : carried_) held += b.size() * kBytesPerSample / 2;
    held += stand_ins_->kept_bytes();
    // With a cache the split changes the image (records made in one pass answer the next), so
    // passes are sized as if the film held every buffer: which images a run writes (component
    // images or not) must not change the cache's records and the image.
    const size_t fixed = resident_bytes(out_.film.pixel_count(), cache_ ? FilmLayout{} : out_.film.layout(), out_.film.tracked_branches(),
                                        !stand_ins_->ambient().empty(), out_.staged);
    PassLimits limits;
    limits.bytes = pass_bytes(fixed, held, *rs_, s_.width, s_.max_memory);
    // Progressive passes (pass_sizing.h), sized on the whole frame so that every process of a
    // group splits its samples as one process would (a pixel's sum in the same order). Not with
    // a cache: records made in one pass answer the next, so the split would change the image.
    const uint32_t progressive = cache_ ? 0 : progressive_pass_samples(wanted);
    StagePasses stage_passes(s_.width, s_.height, ranges, limits, budget_.budgeted(), s_.pass_samples, progressive);
    std::vector<SamplePass>& passes = stage_passes.passes();
    ex_->reset_peak_rays_held();
    for (const SamplePass& p : passes) {
        CREX_CHECK_LT(p.first, p.end);
        CREX_CHECK_LT(p.row_begin, p.row_end);
        CREX_CHECK_LT(uint64_t{0}, p.samples);
    }
    progress_ = {};
    progress_.stage = stage;
    progress_.passes = passes.size();
    stage_samples_ = 0, stage_samples_done_ = 0;
    stage_start_ = Clock::now();
    for (const auto& p : passes) stage_samples_ += p.samples;
    bool out_of_time = false;
    for (size_t i = 0; i < passes.size() && !out_of_time; ++i) {
        // Under a budget a pass may run as several bands of rows: each admitted on the cost
        // measured so far, so the last decision lands within a band's error of the budget.
        for (int row = passes[i].row_begin; row < passes[i].row_end;) {
            SamplePass pass = passes[i];
            pass.row_begin = row;
            pass.samples = row == passes[i].row_begin ? pass.samples : samples_in(pass, ranges, s_.width);
            const bool first = out_.passes == 0 && pass.first == 0;  // the render's first: there is always an image
            const std::optional<SamplePass> admitted = budget_.admit(pass, ranges, s_.width, now(), first);
            if (!admitted || stopping()) {
                out_of_time = true;
                break;
            }
            pass = *admitted;
            progress_.pass = i + 1;
            report_progress("camera rays");
            if (recorder_)
                recorder_->paused([&] {
                    pass_start_image_ = composite_now();
                    pass_start_samples_.resize(out_.film.pixel_count());
                    for (uint32_t p = 0; p < pass_start_samples_.size(); ++p) pass_start_samples_[p] = out_.film.samples(p);
                });
            const double t = now();
            pass_samples_ = pass.samples, pass_rays_start_ = ex_->rays_done();
            // Progressive passes run their crex whole, except the render's first: it always
            // runs (an image in every pixel), so under a budget shorter than it its component
            // rays go in batches like cbtcr's (a 5 % budget overran by 15-65 %).
            const bool first_cut = budget_.budgeted() && out_.passes == 0 && policy_admission_ == ExecutorOptions::TaskAdmission::kNone;
            if (first_cut) ex_->set_task_admission(ExecutorOptions::TaskAdmission::kBatches);
            trace_camera_rays(pass, ranges);
            after_camera_rays();
            if (first_cut) ex_->set_task_admission(policy_admission_);
            pass_start_image_.clear();
            budget_.measured(now() - t, pass.samples);
            stage_samples_done_ += pass.samples;
            samples_in_passes_ += pass.samples, rays_in_passes_ += ex_->rays_done() - pass_rays_start_;
            pass_samples_ = 0;
            ++out_.passes;
            row = pass.row_end;
        }
        if (i == 0)
            if (const size_t bytes = stage_passes.replan_after_first(ex_->peak_rays_held(), out_.film.pixel_count())) {
                progress_.passes = passes.size();
                out_.bytes_per_sample = bytes;
            }
    }
    if (out_of_time) (out_.stopped ? out_.stopped_samples : out_.budget_stopped_samples) += stage_samples_ - stage_samples_done_;
    report_progress("");
}

void PlanRun::trace_camera_rays(const SamplePass& pass, const SampleRanges& ranges) {
    const size_t w = static_cast<size_t>(s_.width);
    const size_t p0 = static_cast<size_t>(pass.row_begin) * w, p1 = static_cast<size_t>(pass.row_end) * w;
    auto first_of = [&](size_t p) { return std::max(ranges.start(p), pass.first); };
    auto samples_of = [&](size_t p) -> uint32_t {
        uint32_t first = first_of(p), end = std::min(pass.end, ranges.stop(p));
        return end > first ? end - first : 0;
    };
    // Each pixel's rays go to a fixed place, so they can be made in parallel and in order.
    std::vector<uint64_t> at(p1 - p0 + 1, 0);
    for (size_t p = p0; p < p1; ++p) at[p - p0 + 1] = at[p - p0] + samples_of(p);
    RayBatch rays;
    rays.resize(at.back());
    tbb::parallel_for(tbb::blocked_range<size_t>(p0, p1, 256), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t p = range.begin(); p < range.end(); ++p) {
            const uint32_t n = samples_of(p);
            for (uint32_t k = 0; k < n; ++k) {
                RayRecord r = camera_ray(*camera_, camera_seeds(p), s_.width, static_cast<uint32_t>(p), first_of(p) + k, s_.filter);
                rays.write(at[p - p0] + k, &r, 1);
            }
        }
    });
    CREX_CHECK_EQ(rays.size(), pass.samples);
    ex_->run_camera_rays(rays);
}

void PlanRun::balance_bands(const SampleRanges& all_rows, bool worked_since_exchange) {
    if (bands_.empty()) return;
    // Every process computes the same split: the film's sample counts and the maps are the
    // same everywhere after an exchange, and the work on the preview's samples in round 1 adds
    // no camera sample. (--resume's final rows count for nothing, as in run_samples, though
    // it runs in one process only.)
    const bool resumed = last_stage_ && !s_.final_rows.empty();
    std::vector<int> split = balanced_row_bands(resumed ? without_rows(all_rows, s_.width, s_.height, s_.final_rows) : all_rows,
                                                s_.width, s_.height, static_cast<int>(bands_.size()) - 1);
    if (split == bands_) return;
    // Work done since the last exchange is in the old bands' rows: shared before they change.
    if (worked_since_exchange) share_with_other_processes(RowExchange::kNewBands, stand_ins_->ambient());
    bands_ = std::move(split);
}

SampleRanges PlanRun::unsampled_corners(const SubsampleGrid& grid, uint64_t& samples) const {
    const size_t pixels = out_.film.pixel_count();
    SampleRanges level{0, s_.spp, std::vector<uint32_t>(pixels, 0), std::vector<uint32_t>(pixels, 0)};
    samples = 0;
    for (uint32_t p = 0; p < pixels; ++p)
        if (grid.rendered(p) && out_.film.samples(p) == 0 && !(out_.subsample && !out_.subsample->rendered(p))) {
            level.end_of[p] = s_.spp;
            samples += s_.spp;
        }
    return level;
}

void PlanRun::reanswer_preview_queries(const SelectiveSetup& sel) {
    // The preview's D samples of pixels that now ask for a finer accuracy are answered again,
    // important pixels first; the old answer's light is taken back out of the film.
    // (Or more hemisphere rays: the preview's records have the fewer of `ic_rays`' two ends.)
    if (sel.ic_accuracy.empty() && sel.ic_divisions.empty()) return;
    const uint32_t preview_divisions = cache_->settings().divisions;
    auto asked_again = [&](const IcAnswer& a) {
        const uint32_t p = a.pixel;
        const bool finer = !sel.ic_accuracy.empty() && sel.ic_accuracy[p] < a.accuracy - 1e-9;
        const bool quieter = !sel.ic_divisions.empty() && sel.ic_divisions[p] > preview_divisions;
        return (finer || quieter) && !inherits_its_quality(sel, p);
    };
    // The answers not asked again are dropped first, their blocks freed: the queries are made a
    // batch at a time from the answers left, not all beside the whole log (a copy, its pointers
    // and a batch's copy held 3.3 times the log at once).
    IcAnswerLog& log = preview_answers_;
    log.erase(std::remove_if(log.begin(), log.end(), [&](const IcAnswer& a) { return !asked_again(a); }), log.end());
    auto query_of = [&](const IcAnswer& a) {
        const uint32_t p = a.pixel;
        return IcQuery{{a.origin[0], a.origin[1], a.origin[2]},
                       normalize_or_zero(Vec3{a.direction[0], a.direction[1], a.direction[2]}),
                       sel.ic_accuracy.empty() ? a.accuracy : sel.ic_accuracy[p],
                       sel.ic_priority[p],
                       a.path,
                       sel.ic_divisions.empty() ? uint16_t{0} : sel.ic_divisions[p]};
    };
    // Said as the selective stage's first step: the cache's progress lines come from here.
    progress_ = {};
    progress_.stage = "selective: the preview's D samples answered again";
    stage_start_ = Clock::now();
    stage_samples_ = log.size(), stage_samples_done_ = 0, pass_samples_ = 0;
    std::vector<size_t> order(log.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return sel.ic_priority[log[a].pixel] > sel.ic_priority[log[b].pixel]; });
    // Batches start small and double, each predicted from the one before (its time per query):
    // the first answers make most of the new records, so their cost is unknown until measured.
    // The first is two queries a thread: a fine record can make a cascade of deeper ones
    // (prog_tc on the room: 5.8 ms a query, so a first batch of 64 took 0.32 s of a 0.78 s
    // budget that had 0.14 s left).
    size_t batch = budget_.budgeted() ? 2 * static_cast<size_t>(std::max(1, tbb::this_task_arena::max_concurrency()))
                                      : std::max<size_t>(1, log.size());
    size_t done = 0;
    double per_query = 0;
    while (done < order.size() && budget_.fits(now(), per_query * static_cast<double>(std::min(batch, order.size() - done)))) {
        const double t = now();
        const size_t end = std::min(order.size(), done + batch);
        std::vector<IcQuery> part;
        part.reserve(end - done);
        for (size_t k = done; k < end; ++k) part.push_back(query_of(log[order[k]]));
        std::vector<Vec3> e;
        answer_queries()(part, e);
        for (size_t k = done; k < end; ++k) {
            const IcAnswer& a = log[order[k]];
            const Vec3 beta{a.beta[0], a.beta[1], a.beta[2]}, before{a.irradiance[0], a.irradiance[1], a.irradiance[2]};
            Vec3 delta = beta * (e[k - done] - before) / kPi;
            if (is_finite(delta)) out_.film.add(aov_of(Component::kD), a.pixel, delta, a.flags);
        }
        per_query = (now() - t) / static_cast<double>(end - done);
        done = end;
        stage_samples_done_ = done;
        batch *= 2;
    }
    out_.ic_reprocessed = done;
    preview_answers_.clear();
    preview_answers_.shrink_to_fit();
}

void PlanRun::redo_preview_direct_light(const SelectiveSetup& sel) {
    // The preview's samples are kept (spec: its work is never thrown away), so a pixel that
    // asks for more shadow rays than the preview's base would otherwise keep a base-quality
    // direct light in them: with few samples per pixel, most of its image (thesis 8.2's
    // progressive direct lighting re-estimates it too).
    if (sel.shadow_rays.empty()) return;
    if (budget_.spent(now())) return;
    // Distributed: in the preview's bands, as the rest of round 1's work on the preview's samples.
    const size_t w = static_cast<size_t>(s_.width);
    const size_t p0 = static_cast<size_t>(first_row()) * w, p1 = static_cast<size_t>(end_row()) * w;
    RayBatch rays;
    for (size_t p = p0; p < p1; ++p) {
        if (sel.shadow_rays[p] <= preview_shadow_rays_) continue;
        const uint32_t kept = std::min(s_.spp, out_.film.samples(static_cast<uint32_t>(p)));
        append_camera_rays(*camera_, camera_seeds(p), s_.width, static_cast<uint32_t>(p), 0, kept, rays, s_.filter);
    }
    if (rays.empty()) return;
    std::vector<Vec3> delta;
    out_.direct_light_redone_shadow_rays += redo_camera_direct_light(*rs_, rays, preview_shadow_rays_, cache_.has_value(), sel.shadow_rays, delta);
    for (size_t i = 0; i < rays.size(); ++i)
        if (is_finite(delta[i])) out_.film.add(kCameraAov, rays.pixel[i], delta[i], rays.flags[i]);
    out_.direct_light_redone += rays.size();
}

}  // namespace

std::vector<Diagnostic> modulation_warnings(const ExecutorStats& stats, const PipelinePlan& plan, double constant_importance) {
    std::string map = fmt::format("the constant importance {:g} (--importance)", constant_importance);
    for (const PlanMap& m : plan.maps)
        if (m.id == plan.modulation_map) map = fmt::format("the map '{}'", m.defines.empty() ? m.name : m.defines);
    std::vector<Diagnostic> out;
    for (const ModulatedStep& m : stats.modulated) {
        if (m.found == 0 || m.taken > 0) continue;
        const char c = component_letter(m.component);
        out.push_back(run_diagnostic("W405", m.where,
                                     fmt::format("{} inside '{{ }}' ran no ray: as occurrence {:g} of {:g} it runs where the importance "
                                                 "is above {:g}/{:g} = {:.3f}, and {} reached at most {:.3f} where {} had rays; raise the "
                                                 "map (or its weight) or put {} earlier inside the braces",
                                                 c, m.index + 1, m.occurrences, m.index, m.occurrences, m.index / m.occurrences, map,
                                                 m.highest_importance, c, c)));
    }
    return out;
}

IcSettings plan_cache_settings(const PipelinePlan& plan, IcSettings ics) {
    for (const PlanVariable& v : plan.variables)
        if (v.variable == pipeline::SelectiveVariable::kIcRadius) {
            // The preview uses the accuracy where the map is 0 (spec: `from`); the selective stage refines.
            ics.accuracy = v.from;
            ics.max_accuracy = std::max({v.from, v.to, ics.accuracy});
        } else if (v.variable == pipeline::SelectiveVariable::kIcRays) {
            // The preview's records have the fewer rays of the two ends (whichever end the map's 0
            // is): the preview stays cheap, and pixels that ask for more make their own.
            ics.divisions = ic_rays_step(std::min(v.from, v.to));
        }
    return ics;
}

bool may_refine_accuracy(const PipelinePlan& plan) {
    for (const PlanVariable& v : plan.variables)
        if ((v.variable == pipeline::SelectiveVariable::kIcRadius && v.to < v.from) ||  // a smaller accuracy is finer
            (v.variable == pipeline::SelectiveVariable::kIcRays && ic_rays_step(v.to) != ic_rays_step(v.from)))
            return true;
    return false;
}

uint32_t plan_rounds(const PipelinePlan& plan) { return plan.settings.rounds.value_or(1); }

bool has_guidance(const PipelinePlan& plan) { return !plan.maps.empty() || !plan.variables.empty(); }

uint64_t total_rays(const ExecutorStats& stats) {
    uint64_t n = stats.camera.rays;
    for (const auto& c : stats.components) n += c.rays;
    return n;
}

RunResult run_plan(const Scene& scene, const PipelinePlan& plan, const RunSettings& settings, ProcessGroup& group, RunObserver& observer) {
    refuse_what_cannot_fit(plan, settings);
    return PlanRun(scene, plan, settings, group, observer).execute();
}

RunResult run_plan(const Scene& scene, const PipelinePlan& plan, const RunSettings& settings) {
    LocalGroup one;
    RunObserver nobody;
    return run_plan(scene, plan, settings, one, nobody);
}

RunResult render(const Scene& scene, const sched::Program& program, const RunSettings& settings, RunObserver& observer) {
    PipelinePlan plan;
    plan.program = program;
    LocalGroup one;
    return run_plan(scene, plan, settings, one, observer);
}

RunResult render(const Scene& scene, const sched::Program& program, const RunSettings& settings) {
    RunObserver nobody;
    return render(scene, program, settings, nobody);
}

}  // namespace crex
