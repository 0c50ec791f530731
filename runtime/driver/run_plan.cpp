#include "runtime/driver/run_plan.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <numeric>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <set>

#include "base/check.h"
#include "runtime/base/cpu_time.h"
#include "runtime/base/memory.h"
#include "runtime/base/sampling.h"
#include "runtime/driver/row_bands.h"
#include "runtime/driver/sample_passes.h"
#include "runtime/pipeline/guidance_graph.h"
#include "runtime/pipeline/pixel_probe.h"
#include "runtime/pipeline/svt.h"
#include "runtime/render/render_scene.h"

namespace crex {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Memory model of a pass: a camera sample in flight is its ray, its hit and shading buffers
// and the children it leaves in the bins. Before passes, 512x512 at 16 spp of (TTMRSGD)* on
// builtin:cornell peaked at 1.51 GB for 4.2 M samples (~360 bytes each); 512 leaves room for
// the allocator's slack (at 400, 64 spp peaked at 1.10 GB under a 1 GiB limit; at 512, 0.87 GB).
constexpr size_t kBytesPerSample = 512;
// What a ray waiting in a bin costs with the step that made it (the bin it was taken from,
// shading buffers) and the allocator's slack, from max RSS over the peak rays held: Cornell
// 256x256 64 spp ~275 bytes (1.2 rays held a sample), the room ~345 (4.1 rays: trans and glass
// split lobes). A scene that holds more than the model's 512 bytes a sample has its later
// passes sized by this (the room at 128 spp went to 2.06 GB under a 1 GiB limit).
constexpr size_t kBytesPerHeldRay = 400;
// The process without any rays: code, Embree's and TBB's arenas, the images being written.
constexpr size_t kBaselineBytes = size_t{96} << 20;
// Beside the film (Film::bytes_per_pixel): the ambient stand-ins, RGB in double.
constexpr size_t kAmbientBytesPerPixel = 3 * 8;
// The images made after the render (composite, layers, tone-mapped copies).
constexpr size_t kOutputBytesPerPixel = 3 * 12;
// A triangle: its vertices and normal here, Embree's copy and BVH nodes.
constexpr size_t kBytesPerTriangle = 256;
// Guidance: the preview, nine linear buffers, maps and their intermediates.
constexpr size_t kGuidanceBytesPerPixel = 12 * 12 + 16 * 4;

// What a render holds whatever its passes: the process's baseline, the film and its ambient
// stand-ins, guidance's buffers while they are to come (`guidance`), the output images.
size_t fixed_bytes(size_t pixels, uint8_t tracked_branches, bool guidance) {
    const size_t per_pixel =
        Film::bytes_per_pixel(tracked_branches) + kAmbientBytesPerPixel + kOutputBytesPerPixel + (guidance ? kGuidanceBytesPerPixel : 0);
    return kBaselineBytes + pixels * per_pixel;
}

// capict: the components whose first-bounce branches the film tracks (their `subsample(X)`).
uint8_t subsampled_components(const PipelinePlan& plan) {
    uint8_t branches = 0;
    for (const PlanVariable& v : plan.variables)
        if (v.variable == pipeline::SelectiveVariable::kSubsample && v.component)
            branches = static_cast<uint8_t>(branches | (1u << static_cast<unsigned>(*v.component)));
    return branches;
}

// A render whose film and buffers alone need more than the machine has free is refused before
// anything is allocated: otherwise the kernel's overcommit lets it start, and the out-of-memory
// killer ends it (or another process) minutes later. A 16384x16384 Cornell box went past 15 GB
// on a 24 GB machine before it was stopped.
void refuse_what_cannot_fit(const PipelinePlan& plan, const RunSettings& s) {
    const std::optional<size_t> available = memory_available_bytes();
    if (!available) return;
    const size_t pixels = static_cast<size_t>(s.width) * static_cast<size_t>(s.height);
    const size_t needed = fixed_bytes(pixels, subsampled_components(plan), plan.staged);
    if (needed <= *available) return;
    constexpr double kGB = 1e9;
    throw std::runtime_error(fmt::format(
        "a {}x{} render holds {:.1f} GB whatever its passes ({} bytes a pixel: the film's sums in double, the "
        "ambient stand-ins, {}the output images), more than the {:.1f} GB of memory and swap this machine has "
        "free; render it smaller (--size)",
        s.width, s.height, static_cast<double>(needed) / kGB, (needed - kBaselineBytes) / std::max<size_t>(pixels, 1),
        plan.staged ? "guidance's buffers, " : "", static_cast<double>(*available) / kGB));
}

bool needs_probe(const PipelinePlan& plan) {
    for (const PlanMap& m : plan.maps)
        if (m.op && pipeline::signature(*m.op).needs_scene) return true;
    return false;
}

std::vector<float> map_values(const guidance::Raster& r, size_t pixels) {
    CREX_CHECK(r.channels == 1 && r.pixels() == pixels);  // every operator makes maps of the image's size
    return r.v;
}

/// The per-pixel values the svt gives the selective stage.
struct SelectiveSetup {
    ShadeParams shade;
    std::vector<uint32_t> spp_end;  ///< per pixel: sample index to end at (<= preview spp: none added)
    std::vector<uint16_t> shadow_rays;
    std::vector<uint16_t> media_samples;
    std::vector<float> specular_threshold;
    std::vector<float> ic_accuracy, ic_priority;
    std::vector<float> modulation;  ///< I(p) of `{ }`
};

// A per-pixel count of rays or samples (1..1024) from a variable's values; returns the largest,
// which sizes the shading buffers.
uint32_t per_pixel_counts(const std::vector<double>& values, std::vector<uint16_t>& counts) {
    counts.resize(values.size());
    uint32_t mx = 1;
    for (size_t p = 0; p < values.size(); ++p) {
        counts[p] = static_cast<uint16_t>(std::clamp(values[p], 1.0, 1024.0));
        mx = std::max<uint32_t>(mx, counts[p]);
    }
    return mx;
}

// ambient += av x the throughput left unexecuted per pixel (RGB).
void add_stand_in(const std::vector<float>& left, const Vec3& av, std::vector<double>& ambient) {
    for (size_t i = 0; i < left.size() && i < ambient.size(); ++i) ambient[i] += (i % 3 == 0 ? av.x : i % 3 == 1 ? av.y : av.z) * left[i];
}

class PlanRun {
public:
    PlanRun(const Scene& scene, const PipelinePlan& plan, const RunSettings& settings, ProcessGroup& group, RunObserver& observer)
        : scene_(scene), plan_(plan), s_(settings), group_(group), observer_(observer), recorder_(observer.checkpoints()),
          out_(settings.width, settings.height) {}

