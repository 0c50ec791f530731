#include "runtime/distributed/mpi_group.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <iostream>

#include "base/check.h"
#include "base/exit_codes.h"
#include "runtime/base/atomic_file.h"
#include "runtime/distributed/ic_share_central.h"
#include "runtime/distributed/ic_share_component.h"
#include "runtime/distributed/partial_rows.h"
#include "runtime/distributed/rank_watchdog.h"
#include "runtime/driver/run_plan.h"
#include "runtime/render/render_scene.h"
#include "runtime/texture/surface_textures.h"

namespace crex::distributed {

struct MpiGroup::Modes {
    IcShare ic_share = IcShare::kNone;  // what is in effect: none without a cache
    ComponentRoles roles;
    std::string ic_file;  // the cache file under component: the first PA sends its records, rank 0 saves
    std::optional<std::vector<Checkpoint>> exchanges;  // rank 0 with a report: the checkpoint of each exchange
    bool exchange_images = false;                      // ... with its image (a reference scores them)
    std::chrono::steady_clock::time_point start;
    bool band_final = true;  // rank 0's own band of the last stage is final before the last exchange
    std::unique_ptr<IrradianceClient> client;  // a PR of component
    std::unique_ptr<CentralShare> central;
    size_t broadcast_shared = 0;  // broadcast: records this rank made and sent already
};

MpiGroup::MpiGroup(const DistributedOptions& options)
    : options_(options), ranks_(distribution()), modes_(std::make_unique<Modes>()) {
    set_rank_timeout(options.rank_timeout);  // bounds the wait for rank 0's inputs too
}
MpiGroup::~MpiGroup() = default;

namespace {

bool interpolates_across_rows(const PipelinePlan& plan) {
    return std::any_of(plan.variables.begin(), plan.variables.end(),
                       [](const PlanVariable& v) { return v.variable == pipeline::SelectiveVariable::kSubsample; });
}

const char* name_of(IcShare mode) {
    switch (mode) {
    case IcShare::kNone: return "none";
    case IcShare::kCentral: return "central";
    case IcShare::kBroadcast: return "broadcast";
    case IcShare::kComponent: return "component";
    }
    return "none";
}

}  // namespace

std::string MpiGroup::share_from_lead(std::string bytes, const std::string& what) { return share_from_rank0(std::move(bytes), what); }

void MpiGroup::keep_partial_outputs(const std::vector<std::string>& outputs, int width, int height, const ImageMetadata& identity) {
    // From here a fault writes the rows rank 0 finished beside each output (partial_rows.h).
    if (ranks_.rank == 0) arm_partial_outputs(outputs, width, height, identity);
}

void MpiGroup::begin(const PipelinePlan& plan, RunSettings& s, const CheckpointRecorder* exchanges_for) {
    // The modes below start with blocking collectives (communicators): a rank stuck setting
    // up is named here instead of blocking them.
    all_ranks_arrive("the start of the render (inputs read and checked)");
    // Sharing a cache means something only with one: without, every rank renders rows.
    if (s.irradiance_cache) modes_->ic_share = options_.ic_share;
    if (modes_->ic_share == IcShare::kComponent) {
        modes_->roles = component_roles(ranks_.size, ranks_.rank);
        ranks_ = render_rows_on_first(modes_->roles.pr_count);
        start_component_protocol(modes_->roles);
        if (!modes_->roles.answers) {
            modes_->client = std::make_unique<IrradianceClient>(modes_->roles.pa);
            // The PA loads the records (the bytes rank 0 read) and holds them; this rank's own
            // cache stays empty. Rank 0 saves the first PA's, on its own machine (end()).
            if (ranks_.rank == 0) modes_->ic_file = s.ic_file;
            // Nor does it answer a query: no caustic map to build (8 ranks built 8 maps, 6 of
            // them unused, and starved a neighbouring test's rank of its 1 s to start).
            s.irradiance_cache->caustic_photons = 0;
            s.ic_file.clear();
            s.ic_file_bytes.reset();
            s.ic_records.clear();
        }
    } else if (modes_->ic_share == IcShare::kCentral) {
        modes_->central = std::make_unique<CentralShare>();
    }
    modes_->band_final = !interpolates_across_rows(plan);
    // After an exchange rank 0's film holds every row as it is then: a point of the report's
    // error curve (before it, only rank 0's own band is current).
    // Without a reference nothing reads the images, and one a round at frame size is much.
    if (ranks_.rank == 0 && exchanges_for) {
        modes_->exchanges.emplace();
        modes_->exchange_images = exchanges_for->scores();
    }
    modes_->start = std::chrono::steady_clock::now();
    waited_before_ = seconds_waiting_for_ranks();
}

bool MpiGroup::serves_only() const { return modes_->ic_share == IcShare::kComponent && modes_->roles.answers; }

void MpiGroup::share_rows(SharedRows& rows) {
    // Rank 0 before the last exchange of rows: its own band of the last stage is final (what a
    // fault writes, partial_rows.h), unless the plan's image is made from more than each row's
    // film: a subsample variable interpolates pixels from corners in other rows, capict adds
    // stand-ins across rows, both at the end. Earlier exchanges carry rows still to change;
    // after the last one, final_image() keeps every row. Kept before any wait that may time out.
    if (rows.why == RowExchange::kEnd && modes_->band_final && ranks_.rank == 0)
        keep_finished_rows(rows.film, rows.ambient, rows.bounds[static_cast<size_t>(ranks_.band)],
                           rows.bounds[static_cast<size_t>(ranks_.band) + 1]);
    if (modes_->client) modes_->client->at_exchange();  // the PA serves the other PRs while this one waits
    distributed::share_rows(ranks_, rows);
    // The end is added from the final image (exchange_checkpoints()); new bands follow the
    // round's guidance, with nothing of the round rendered yet but the work on the preview's samples.
    auto& exchanges = modes_->exchanges;
    if (!exchanges || rows.why == RowExchange::kEnd || rows.why == RowExchange::kNewBands) return;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - modes_->start).count();
    const bool preview = rows.why == RowExchange::kPreview;
    exchanges->push_back({seconds, preview ? "preselective" : "selective",
                          preview ? std::string("the preview, rows of every rank")
                                  : fmt::format("round {} done, rows of every rank", exchanges->size()),
                          0, modes_->exchange_images ? rows.film.composite(&rows.ambient) : std::vector<float>{}, std::nullopt});
}

