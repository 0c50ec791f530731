#include "apps/crex/run_distributed.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>

#include "apps/crex/distributed_partial.h"
#include "apps/crex/exit_codes.h"
#include "apps/crex/ic_share_central.h"
#include "apps/crex/ic_share_component.h"
#include "apps/crex/run_resume.h"
#include "compiler/sched/print.h"
#include "runtime/base/atomic_file.h"
#include "runtime/render/render_scene.h"

namespace crex::app {

struct DistributedRun::Modes {
    std::string ic_share = "none";  // what is in effect: none without a cache
    ComponentRoles roles;
    std::string ic_file;  // --ic-file under component: the first PA sends its records, rank 0 saves
    std::shared_ptr<std::vector<Checkpoint>> exchanges;  // rank 0 with a report: the image at each exchange
#ifdef CREX_WITH_MPI
    std::shared_ptr<IrradianceClient> client;  // a PR of component
    std::shared_ptr<CentralShare> central;
#endif
};

DistributedRun::DistributedRun() : ranks_(distribution()), modes_(std::make_unique<Modes>()) {}
DistributedRun::~DistributedRun() = default;

namespace {
// Rank 0 before the last exchange of rows: its own band of the last stage is final (what a
// fault writes, distributed_partial.h), unless the plan's image is made from more than each
// row's film: a subsample variable interpolates pixels from corners in other rows, capict adds
// stand-ins across rows, both at the end. Earlier exchanges carry rows still to change; after
// the last one, RunSettings::final_image keeps every row.
void keep_band_if_final(const Distribution& d, bool band_final, const SharedRows& rows) {
    if (rows.why == RowExchange::kEnd && band_final && d.rank == 0)
        keep_finished_rows(rows.film, rows.ambient, rows.bounds[static_cast<size_t>(d.band)], rows.bounds[static_cast<size_t>(d.band) + 1]);
}

bool interpolates_across_rows(const PipelinePlan& plan) {
    return std::any_of(plan.variables.begin(), plan.variables.end(),
                       [](const PlanVariable& v) { return v.variable == pipeline::SelectiveVariable::kSubsample; });
}
}  // namespace

std::vector<Checkpoint> DistributedRun::exchange_checkpoints() const {
    return modes_->exchanges ? *modes_->exchanges : std::vector<Checkpoint>{};
}

bool DistributedRun::answers_irradiance() const { return modes_->ic_share == "component" && modes_->roles.answers; }

std::optional<int> DistributedRun::configure(const RunOptions& opt, const RunInput& in, RunSetup& setup) {
    if (!ranks_.active()) return std::nullopt;
    // From here a fault writes the rows rank 0 finished beside each -o (distributed_partial.h).
    if (ranks_.rank == 0)
        arm_partial_outputs(setup.outputs, setup.settings.width, setup.settings.height, partial_identity(in, setup));
    // What a distributed run cannot do yet was refused by rank 0 (distributed_input.cpp).
    // The modes below start with blocking collectives (communicators): a rank stuck setting
    // up is named here instead of blocking them.
    all_ranks_arrive("the start of the render (inputs read and checked)");
    RunSettings& s = setup.settings;
    // Sharing a cache means something only with one: without, every rank renders rows.
    if (s.irradiance_cache) modes_->ic_share = opt.ic_share;
#ifdef CREX_WITH_MPI
    if (modes_->ic_share == "component") {
        modes_->roles = component_roles(ranks_.size, ranks_.rank);
        ranks_ = render_rows_on_first(modes_->roles.pr_count);
        start_component_protocol(modes_->roles);
        if (!modes_->roles.answers) {
            auto client = std::make_shared<IrradianceClient>(modes_->roles.pa);
            modes_->client = client;
            s.answer_ic_queries = [client](IrradianceCache&, const std::vector<IcQuery>& q, std::vector<Vec3>& e) { client->answer(q, e); };
            // The PA loads the records (the bytes rank 0 read) and holds them; this rank's own
            // cache stays empty. Rank 0 saves the first PA's, on its own machine (finish()).
            if (ranks_.rank == 0) modes_->ic_file = s.ic_file;
            // Nor does it answer a query: no caustic map to build (8 ranks built 8 maps, 6 of
            // them unused, and starved a neighbouring test's rank of its 1 s to start).
            s.irradiance_cache->caustic_photons = 0;
            s.ic_file.clear();
            s.ic_file_bytes.reset();
            s.ic_records.clear();
        }
    } else if (modes_->ic_share == "central") {
        auto central = std::make_shared<CentralShare>();
        modes_->central = central;
        s.answer_ic_queries = [central](IrradianceCache& cache, const std::vector<IcQuery>& q, std::vector<Vec3>& e) {
            central->answer(cache, q, e);
        };
        s.share_cache = [central](IrradianceCache& cache) { central->exchange(cache); };
    } else if (modes_->ic_share == "broadcast") {
        auto shared = std::make_shared<size_t>(0);
        const Distribution d = ranks_;
        s.share_cache = [d, shared](IrradianceCache& cache) { share_cache_records(d, cache, *shared); };
    }
#endif
    s.band = ranks_.band;
    s.bands = ranks_.bands;
    const Distribution d = ranks_;
    const bool band_final = !interpolates_across_rows(in.plan);
    // After an exchange rank 0's film holds every row as it is then: a point of the report's
    // error curve (before it, only rank 0's own band is current).
    if (ranks_.rank == 0 && (setup.reference || !opt.report_dir.empty()))
        modes_->exchanges = std::make_shared<std::vector<Checkpoint>>();
    auto exchanges = modes_->exchanges;
    const auto start = std::chrono::steady_clock::now();
    auto note_exchange = [exchanges, start](const SharedRows& rows) {
        // The end is added by cmd_run from the written image; new bands follow the round's
        // guidance, with nothing of the round rendered yet but the work on the preview's samples.
        if (!exchanges || rows.why == RowExchange::kEnd || rows.why == RowExchange::kNewBands) return;
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const bool preview = rows.why == RowExchange::kPreview;
        exchanges->push_back({seconds, preview ? "preselective" : "selective",
                              preview ? std::string("the preview, rows of every rank")
                                      : fmt::format("round {} done, rows of every rank", exchanges->size()),
                              0, rows.film.composite(&rows.ambient)});
    };
#ifdef CREX_WITH_MPI
    auto client = modes_->client;
    s.share_rows = [d, band_final, client, note_exchange](SharedRows& rows) {
        keep_band_if_final(d, band_final, rows);  // before any wait that may time out
        if (client) client->at_exchange();  // the PA serves the other PRs while this one waits
        share_rows(d, rows);
        note_exchange(rows);
    };
    s.sum_over_processes = [d, client](std::vector<double>& values) {
        if (client) client->at_exchange();  // as at an exchange of rows: the PA serves the others meanwhile
        sum_over_row_ranks(d, values);
    };
#else
    s.share_rows = [d, band_final, note_exchange](SharedRows& rows) {
        keep_band_if_final(d, band_final, rows);
        share_rows(d, rows);
        note_exchange(rows);
    };
    s.sum_over_processes = [d](std::vector<double>& values) { sum_over_row_ranks(d, values); };
#endif
    if (ranks_.rank == 0)  // every row, as the image will be written
        s.final_image = [](const std::vector<float>& rgb, int width) {
            keep_finished_rows(rgb, width, 0, static_cast<int>(rgb.size() / (3 * static_cast<size_t>(width))));
        };
    s.save_ic_file = ranks_.rank == 0;
    waited_before_ = seconds_waiting_for_ranks();
    return std::nullopt;
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

int DistributedRun::serve(const RunInput& in, const RunSetup& setup) {
#ifdef CREX_WITH_MPI
    const RunSettings& s = setup.settings;
    RenderScene rs(*in.scene->scene, texture_cache_bytes(s.max_memory));
    rs.set_view(s.width, s.height);
    IrradianceCache cache(rs, plan_cache_settings(in.plan, *s.irradiance_cache));
    for (const auto& r : s.ic_records) cache.insert(r);
    if (s.ic_file_bytes)  // the file as rank 0 read it: it may exist on rank 0's machine only
        if (std::string error = cache.load_bytes(*s.ic_file_bytes, s.ic_file); !error.empty())
            abort_all_ranks(fmt::format("crex run: error: rank {}: irradiance cache: {}\n", ranks_.rank, error), kExitInputErrors);
    ServeResult served = serve_irradiance(modes_->roles, cache);
    // Rank 0 writes --ic-file, as every output: the file is on its machine, not this one's.
    if (modes_->roles.pa_index == 0 && !s.ic_file.empty()) send_bytes(0, cache.to_bytes(), "the irradiance cache for --ic-file");
    totals(0, cache.stats(), served.seconds, 0, waited_before_);
    return kExitOk;
#else
    (void)in, (void)setup;
    return kExitOk;
#endif
}

std::optional<int> DistributedRun::finish(const RunSetup& setup, RunResult& result) {
#ifdef CREX_WITH_MPI
    if (modes_->client) modes_->client->done();
    if (!modes_->ic_file.empty()) {  // rank 0 under component: the first PA's records
        const std::string bytes = receive_bytes(modes_->roles.pa, "the irradiance cache for --ic-file");
        if (std::string error = write_file_atomically(modes_->ic_file, bytes); !error.empty())
            abort_all_ranks(fmt::format("crex run: error: cannot save the irradiance cache: {}\n", error), kExitFailure);
    }
    if (modes_->central) modes_->central->finish();
#endif
    const RankTotals t = totals(static_cast<double>(total_rays(result.stats)), result.ic_stats, result.render_seconds,
                                static_cast<double>(result.budget_stopped_samples), waited_before_);
    rays_ = t.rays, slowest_ = t.slowest;
    if (ranks_.rank != 0) return kExitOk;
    disarm_partial_outputs();  // every rank is past its last wait: the outputs themselves follow
    std::string how = "in bands of rows";
    if (modes_->ic_share == "component")
        how = fmt::format("--ic-share component: {} PA rank(s) answering irradiance queries, {} PR rank(s) rendering bands of rows",
                          modes_->roles.pa_count, modes_->roles.pr_count);
    else if (setup.settings.irradiance_cache)
        how = fmt::format("in bands of rows, --ic-share {}", modes_->ic_share);
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
    if (setup.budget > 0)
        result.notes.push_back(fmt::format("under mpirun each rank spends the whole budget ({:g} s) on its own band of rows, deciding "
                                           "its passes alone: {:.0f} camera samples left out over all ranks",
                                           setup.budget, t.left_out));
    return std::nullopt;
}

}  // namespace crex::app