    RunResult execute();

private:
    // A stage's camera samples in passes; after each pass's camera rays, `after_camera_rays`
    // runs the programs over its bins.
    void run_samples(const std::string& stage, const SampleRanges& ranges, const std::function<void()>& after_camera_rays);
    void trace_camera_rays(const SamplePass& pass, const SampleRanges& ranges);
    void flush_bins();  // rays left at the end of a pass: D stands in as ambient, the rest dropped
    std::vector<float> snapshot() const;       // the image a checkpoint records
    std::vector<float> composite_now() const;  // film + what waiting rays stand in for
    size_t pass_bytes(size_t held_bytes) const;
    void report_progress(const std::string& step);
    void stage_end(const std::string& what, const std::string& next);
    double now() const { return clock_(); }

    void setup_cache();
    void save_cache();
    void measure_light_left_out();
    // A batch of D queries answered here, or by another process of the group.
    IcAnswerFn answer_queries() {
        return [this](const std::vector<IcQuery>& q, std::vector<Vec3>& e) { group_.answer_queries(*cache_, q, e); };
    }
    SelectiveSetup guidance(bool from_current_image);
    void reanswer_preview_queries(const SelectiveSetup& sel);
    void redo_preview_direct_light(const SelectiveSetup& sel);
    void refine_components(const sched::Program& program);

    const Scene& scene_;
    const PipelinePlan& plan_;
    const RunSettings& s_;
    ProcessGroup& group_;
    RunObserver& observer_;
    CheckpointRecorder* recorder_;  // reports: image snapshots during the render (null: none)
    RunResult out_;
    std::optional<RenderScene> rs_;
    std::optional<CameraRays> camera_;
    std::optional<Executor> ex_;
    std::function<double()> clock_;
    std::vector<double> ambient_;  // av of D rays dropped at the end of passes
    std::array<std::vector<float>, kComponentCount> leftover_beta_;  // ambient_auto: per pixel RGB
    void add_auto_ambient();
    // Distributed rendering: rows (and the cache's records) exchanged with the other processes,
    // the work since the last exchange done in the bands of `bands_`; `ambient`: the stand-ins
    // that go with the film.
    void share_rows(RowExchange why, std::vector<double>& ambient) {
        if (bands_.empty()) return;
        SharedRows rows{out_.film, ambient, {}, bands_, why};
        for (auto& left : leftover_beta_) rows.throughput_left.push_back(&left);
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
    // Has any pixel an even and an odd sample (the two halves noise() compares)?
    bool two_samples_somewhere() const {
        for (uint32_t p = 0; p < out_.film.pixel_count(); ++p)
            if (out_.film.samples(p) >= 2) return true;
        return false;
    }
    std::vector<int> bands_;  // distributed rendering: the split of the stage running (row_bands.h)
    std::vector<double> preview_ambient_;  // the preview's stand-ins: for the D rays it carries
    // What the executed rays of component c found in pixels [p0, p1) (sample-summed RGB).
    Vec3 found_by(size_t c, size_t p0, size_t p1) const;
    // What an unexecuted ray of component c brings back per unit throughput: what its
    // executed rays did (`measured`), else `fallback`.
    Vec3 ambient_per_throughput(size_t c, const ExecutorStats& stats, const Vec3& fallback, bool& measured) const;
    std::array<RayBatch, kComponentCount> carried_;  // the preview's rays waiting for the selective crex
    // With a report: the image and sample counts when the running pass began (see snapshot()).
    std::vector<float> pass_start_image_;
    std::vector<uint32_t> pass_start_samples_;
    std::optional<IrradianceCache> cache_;
    std::vector<IcAnswer> preview_answers_;
    uint32_t preview_shadow_rays_ = 1;  ///< the base quality the preview's hits were shaded at
    std::optional<PixelProbe> surfaces_;      // capict: what each pixel centre sees
    std::vector<float> replay_start_image_;   // capict, reports: the image before the refinement round running
    std::vector<uint8_t> first_bounce_runs_;  // capict: the executor's gate (bit c: c's first bounces run)
    double base_aa_ = 0;
    double seconds_per_sample_ = 0;  // measured under a budget: camera sample and its rays
    bool last_stage_ = false;  // the render's last camera samples: not traced in RunSettings::final_rows
    ExecutorOptions::TaskAdmission policy_admission_ = ExecutorOptions::TaskAdmission::kWhole;  // the policy's
    // Progress within the running stage.
    RunProgress progress_;
    uint64_t stage_samples_ = 0, stage_samples_done_ = 0;
    Clock::time_point stage_start_ = Clock::now();
};

size_t PlanRun::pass_bytes(size_t held_bytes) const {
    // A model, not a measurement of the process, so that the passes (and so the order of the
    // film's sums) are the same on every run: what the process holds (scene, film, carried
    // rays) and what is still to come (guidance's buffers, the output images).
    size_t used = fixed_bytes(out_.film.pixel_count(), out_.film.tracked_branches(), out_.staged && out_.preview.empty()) + held_bytes;
    for (const auto& g : rs_->embree->geometries()) used += g.indices.size() * kBytesPerTriangle;
    if (rs_->textures) used += texture_cache_bytes(s_.max_memory);
    // At least one row of samples, whatever the limit says: a pass cannot be smaller.
    size_t row = static_cast<size_t>(s_.width) * kBytesPerSample;
    return s_.max_memory > used + row ? s_.max_memory - used : row;
}

void PlanRun::report_progress(const std::string& step) {
    progress_.step = step;
    progress_.stage_seconds = seconds_since(stage_start_);
    progress_.fraction = stage_samples_ ? double(stage_samples_done_) / double(stage_samples_) : 0;
    progress_.rays = ex_ ? ex_->rays_done() : 0;
    observer_.progress(progress_);
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
                RayRecord r = camera_ray(*camera_, s_.seed, s_.width, static_cast<uint32_t>(p), first_of(p) + k, s_.filter);
                rays.write(at[p - p0] + k, &r, 1);
            }
        }
    });
    CREX_CHECK(rays.size() == pass.samples);
    ex_->run_camera_rays(rays);
}