void MpiGroup::sum(std::vector<double>& values) {
    if (modes_->client) modes_->client->at_exchange();  // as at an exchange of rows: the PA serves the others meanwhile
    sum_over_row_ranks(ranks_, values);
}

void MpiGroup::share_cache(IrradianceCache& cache) {
    if (modes_->central) modes_->central->exchange(cache);
    if (modes_->ic_share == IcShare::kBroadcast) share_cache_records(ranks_, cache, modes_->broadcast_shared);
}

void MpiGroup::answer_queries(IrradianceCache& cache, const std::vector<IcQuery>& queries, std::vector<Vec3>& irradiance) {
    if (modes_->client) modes_->client->answer(queries, irradiance);
    else if (modes_->central) modes_->central->answer(cache, queries, irradiance);
    else cache.irradiance(queries, 0, irradiance);
}

void MpiGroup::final_image(const std::vector<float>& rgb, int width) {
    if (ranks_.rank == 0)  // every row, as the image will be written
        keep_finished_rows(rgb, width, 0, static_cast<int>(rgb.size() / (3 * static_cast<size_t>(width))));
}

std::vector<Checkpoint> MpiGroup::exchange_checkpoints(const RunResult& result) const {
    std::vector<Checkpoint> out = modes_->exchanges ? *modes_->exchanges : std::vector<Checkpoint>{};
    out.push_back({slowest_, "end", "end of render (the rows of every rank)", static_cast<uint64_t>(rays_),
                   modes_->exchange_images ? result.image() : std::vector<float>{}, std::nullopt});
    return out;
}

void MpiGroup::fail(ProcessFailure why, const std::string& what) {
    const int rank = ranks_.rank;
    switch (why) {
    case ProcessFailure::kInternal:
        abort_all_ranks(fmt::format("crex run: internal error on rank {}: {}\n", rank, what), kExitFailure);
        break;
    case ProcessFailure::kInput: abort_all_ranks(fmt::format("crex run: error: rank {}: {}\n", rank, what), kExitInputErrors); break;
    case ProcessFailure::kRender:
        abort_all_ranks(fmt::format("crex run: error: rank {}: rendering failed: {}\n", rank, what), kExitFailure);
        break;
    case ProcessFailure::kServe:
        abort_all_ranks(fmt::format("crex run: error: rank {}: answering irradiance queries failed: {}\n", rank, what), kExitFailure);
        break;
    }
    std::_Exit(kExitFailure);  // abort_all_ranks returns only outside mpirun, which a group of ranks never is
}

