/// \file run_distributed.h
/// What `crex run` does differently under mpirun (issue 19): which rows this rank renders,
/// how the irradiance cache is shared (--ic-share), the PA ranks' serve loop of the
/// component-based cache, and the totals over the ranks in rank 0's notes.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "apps/crex/distributed.h"
#include "apps/crex/run_input.h"
#include "apps/crex/run_options.h"
#include "apps/crex/run_setup.h"
#include "runtime/report/checkpoints.h"

namespace crex::app {

class DistributedRun {
public:
    DistributedRun();
    ~DistributedRun();

    /// Settings for this rank (its rows, the exchanges, the cache hooks). An exit code when the
    /// run cannot go distributed (printed by rank 0). Collective under mpirun.
    std::optional<int> configure(const RunOptions& opt, const RunInput& in, RunSetup& setup);
    bool active() const { return ranks_.active(); }
    int rank() const { return ranks_.rank; }
    /// A PA rank of --ic-share component: it answers irradiance queries instead of rendering.
    bool answers_irradiance() const;
    /// A PA rank's whole run: serve until every PR is done, send rank 0 the records for
    /// --ic-file (the first PA: it holds them), then the totals. Returns the exit code.
    int serve(const RunInput& in, const RunSetup& setup);
    /// After this rank's render: the totals over all ranks; rank 0 gets them as a note (and
    /// saves --ic-file under component, from the first PA). Collective. Returns the exit code
    /// on ranks other than 0 (they write nothing); none on rank 0, which writes the outputs.
    std::optional<int> finish(const RunSetup& setup, RunResult& result);
    /// After finish(): the rays over all ranks, and the slowest rank's render time.
    double rays_over_ranks() const { return rays_; }
    double slowest_render_seconds() const { return slowest_; }
    /// Rank 0, with a report or a reference: the image after each exchange of rows but the
    /// last, when its film holds every rank's rows (rank 0's clock; rays not counted), for the
    /// error curve's points before the end.
    std::vector<Checkpoint> exchange_checkpoints() const;

private:
    struct Modes;
    Distribution ranks_;
    std::unique_ptr<Modes> modes_;
    double rays_ = 0, slowest_ = 0;
    double waited_before_ = 0;  // seconds waited for other ranks before the render
};

}  // namespace crex::app