void PlanRun::flush_bins() {
    for (size_t c = 0; c < kComponentCount; ++c) {
        RayBatch& bin = ex_->bins()[c];
        if (s_.ambient_auto && !bin.empty()) {
            std::vector<float>& left = leftover_beta_[c];
            if (left.empty()) left.assign(3 * out_.film.pixel_count(), 0.0f);
            for (size_t i = 0; i < bin.size(); ++i) {
                float* l = &left[3 * static_cast<size_t>(bin.pixel[i])];
                l[0] += bin.br[i], l[1] += bin.bg[i], l[2] += bin.bb[i];
            }
        } else if (c == static_cast<size_t>(Component::kD)) {
            add_ambient(bin, s_.ambient, ambient_);
        }
        out_.rays_left[c] += bin.size();
        bin = RayBatch();  // freed: bins kept at their largest would add up over passes
    }
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
    std::vector<double> ambient = ambient_;
    if (s_.ambient_auto) {
        // The image if the render stopped here: rays still waiting (this pass's, the preview's
        // carried ones, those dropped at earlier passes' ends) stand in with what their
        // component's rays brought back so far, as at the end of a render. Without this a
        // checkpoint inside a pass counted its new samples with only their camera light and
        // the error curve rose through every pass (issue 17).
        for (size_t c = 0; c < kComponentCount; ++c) {
            bool measured = false;
            Vec3 av = ambient_per_throughput(c, ex_->stats(), Vec3{}, measured);
            if (!measured) continue;
            add_ambient(ex_->bins()[c], av, ambient);
            add_ambient(carried_[c], av, ambient);
            add_stand_in(leftover_beta_[c], av, ambient);
        }
    } else {
        add_ambient(ex_->bins()[static_cast<size_t>(Component::kD)], s_.ambient, ambient);
        add_ambient(carried_[static_cast<size_t>(Component::kD)], s_.ambient, ambient);
    }
    out_.component_subsample.add_stand_ins(out_.film, ambient);
    std::vector<float> rgb = out_.film.composite(&ambient);
    if (out_.subsample) out_.subsample->fill(rgb);
    return rgb;
}

Vec3 PlanRun::found_by(size_t c, size_t p0, size_t p1) const {
    const Film& film = out_.film;
    const size_t aov = aov_of(static_cast<Component>(c));
    double found[3] = {0, 0, 0};
    for (size_t p = p0; p < p1; ++p) {
        Vec3 v = film.pixel_value(aov, static_cast<uint32_t>(p)) * double(film.samples(static_cast<uint32_t>(p)));
        found[0] += v.x, found[1] += v.y, found[2] += v.z;
    }
    return {found[0], found[1], found[2]};
}

Vec3 PlanRun::ambient_per_throughput(size_t c, const ExecutorStats& stats, const Vec3& fallback, bool& measured) const {
    const double* beta = stats.components[c].beta;
    measured = beta[0] + beta[1] + beta[2] > 0;
    if (!measured) return fallback;
    return per_unit(found_by(c, 0, out_.film.pixel_count()), {beta[0], beta[1], beta[2]});
}