namespace {

struct RankTotals {
    double rays = 0, records = 0, misses = 0, waiting = 0, slowest = 0, left_out = 0;
};

// `left_out`: camera samples this rank's budget left out of its band.
// `waited_before`: seconds this rank waited before the render (for rank 0's inputs, for the
// others to set up), which the idle share of the render leaves out.
RankTotals totals(double rays, const IcStats& ic, double render_seconds, double left_out, double waited_before) {
    all_ranks_arrive("the end of the render");
    RankTotals t;
    // Misses as the thesis counts them: lookups (at every bounce) not interpolated from records.
    t.rays = sum_over_ranks(rays);
    t.records = sum_over_ranks(static_cast<double>(ic.records));
    t.misses = sum_over_ranks(static_cast<double>(ic.lookups - ic.interpolated));
    t.waiting = sum_over_ranks(seconds_waiting_for_ranks() - waited_before);
    t.slowest = max_over_ranks(render_seconds);
    t.left_out = sum_over_ranks(left_out);
    return t;
}

}  // namespace

void MpiGroup::serve(const PipelinePlan& plan, const Scene& scene, const RunSettings& s) {
    RenderScene rs(scene, texture_cache_bytes(s.max_memory));
    rs.set_view(s.width, s.height);
    IrradianceCache cache(rs, plan_cache_settings(plan, *s.irradiance_cache));
    cache.insert(s.ic_records);
    if (s.ic_file_bytes)  // the file as rank 0 read it: it may exist on rank 0's machine only
        if (std::string error = cache.load_bytes(*s.ic_file_bytes, s.ic_file); !error.empty())
            abort_all_ranks(fmt::format("crex run: error: rank {}: irradiance cache: {}\n", ranks_.rank, error), kExitInputErrors);
    ServeResult served = serve_irradiance(modes_->roles, cache);
    // Rank 0 writes --ic-file, as every output: the file is on its machine, not this one's.
    if (modes_->roles.pa_index == 0 && !s.ic_file.empty()) send_bytes(0, cache.to_bytes(), "the irradiance cache for --ic-file");
    totals(0, cache.stats(), served.seconds, 0, waited_before_);
}

void MpiGroup::end(const RunSettings& settings, RunResult& result) {
    if (modes_->client) modes_->client->done();
    if (!modes_->ic_file.empty()) {  // rank 0 under component: the first PA's records
        const std::string bytes = receive_bytes(modes_->roles.pa, "the irradiance cache for --ic-file");
        if (std::string error = write_file_atomically(modes_->ic_file, bytes); !error.empty())
            abort_all_ranks(fmt::format("crex run: error: cannot save the irradiance cache: {}\n", error), kExitFailure);
    }
    if (modes_->central) modes_->central->finish();
    const RankTotals t = totals(static_cast<double>(total_rays(result.stats)), result.ic_stats, result.render_seconds,
                                static_cast<double>(result.budget_stopped_samples), waited_before_);
    rays_ = t.rays, slowest_ = t.slowest;
    if (ranks_.rank != 0) return;
    disarm_partial_outputs();  // every rank is past its last wait: the outputs themselves follow
    std::string how = "in bands of rows";
    if (modes_->ic_share == IcShare::kComponent)
        how = fmt::format("--ic-share component: {} PA rank(s) answering irradiance queries, {} PR rank(s) rendering bands of rows",
                          modes_->roles.pa_count, modes_->roles.pr_count);
    else if (settings.irradiance_cache)
        how = fmt::format("in bands of rows, --ic-share {}", name_of(modes_->ic_share));
    // The bands change per stage: rank 0's rows here are those of the last stage's band.
    const std::vector<int>& bounds = result.row_bands;
    std::vector<int> rows;
    for (size_t b = 0; b + 1 < bounds.size(); ++b) rows.push_back(bounds[b + 1] - bounds[b]);
    result.notes.push_back(fmt::format("rendered by {} ranks under mpirun {}: {:.0f} rays and {:.0f} irradiance records over all "
                                       "ranks, the slowest rank {:.3f} s; {:.0f} cache misses over all ranks; idle {:.1f} % (time "
                                       "ranks waited for others over ranks x slowest); the table below is rank 0's (rows {}..{} "
                                       "in the last stage; each stage's bands of rows carry about the same camera samples, the last "
                                       "stage's hold {} rows)",
                                       ranks_.size, how, t.rays, t.records, t.slowest, t.misses,
                                       t.slowest > 0 ? 100 * t.waiting / (ranks_.size * t.slowest) : 0.0, bounds.at(0), bounds.at(1) - 1,
                                       fmt::join(rows, ", ")));
    // Each rank spends the whole budget on its own band (its own clock, its own passes): the
    // run takes about the budget, as one process does, and covers N bands in it.
    if (const double budget = settings.executor.budget_seconds; budget > 0)
        result.notes.push_back(fmt::format("under mpirun each rank spends the whole budget ({:g} s) on its own band of rows, deciding "
                                           "its passes alone: {:.0f} camera samples left out over all ranks",
                                           budget, t.left_out));
}

}  // namespace crex::distributed
