/// \file record_exchange.h
/// Irradiance records made on each rank of a communicator, exchanged so that every rank holds
/// all of them (MPI only): --ic-share broadcast among the ranks that render rows, and the PA
/// ranks of --ic-share component among themselves.
#pragma once

#ifdef CREX_WITH_MPI
#include <mpi.h>

#include <string>

#include "runtime/cache/irradiance_cache.h"

namespace crex::distributed {

/// The records this rank made since the last call go to every rank of `comm`, and every other
/// rank's are inserted here, in rank order (so every rank's cache ends the same). `shared`
/// counts the records this rank made that were already sent (start at 0). The records this
/// rank made must be the cache's last ones (others' are appended only here). Collective and
/// bounded: `point` names the exchange in a timeout's error.
void allgather_new_records(MPI_Comm comm, IrradianceCache& cache, size_t& shared, const std::string& point);

}  // namespace crex::distributed

#endif