void PlanRun::add_auto_ambient() {
    const Film& film = out_.film;
    const size_t pixels = film.pixel_count();
    // Over this process's rows: distributed, each pixel is final in the band of the process
    // that rendered the last stage there, so the sums over every process's rows are those of
    // the whole image, and what every process's rays did stands in for every process's rays.
    const size_t p0 = static_cast<size_t>(first_row()) * static_cast<size_t>(s_.width);
    const size_t p1 = static_cast<size_t>(end_row()) * static_cast<size_t>(s_.width);
    // sums: the image's radiance summed (3), then per component what its executed rays found
    // (3) and their throughput (3).
    std::vector<double> sums(3 + 6 * kComponentCount, 0.0);
    {
        // Where no ray of a component ran, the mean radiance of the image stands in (RADIANCE's
        // usual choice of -av): the preview's for a pipeline, else the composite so far.
        std::vector<float> rgb = out_.preview.empty() ? film.composite(&ambient_) : out_.preview;
        for (size_t p = p0; p < p1; ++p)
            for (size_t k = 0; k < 3; ++k) sums[k] += std::isfinite(rgb[3 * p + k]) ? rgb[3 * p + k] : 0.0f;
    }
    for (size_t c = 0; c < kComponentCount; ++c) {
        const Vec3 found = found_by(c, p0, p1);
        const double* beta = out_.stats.components[c].beta;
        double* at = &sums[3 + 6 * c];
        at[0] = found.x, at[1] = found.y, at[2] = found.z, at[3] = beta[0], at[4] = beta[1], at[5] = beta[2];
    }
    if (!bands_.empty()) group_.sum(sums);
    const Vec3 mean = Vec3{sums[0], sums[1], sums[2]} / double(std::max<size_t>(pixels, 1));
    for (size_t c = 0; c < kComponentCount; ++c) {
        std::vector<float>& left = leftover_beta_[c];
        if (std::all_of(left.begin(), left.end(), [](float b) { return b == 0; })) {  // none left (distributed, all are kept)
            left = {};
            continue;
        }
        const double* at = &sums[3 + 6 * c];
        const bool measured = at[3] + at[4] + at[5] > 0;
        const Vec3 av = measured ? per_unit({at[0], at[1], at[2]}, {at[3], at[4], at[5]}) : mean;
        out_.auto_ambient[c] = av;
        add_stand_in(leftover_beta_[c], av, ambient_);
        out_.notes.push_back(fmt::format("unexecuted {} rays stood in with av = ({:.3g}, {:.3g}, {:.3g}), {}",
                                         kComponentTable[c].letter, av.x, av.y, av.z,
                                         measured ? "what its executed rays brought back per unit throughput"
                                                  : "the mean radiance of the image (none of its rays ran)"));
        leftover_beta_[c] = {};
    }
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
    PassLimits limits;
    size_t held = 0;
    for (const RayBatch& b : carried_) held += b.size() * kBytesPerSample / 2;
    limits.bytes = pass_bytes(held);
    limits.bytes_per_sample = kBytesPerSample;
    limits.max_samples = s_.pass_samples;
    // Under a budget, camera samples are scheduled work (issue 15): one sample index per pass,
    // each admitted on the cost per sample measured so far, the last one cut to the rows that
    // fit. The first sample of the render always runs: there is always an image.
    const bool budgeted = s_.executor.budget_seconds > 0;
    if (budgeted) limits.max_samples = 1;
    // The model's bytes per sample hold for scenes like the Cornell box; where lobe splitting
    // keeps many more rays in flight (the room's trans and glass: 2.9 GB under a 1 GiB limit)
    // the first pass is an eighth of the budget, and the rest is planned again on the rays it
    // actually held.
    const size_t full_bytes = limits.bytes;
    if (!budgeted && !s_.pass_samples) limits.bytes = std::max<size_t>(limits.bytes / 8, limits.bytes_per_sample);
    std::vector<SamplePass> passes = plan_sample_passes(s_.width, s_.height, ranges, limits);
    ex_->reset_peak_rays_held();
    for (const SamplePass& p : passes) CREX_CHECK(p.first < p.end && p.row_begin < p.row_end && p.samples > 0);
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
            if (budgeted && (out_.passes > 0 || pass.first > 0)) {
                auto fits = pass_within(pass, ranges, s_.width, seconds_per_sample_, s_.executor.budget_seconds - now());
                if (!fits) {
                    out_of_time = true;
                    break;
                }
                pass = *fits;
            }
            progress_.pass = i + 1;
            report_progress("camera rays");
            if (recorder_)
                recorder_->paused([&] {
                    pass_start_image_ = composite_now();
                    pass_start_samples_.resize(out_.film.pixel_count());
                    for (uint32_t p = 0; p < pass_start_samples_.size(); ++p) pass_start_samples_[p] = out_.film.samples(p);
                });
            const double t = now();
            // Progressive passes run their crex whole, except the render's first: it always
            // runs (an image in every pixel), so under a budget shorter than it its component
            // rays go in batches like cbtcr's (a 5 % budget overran by 15-65 %).
            const bool first_cut = budgeted && out_.passes == 0 && policy_admission_ == ExecutorOptions::TaskAdmission::kNone;
            if (first_cut) ex_->set_task_admission(ExecutorOptions::TaskAdmission::kBatches);
            trace_camera_rays(pass, ranges);
            after_camera_rays();
            if (first_cut) ex_->set_task_admission(policy_admission_);
            pass_start_image_.clear();
            // What a camera sample and all its rays cost, smoothed over passes (the thesis's
            // continuous profiling): the next pass or band is admitted on it.
            const double measured = (now() - t) / static_cast<double>(pass.samples);
            seconds_per_sample_ = seconds_per_sample_ > 0 ? 0.5 * seconds_per_sample_ + 0.5 * measured : measured;
            stage_samples_done_ += pass.samples;
            ++out_.passes;
            row = pass.row_end;
        }
        if (i == 0 && !budgeted && !s_.pass_samples && passes.size() > 1 && passes[0].row_begin == 0 && passes[0].row_end == s_.height) {
            // Plan the rest on what the first pass held: its samples' rays in flight.
            const size_t measured = ex_->peak_rays_held() * kBytesPerHeldRay / std::max<uint64_t>(1, passes[0].samples);
            limits.bytes_per_sample = std::max(limits.bytes_per_sample, measured);
            limits.bytes = full_bytes;
            SampleRanges rest = ranges;
            if (rest.start_of.empty() && rest.end_of.empty()) {
                rest.first = std::max(rest.first, passes[0].end);
            } else {
                rest.start_of.resize(out_.film.pixel_count());
                rest.end_of.resize(out_.film.pixel_count());
                for (size_t p = 0; p < rest.start_of.size(); ++p) {
                    rest.start_of[p] = std::max(ranges.start(p), passes[0].end);
                    rest.end_of[p] = ranges.stop(p);
                }
            }
            std::vector<SamplePass> later = plan_sample_passes(s_.width, s_.height, rest, limits);
            passes.resize(1);
            passes.insert(passes.end(), later.begin(), later.end());
            progress_.passes = passes.size();
            out_.bytes_per_sample = limits.bytes_per_sample;
        }
    }
    if (out_of_time) out_.budget_stopped_samples += stage_samples_ - stage_samples_done_;
    report_progress("");
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
    if (worked_since_exchange) share_with_other_processes(RowExchange::kNewBands, ambient_);
    bands_ = std::move(split);
}

void PlanRun::setup_cache() {
    IcSettings ics = plan_cache_settings(plan_, *s_.irradiance_cache);
    base_aa_ = ics.accuracy;
    cache_.emplace(*rs_, ics);
    cache_->set_progress([this](const IcStats& st) {
        report_progress(fmt::format("D: irradiance cache, {} records, {:.1f} M hemisphere rays", st.records, st.hemisphere_rays / 1e6));
    });
    for (const auto& r : s_.ic_records) cache_->insert(r);
    if (s_.ic_file_bytes || (!s_.ic_file.empty() && std::filesystem::exists(s_.ic_file))) {
        size_t before = cache_->records().size();
        // Records are validated against the scene's extent either way.
        std::string error = s_.ic_file_bytes ? cache_->load_bytes(*s_.ic_file_bytes, s_.ic_file) : cache_->load(s_.ic_file);
        if (!error.empty()) throw RunInputError("irradiance cache: " + error);
        out_.ic_loaded = cache_->records().size() - before;
    }
}

void PlanRun::save_cache() {
    out_.ic_records = cache_->records();
    out_.ic_stats = cache_->stats();
    if (s_.ic_file.empty() || !group_.saves_cache_file()) return;
    std::string error = cache_->save(s_.ic_file);
    if (!error.empty()) throw std::runtime_error("cannot save the irradiance cache: " + error);
}

