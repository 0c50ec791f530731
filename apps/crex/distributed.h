/// \file distributed.h
/// `mpirun -np N crex run ...` (issue 19, thesis chapter 6): the same command on N ranks. Each
/// rank reads the same inputs and renders the camera samples of its own band of rows (rank r:
/// rows [r H / N, (r + 1) H / N)); the film's rows are shared between the ranks after the
/// preview, before each round's guidance (the maps see the whole image) and at the end, so
/// every pixel is the sum of exactly the samples one rank traced: without an irradiance
/// cache, the image is the single-process image. Rank 0 alone writes outputs and prints.
/// With a cache, --ic-share: none (each rank its own) or broadcast (records exchanged where
/// rows are).
/// Without Open MPI at build time, or outside mpirun, crex runs as one process.
#pragma once

#include <functional>
#include <vector>

#include "runtime/cache/irradiance_cache.h"
#include "runtime/render/film.h"

namespace crex::app {

struct Distribution {
    int rank = 0, size = 1;
    bool active() const { return size > 1; }
    /// The rows this rank renders of an image `height` rows high.
    int row_begin(int height) const { return static_cast<int>(static_cast<long long>(height) * rank / size); }
    int row_end(int height) const { return static_cast<int>(static_cast<long long>(height) * (rank + 1) / size); }
};

/// Starts MPI when this process was launched by mpirun (Open MPI's environment says so) and
/// ends it when the session ends. Without that, one process and no MPI at all.
class DistributedSession {
public:
    DistributedSession(int& argc, char**& argv);
    ~DistributedSession();
    DistributedSession(const DistributedSession&) = delete;
    DistributedSession& operator=(const DistributedSession&) = delete;
};

/// This process's place among the ranks (rank 0 of 1 when not distributed).
Distribution distribution();

/// Every rank's film and ambient stand-ins take each band of rows from the rank that renders it.
void share_rows(const Distribution& d, Film& film, std::vector<double>& ambient);

/// --ic-share broadcast: the records this rank made since the last call go to every rank, and
/// every other rank's are inserted here, in rank order. `shared` counts the records this rank
/// made that were already sent (start at 0). Collective.
void share_cache_records(const Distribution& d, IrradianceCache& cache, size_t& shared);

/// Sums `value` over the ranks, or its largest (every rank gets the result): statistics for
/// rank 0's summary. Collective: every rank must call them, in the same order.
double sum_over_ranks(double value);
double max_over_ranks(double value);

}  // namespace crex::app
