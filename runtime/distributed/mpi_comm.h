/// \file mpi_comm.h
/// The MPI exchanges of a distributed run (distributed.h says what the ranks do): the ranks'
/// places, rows and sums among the ranks that render rows, the lead's inputs to every rank,
/// bytes point to point, and ending every rank on a failure. Every wait for another rank is
/// bounded (rank_watchdog.h). Without Open MPI at build time, or outside mpirun, each is the
/// one-process answer.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "runtime/cache/irradiance_cache.h"
#include "runtime/driver/process_group.h"

namespace crex::distributed {

struct Distribution {
    int rank = 0, size = 1;   ///< among all ranks (MPI_COMM_WORLD)
    int band = 0, bands = 1;  ///< this rank's band of rows among the ranks that render rows
    bool active() const { return size > 1; }
};

/// MPI started when this process was launched by mpirun (distributed.h's DistributedSession),
/// and finished.
void start_mpi(int& argc, char**& argv);
void finish_mpi();

/// This process's place among the ranks (rank 0 of 1 when not distributed); every rank
/// renders rows.
Distribution distribution();

/// Only the first `renderers` ranks render rows from here on (the others answer irradiance
/// queries, --ic-share component): their bands and the communicator rows are shared on.
/// Collective over all ranks. A rank beyond them gets band -1.
Distribution render_rows_on_first(int renderers);

/// Every row-rendering rank's per-pixel buffers (`rows`: the film, its ambient stand-ins, the
/// throughput left for --ambient auto) take each band of rows from the rank that rendered it,
/// band b being rows [rows.bounds[b], rows.bounds[b + 1]) (the split of the work since the
/// last exchange, which every rank computed alike: a rank with another split ends the run as
/// an internal error); waits are bounded (a late rank is named). Collective over those ranks.
void share_rows(const Distribution& d, SharedRows& rows);

/// `values` summed over the row-rendering ranks, on each (bounded). Collective over those ranks.
void sum_over_row_ranks(const Distribution& d, std::vector<double>& values);

/// --ic-share broadcast: the records this rank made since the last call go to every
/// row-rendering rank, and every other rank's are inserted here, in rank order. `shared`
/// counts the records this rank made that were already sent (start at 0). Collective.
void share_cache_records(const Distribution& d, IrradianceCache& cache, size_t& shared);

/// Rank 0's `text` on every rank (rank 0 gets its own back): the inputs rank 0 read, as
/// data. Collective; bounded (the others wait --rank-timeout for rank 0 to read and plan).
/// `what` names the data in a timeout's error.
std::string share_from_rank0(std::string text, const std::string& what);

/// `bytes` from this rank to world rank `to`, and their receipt there (point to point, any
/// size, bounded; `what` names them in a timeout's error). `tag` keeps one kind of message
/// apart from the others.
constexpr int kBytesTag = 7304;
constexpr int kFrameTag = 7305;  ///< what a frame of a sequence did (MpiGroup::tell_lead)
void send_bytes(int to, const std::string& bytes, const std::string& what, int tag = kBytesTag);
std::string receive_bytes(int from, const std::string& what, int tag = kBytesTag);
/// `bytes` to rank `to` without waiting for it to take them (kept until it does), so that a
/// rank that tells and then joins a collective cannot wait on a receiver that is in the same
/// collective; wait_for_posted() completes every such send (bounded).
void post_bytes(int to, const std::string& bytes, int tag);
void wait_for_posted(const std::string& what);
/// The next bytes any rank sent with `tag`, if some have arrived; with `wait`, waits for them
/// (bounded). Not distributed: none.
std::optional<std::string> receive_bytes_from_any(int tag, bool wait, const std::string& what);

/// Every rank's `bytes` on every rank, in rank order (all ranks of the world; collective and
/// bounded: `point` names the exchange in a timeout's error). Not distributed: its own.
std::vector<std::string> all_gather_bytes(const std::string& bytes, const std::string& point);

/// Every rank (of all) reached `point`, bounded like every wait: before the last collectives.
void all_ranks_arrive(const std::string& point);

/// Sums `value` over all ranks, or its largest (every rank gets the result): statistics for
/// rank 0's summary. Collective: every rank must call them, in the same order.
double sum_over_ranks(double value);
double max_over_ranks(double value);

/// Seconds this rank waited for others (0 when not distributed).
double seconds_waiting_for_ranks();

/// Ends every rank after `message` (printed by this rank): a failure on one rank must not
/// leave the others waiting for it. Rank 0 first writes the rows it finished
/// (partial_rows.h; end_all_ranks in rank_watchdog.h). Returns only when not distributed.
void abort_all_ranks(const std::string& message, int exit_code);

}  // namespace crex::distributed