SelectiveSetup PlanRun::guidance(bool from_current_image) {
    const int w = s_.width, h = s_.height;
    const size_t pixels = out_.film.pixel_count();
    const Film& film = out_.film;
    const uint32_t s0 = s_.spp;
    SelectiveSetup sel;
    sel.shade = s_.executor.shade;
    // With a cache, D hits stay irradiance queries in the selective stage too. (They did not:
    // every selective D sample was path traced, so a cached pipeline's gold had the fireflies
    // of uniform path tracing at twice the cost; Cornell 128x128 prog_dis_all --uniform max,
    // FLIP 0.122 against 0.080 for crex run --ic with the same settings.)
    sel.shade.ic_queries = cache_.has_value();
    sel.spp_end.assign(pixels, s0);
    if (plan_.settings.selective_spp) std::fill(sel.spp_end.begin(), sel.spp_end.end(), std::max(s0, *plan_.settings.selective_spp));

    // The maps: computed by the guidance graph, or constant under --uniform.
    std::optional<GuidanceGraph> graph;
    std::optional<guidance::Raster> constant;
    if (s_.uniform != UniformQuality::kOff) {
        guidance::Raster r;
        r.width = w, r.height = h, r.channels = 1;
        r.v.assign(pixels, s_.uniform == UniformQuality::kMax ? 1.0f : 0.0f);
        constant = std::move(r);
    } else {
        // The stand-ins of the image the maps see: the preview's (its carried D rays', shared
        // with its rows), or, in a later round, once the carried rays have run, the film's own.
        const std::vector<double>& preview_ambient = from_current_image ? ambient_ : preview_ambient_;
        GuidanceInputs in;
        in.width = w, in.height = h;
        in.preview = from_current_image ? film.composite(&preview_ambient) : out_.preview;
        in.scene = &scene_;
        // Only the buffers the plan reads: at 1920x1080 all ten took 250 MB.
        std::set<std::string> read;
        for (const PlanBuffer& b : plan_.buffers) read.insert(b.buffer);
        for (const PlanMap& m : plan_.maps)
            if (m.op == pipeline::GuidanceOperator::kNoise) read.insert("noise");
        if (read.count("noise")) in.buffers["noise"] = film.noise_image();
        if (read.count("direct") || read.count("emission")) {
            std::vector<float> camera_aov = film.aov_image(kCameraAov), emission = film.emission_image();
            for (size_t i = 0; i < camera_aov.size(); ++i) camera_aov[i] = std::max(0.0f, camera_aov[i] - emission[i]);
            if (read.count("direct")) in.buffers["direct"] = std::move(camera_aov);
            if (read.count("emission")) in.buffers["emission"] = std::move(emission);
        }
        if (read.count("ambient")) {
            std::vector<float> a(3 * pixels, 0.0f);
            for (uint32_t p = 0; p < pixels; ++p)
                for (size_t c = 0; c < 3; ++c)
                    a[3 * p + c] = film.samples(p) ? static_cast<float>(preview_ambient[3 * p + c] / film.samples(p)) : 0.0f;
            in.buffers["ambient"] = std::move(a);
        }
        for (size_t c = 0; c < kComponentCount; ++c) {
            std::string letter(1, kComponentTable[c].letter);
            if (read.count(letter)) in.buffers[letter] = film.aov_image(aov_of(static_cast<Component>(c)));
        }
        PixelProbe probe;
        if (needs_probe(plan_)) {
            probe = probe_pixels(*rs_, w, h);
            in.probe = &probe;
        }
        graph.emplace(plan_, std::move(in));
        out_.maps.clear();  // a later round's maps replace the earlier ones
        for (const PlanMap& m : plan_.maps)
            if (!m.defines.empty()) {
                const guidance::Raster& r = graph->map(m.id);
                out_.maps.push_back({m.defines, r});
                if (std::all_of(r.v.begin(), r.v.end(), [](float v) { return !(v > 0); }))
                    out_.notes.push_back(fmt::format("map '{}' is 0 everywhere: what it drives stays at its base value{}", m.name,
                                                     m.op == pipeline::GuidanceOperator::kNoise && !two_samples_somewhere()
                                                         ? " (noise() compares a pixel's even and odd samples, and no pixel has two "
                                                           "yet: a budget cut the preview, or its spp is 1)"
                                                         : ""));
            }
    }
    auto map_of = [&](const std::string& id) -> const guidance::Raster& {
        if (constant) return *constant;
        const guidance::Raster& r = graph->map(id);
        if (id.rfind("map.", 0) != 0) {  // an inline map (`by edges(direct)`): shown as the user wrote it
            std::string shown = id;
            for (const PlanMap& m : plan_.maps)
                if (m.id == id && !m.name.empty()) shown = m.name;
            bool seen = false;
            for (const auto& [name, raster] : out_.maps) seen |= name == shown;
            if (!seen) out_.maps.push_back({shown, r});
        }
        return r;
    };

    for (const PlanVariable& var : plan_.variables) {
        std::vector<float> m = map_values(map_of(var.map), pixels);
        // One case per pipeline::SelectiveVariable, no default (-Werror=switch): a variable the
        // compiler knows and the runtime does not bind does not compile.
        using V = pipeline::SelectiveVariable;
        switch (var.variable) {
        case V::kSpp: {
            auto v = variable_values(var.from, var.to, var.modulation, m, true);
            for (size_t p = 0; p < pixels; ++p) sel.spp_end[p] = static_cast<uint32_t>(std::clamp(v[p], 1.0, double(1u << 20)));
            break;
        }
        case V::kShadowRays: {
            sel.shade.shadow_rays = per_pixel_counts(variable_values(var.from, var.to, var.modulation, m, true), sel.shadow_rays);
            break;
        }
        case V::kSpecularThreshold: {
            auto v = variable_values(var.from, var.to, var.modulation, m, false);
            sel.specular_threshold.assign(v.begin(), v.end());
            break;
        }
        case V::kSubsample:
            if (!var.component) {
                out_.subsample.emplace(w, h, variable_values(var.from, var.to, var.modulation, m, true));
                break;
            }
            if (!surfaces_) {  // capict: which corners see a pixel's surface, probed once
                surfaces_ = probe_pixels(*rs_, w, h);
                out_.component_subsample.set_surfaces(*surfaces_);
            }
            out_.component_subsample.build(*var.component, w, h, variable_values(var.from, var.to, var.modulation, m, true), film);
            break;
        case V::kIcRadius: {
            if (!cache_) {
                out_.notes.push_back("ic_radius is not executed: the render has no irradiance cache");
                break;
            }
            auto v = variable_values(var.from, var.to, var.modulation, m, false);
            sel.ic_accuracy.assign(v.begin(), v.end());
            sel.ic_priority = m;
            break;
        }
        case V::kMediaSamples: {
            if (!rs_->medium) {
                out_.notes.push_back("media_samples is not executed: the scene has no participating medium");
                break;
            }
            sel.shade.media_samples = per_pixel_counts(variable_values(var.from, var.to, var.modulation, m, true), sel.media_samples);
            break;
        }
        }
    }
    if (!plan_.modulation_map.empty()) sel.modulation = map_values(map_of(plan_.modulation_map), pixels);
    if (out_.subsample)
        for (size_t p = 0; p < pixels; ++p)
            if (!out_.subsample->rendered(static_cast<uint32_t>(p))) sel.spp_end[p] = 0;
    return sel;
}

void PlanRun::reanswer_preview_queries(const SelectiveSetup& sel) {
    // The preview's D samples of pixels that now ask for a finer accuracy are answered again,
    // important pixels first; the old answer's light is taken back out of the film.
    if (sel.ic_accuracy.empty()) return;
    std::vector<IcQuery> again;
    std::vector<const IcAnswer*> from;
    for (const auto& a : preview_answers_) {
        uint32_t p = a.query.pixel;
        if (!(sel.ic_accuracy[p] < a.accuracy - 1e-9)) continue;
        again.push_back({a.query.origin, normalize_or_zero(a.query.direction), sel.ic_accuracy[p], sel.ic_priority[p], a.query.path});
        from.push_back(&a);
    }
    // Under a budget, in batches of the most important pixels first, while time is left: a
    // sample not answered again keeps its coarser (valid) answer. (Answered in one go, the new
    // records of prog_tc's fine pixels took a 0.96 s budget to 1.46 s on the Cornell box.)
    std::vector<size_t> order(again.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return again[a].priority > again[b].priority; });
    const bool budgeted = s_.executor.budget_seconds > 0;
    // Batches start small and double, each predicted from the one before (its time per query):
    // the first answers make most of the new records, so their cost is unknown until measured.
    size_t batch = budgeted ? 64 : std::max<size_t>(1, again.size());
    size_t done = 0;
    double per_query = 0;
    while (done < order.size() &&
           !(budgeted && now() + per_query * static_cast<double>(std::min(batch, order.size() - done)) > s_.executor.budget_seconds)) {
        const double t = now();
        const size_t end = std::min(order.size(), done + batch);
        std::vector<IcQuery> part;
        for (size_t k = done; k < end; ++k) part.push_back(again[order[k]]);
        std::vector<Vec3> e;
        answer_queries()(part, e);
        for (size_t k = done; k < end; ++k) {
            const IcAnswer& a = *from[order[k]];
            Vec3 delta = a.query.beta * (e[k - done] - a.irradiance) / kPi;
            if (is_finite(delta)) out_.film.add(aov_of(Component::kD), a.query.pixel, delta, a.query.flags);
        }
        per_query = (now() - t) / static_cast<double>(end - done);
        done = end;
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
    if (s_.executor.budget_seconds > 0 && now() >= s_.executor.budget_seconds) return;  // the budget is spent
    // Distributed: in the preview's bands, as the rest of round 1's work on the preview's samples.
    const size_t w = static_cast<size_t>(s_.width);
    const size_t p0 = static_cast<size_t>(first_row()) * w, p1 = static_cast<size_t>(end_row()) * w;
    RayBatch rays;
    for (size_t p = p0; p < p1; ++p) {
        if (sel.shadow_rays[p] <= preview_shadow_rays_) continue;
        const uint32_t kept = std::min(s_.spp, out_.film.samples(static_cast<uint32_t>(p)));
        append_camera_rays(*camera_, s_.seed, s_.width, static_cast<uint32_t>(p), 0, kept, rays, s_.filter);
    }
    if (rays.empty()) return;
    std::vector<Vec3> delta;
    out_.direct_light_redone_shadow_rays += redo_camera_direct_light(*rs_, rays, preview_shadow_rays_, sel.shadow_rays, delta);
    for (size_t i = 0; i < rays.size(); ++i)
        if (is_finite(delta[i])) out_.film.add(kCameraAov, rays.pixel[i], delta[i], rays.flags[i]);
    out_.direct_light_redone += rays.size();
}

void PlanRun::refine_components(const sched::Program& program) {
    // capict's recursion (thesis 7.2): squares whose corners' light differs by more than the
    // component's threshold split, and the new corners render the branch they skipped, by
    // tracing their selective samples again with everything but that branch not counted.
    // Each split halves a square, so a spacing of 2^k ends within k rounds.
    const size_t pixels = out_.film.pixel_count();
    for (int round = 0; round < 11; ++round) {
        std::vector<float> before;
        if (recorder_) recorder_->paused([&] { before = composite_now(); });
        std::vector<uint8_t> runs(pixels, 0);
        uint8_t replay = 0;
        for (const PlanVariable& v : plan_.variables) {
            if (v.variable != pipeline::SelectiveVariable::kSubsample || !v.component || !v.refine) continue;
            std::vector<uint8_t> added = out_.component_subsample.refine(*v.component, *v.refine, out_.film);
            if (added.empty()) continue;
            const unsigned bit = 1u << static_cast<unsigned>(*v.component);
            replay = static_cast<uint8_t>(replay | bit);
            for (size_t p = 0; p < pixels; ++p)
                if (added[p]) runs[p] = static_cast<uint8_t>(runs[p] | bit);
        }
        if (!replay) return;
        SampleRanges ranges;
        ranges.start_of.assign(pixels, 0);
        ranges.end_of.assign(pixels, 0);
        for (size_t p = 0; p < pixels; ++p)
            if (runs[p]) ranges.start_of[p] = s_.spp, ranges.end_of[p] = out_.film.samples(static_cast<uint32_t>(p));
        replay_start_image_ = std::move(before);
        first_bounce_runs_ = std::move(runs);
        ex_->set_first_bounce_runs(&first_bounce_runs_);
        ex_->set_replay_branches(replay);
        run_samples(fmt::format("refinement {}", round + 1), ranges, [&] {
            ex_->run_stage(program.preselective);
            ex_->run_stage(program.selective);
            flush_bins();
        });
        ex_->set_replay_branches(0);
        replay_start_image_.clear();
        ++out_.refinements;
    }
}

RunResult PlanRun::execute() {
    auto t_setup = Clock::now();
    // One texture cache for the render, its share of --max-memory (pass_bytes() counts it).
    rs_.emplace(scene_, texture_cache_bytes(s_.max_memory));
    rs_->set_view(s_.width, s_.height, s_.texture_filter_width);
    for (const auto& w : rs_->warnings) out_.warnings.push_back(w);
    out_.setup_seconds = seconds_since(t_setup);
    const double cpu_at_start = process_cpu_seconds();
    const size_t pixels = out_.film.pixel_count();
    ambient_.assign(3 * pixels, 0.0);
    // A pipeline runs in stages (its preview is kept and shown); a bare crex runs each pass
    // through both programs.
    out_.staged = plan_.staged;
    if (out_.staged && !s_.windows.empty())  // guidance reads the whole preview: a window has no meaning there
        throw RunInputError("only a plain crex renders windows of the frame, not a pipeline");
    if (s_.uniform != UniformQuality::kOff && !has_guidance(plan_))
        out_.notes.push_back("--uniform has no effect: the plan varies nothing");
    // What no pass size can shrink is over the limit: say so, rather than let the limit look kept.
    if (const size_t fixed = fixed_bytes(pixels, subsampled_components(plan_), out_.staged); fixed > s_.max_memory)
        out_.notes.push_back(fmt::format("the render's film, buffers and images alone hold {:.0f} MiB, more than --max-memory "
                                         "{:.0f} MiB: its passes go one row at a time, and the process holds more than that limit",
                                         static_cast<double>(fixed) / (1 << 20), static_cast<double>(s_.max_memory) / (1 << 20)));

    // One clock from the first camera ray for every stage (spec §7); reports pause it while
    // they copy snapshots.
    const auto t0 = Clock::now();
    CheckpointRecorder* rec = recorder_;
    ExecutorOptions eo = s_.executor;
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
    if (rec) {
        rec->start();
        clock_ = [rec] { return rec->now(); };
    } else if (eo.clock) {
        clock_ = eo.clock;
    } else {
        clock_ = [t0] { return seconds_since(t0); };
    }
    eo.clock = clock_;
    if (rec) eo.checkpoint = [this, rec](const std::string& what, bool boundary) {
        rec->event(what, boundary, ex_->rays_done(), [this] { return snapshot(); });
    };
    eo.progress = [this](const std::string& what, uint64_t rays) {
        if (s_.executor.progress) s_.executor.progress(what, rays);
        report_progress(what);
    };
    if (s_.irradiance_cache) {
        setup_cache();
        eo.shade.ic_queries = true;
        eo.irradiance = executor_hook(answer_queries(), base_aa_, nullptr, out_.staged ? nullptr : s_.executor.importance,
                                      out_.staged ? &preview_answers_ : nullptr);
    }
    {
        // capict: the branches of the components sub-sampled are tracked from the first
        // camera ray, so the preview's samples count in the interpolation too.
        if (const uint8_t branches = subsampled_components(plan_)) out_.film.track_branches(branches);
    }
    ex_.emplace(*rs_, out_.film, eo);
    policy_admission_ = eo.task_admission;
    camera_.emplace(scene_.camera, s_.width, s_.height, rs_->embree->origin_offset());
    const sched::Program& program = plan_.program;
    // Distributed: nothing is known of the first stage's cost yet. With --ambient auto every
    // process keeps every component's throughput left unexecuted, so that their rows are
    // shared alike (a pixel's may have been left by the process whose band held it before).
    if (group_.bands() > 0) {
        bands_ = equal_row_bands(s_.height, group_.bands());
        if (s_.ambient_auto)
            for (auto& left : leftover_beta_) left.assign(3 * pixels, 0.0f);
    }

    if (!out_.staged) {
        // A plain crex (or a pipeline that varies nothing): each pass runs both programs.
        last_stage_ = true;
        const SampleRanges every_pixel{s_.first_sample, s_.first_sample + s_.spp, {}, {}};
        run_samples("render", s_.windows.empty() ? every_pixel : only_windows(every_pixel, s_.width, s_.height, s_.windows), [&] {
            if (rec) rec->set_stage("preselective");
            ex_->run_stage(program.preselective);
            if (rec) {
                rec->event("end of the pre-selective crex", true, ex_->rays_done(), [this] { return snapshot(); }, true);
                rec->set_stage("selective");
            }
            ex_->run_stage(program.selective);
            flush_bins();
        });
        if (rec) {
            rec->set_stage("end");
            rec->event("end of render", true, ex_->rays_done(), [this] { return snapshot(); }, true);
        }
    } else {
        // 1. Pre-selective: the rays each pass leaves waiting are carried to the selective stage.
        run_samples("pre-selective", {0, s_.spp, {}, {}}, [&] {
            ex_->run_stage(program.preselective);
            for (size_t c = 0; c < kComponentCount; ++c) {
                RayBatch& bin = ex_->bins()[c];
                carried_[c].append(bin, 0, bin.size());
                bin.clear();
            }
        });
        {
            // The preview's image: the rays it carries to the selective stage stand in as av
            // (D's) until they run. The stand-ins are shared with the film's rows, so that
            // guidance sees the same preview on every process (ambient_ is still zero: the
            // preview drops no ray, it carries them).
            CREX_CHECK(std::all_of(ambient_.begin(), ambient_.end(), [](double a) { return a == 0; }));
            preview_ambient_ = ambient_;
            add_ambient(carried_[static_cast<size_t>(Component::kD)], s_.ambient, preview_ambient_);
            share_with_other_processes(RowExchange::kPreview, preview_ambient_);
            out_.preview = out_.film.composite(&preview_ambient_);
        }
        out_.preview_seconds = seconds_since(t0);
        out_.preview_rays = total_rays(ex_->stats());
        if (cache_) out_.ic_preview_records = cache_->records().size();
        stage_end("end of the pre-selective stage", "guidance");

        // 2-3. Guidance and selective rendering, `rounds` times (the cyclic process, spec §1):
        // each round computes the maps on the image so far and takes the samples its svt asks
        // for by then (a share r / rounds of the way from the preview's spp to the target)
        // beyond what each pixel has; the first round also runs the preview's waiting rays.
        const uint32_t rounds = std::max<uint32_t>(1, s_.rounds ? s_.rounds : plan_rounds(plan_));
        const std::vector<float>* base_importance = s_.executor.importance;
        double selective_seconds = 0;
        for (uint32_t round = 1; round <= rounds; ++round) {
            const std::string label = rounds > 1 ? fmt::format(" (round {}/{})", round, rounds) : "";
            auto t_guidance = Clock::now();
            progress_ = {};
            progress_.stage = "guidance" + label;
            report_progress("maps");
            if (round > 1) share_with_other_processes(RowExchange::kRound, ambient_);  // the maps see every row as it is now
            SelectiveSetup sel = guidance(round > 1);
            if (round == 1) preview_ambient_ = {};  // the maps have seen the preview
            out_.guidance_seconds += seconds_since(t_guidance);
            stage_end("end of guidance" + label, "selective");

            auto t_selective = Clock::now();
            ShadeParams shade = sel.shade;
            if (!sel.shadow_rays.empty()) shade.shadow_rays_per_pixel = &sel.shadow_rays;
            if (!sel.media_samples.empty()) shade.media_samples_per_pixel = &sel.media_samples;
            if (!sel.specular_threshold.empty()) shade.specular_threshold_per_pixel = &sel.specular_threshold;
            ex_->set_shade_params(shade);
            if (round == 1) redo_preview_direct_light(sel);
            if (cache_) {
                if (round == 1) reanswer_preview_queries(sel);
                ex_->set_irradiance(executor_hook(answer_queries(), base_aa_, sel.ic_accuracy.empty() ? nullptr : &sel.ic_accuracy,
                                                  sel.ic_priority.empty() ? nullptr : &sel.ic_priority));
            }
            if (out_.component_subsample.any()) {  // capict: this round's grids gate the new samples' first bounces
                first_bounce_runs_ = out_.component_subsample.first_bounce_runs(pixels);
                ex_->set_first_bounce_runs(&first_bounce_runs_);
            }
            const std::vector<float>* modulation = sel.modulation.empty() ? base_importance : &sel.modulation;
            auto run_selective = [&] {
                ex_->set_importance(modulation);
                ex_->run_stage(program.selective);
                ex_->set_importance(base_importance);
                flush_bins();
            };
            if (round == 1) {  // the preview's waiting rays first
                for (size_t c = 0; c < kComponentCount; ++c) std::swap(ex_->bins()[c], carried_[c]);
                run_selective();
                for (RayBatch& b : carried_) b = RayBatch();
            }
            SampleRanges ranges;
            ranges.start_of.resize(pixels);
            ranges.end_of.resize(pixels);
            for (size_t p = 0; p < pixels; ++p) {
                ranges.start_of[p] = out_.film.samples(static_cast<uint32_t>(p));
                double target = sel.spp_end[p] <= s_.spp ? 0 : s_.spp + double(sel.spp_end[p] - s_.spp) * round / rounds;
                ranges.end_of[p] = static_cast<uint32_t>(std::ceil(target - 1e-9));
            }
            last_stage_ = round == rounds;
            // Distributed: bands of about the same camera samples for this round. In round 1 the
            // work on the preview's samples above (carried rays, direct light redone, queries
            // answered again) was done in the preview's bands.
            balance_bands(ranges, round == 1);
            run_samples("selective" + label, ranges, [&] {
                ex_->run_stage(program.preselective);
                run_selective();
            });
            last_stage_ = false;
            selective_seconds += seconds_since(t_selective);
            if (round < rounds) stage_end("end of selective rendering" + label, "guidance");
        }
        if (out_.component_subsample.any() && s_.executor.budget_seconds <= 0) refine_components(program);
        out_.selective_seconds = selective_seconds;
        if (cache_) out_.ic_selective_records = cache_->records().size() - out_.ic_preview_records;
        out_.selective_rays = total_rays(ex_->stats()) - out_.preview_rays;
        stage_end("end of render", "end");
    }

    out_.stats = ex_->stats();
    if (s_.ambient_auto) add_auto_ambient();
    // Distributed: capict's refinement above kept the last round's bands (no exchange since).
    share_rows(RowExchange::kEnd, ambient_);
    out_.row_bands = bands_;
    out_.ambient = std::move(ambient_);
    if (!bands_.empty()) group_.final_image(out_.image(), s_.width);
    // Passes repeat a step's warning (a '*' cap hit in every pass): each is said once.
    std::set<std::string> said;
    for (const auto& w : ex_->warnings())
        if (said.insert(w).second) out_.warnings.push_back(w);
    out_.render_seconds = clock_();
    out_.render_cpu_seconds = process_cpu_seconds() - cpu_at_start;
    out_.render_thread_seconds = out_.render_seconds * tbb::this_task_arena::max_concurrency();
    if (rs_->textures) out_.textures = rs_->textures->stats();
    if (cache_) save_cache();
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

}  // namespace

IcSettings plan_cache_settings(const PipelinePlan& plan, IcSettings ics) {
    for (const PlanVariable& v : plan.variables)
        if (v.variable == pipeline::SelectiveVariable::kIcRadius) {
            // The preview uses the accuracy where the map is 0 (spec: `from`); the selective stage refines.
            ics.accuracy = v.from;
            ics.max_accuracy = std::max({v.from, v.to, ics.accuracy});
        }
    return ics;
}

uint32_t plan_rounds(const PipelinePlan& plan) { return plan.settings.rounds.value_or(1); }

bool has_guidance(const PipelinePlan& plan) { return !plan.maps.empty() || !plan.variables.empty(); }

uint64_t total_rays(const ExecutorStats& stats) {
    uint64_t n = stats.camera.rays;
    for (const auto& c : stats.components) n += c.rays;
    return n;
}

std::vector<float> RunResult::image() const {
    std::vector<double> stand_in = ambient;
    component_subsample.add_stand_ins(film, stand_in);
    std::vector<float> rgb = film.composite(&stand_in);
    if (subsample) subsample->fill(rgb);
    return rgb;
}

std::vector<float> RunResult::aov_image(size_t aov) const {
    std::vector<float> rgb = film.aov_image(aov);
    // capict: a component's image takes its branch's interpolation (the whole branch, also what
    // it found through other components' rays below the first bounce), so the images still add
    // up to the final image.
    if (aov != kCameraAov && component_subsample.grid(static_cast<Component>(aov - 1))) {
        std::vector<double> delta = component_subsample.stand_ins(film, static_cast<Component>(aov - 1));
        for (uint32_t p = 0; p < film.pixel_count(); ++p)
            if (const double n = film.samples(p); n > 0)
                for (size_t k = 0; k < 3; ++k) {
                    const float v = static_cast<float>(rgb[3 * p + k] + delta[3 * p + k] / n);
                    rgb[3 * p + k] = std::isfinite(v) ? v : 0.0f;
                }
    }
    if (subsample) subsample->fill(rgb);
    return rgb;
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
