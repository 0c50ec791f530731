/// \file distributed.h
/// Distributed rendering as a library (issue 19, thesis chapter 6): `mpirun -np N crex run ...`
/// is the same command on N ranks, each a process of one MpiGroup (mpi_group.h), the
/// ProcessGroup the driver and the run API already take. The lead (rank 0) alone reads the
/// inputs and sends them as data (runtime/api/shared_inputs.h), writes the outputs and prints.
/// The ranks that render rows (all of them; under IcShare::kComponent only the PR ranks) each
/// render the camera samples of their own band of rows, chosen per stage
/// (runtime/driver/row_bands.h): equal bands for the preview (or a plain crex), then for each
/// round bands of about the same camera samples, which every rank computes alike from the film
/// they all hold. The film's rows are shared after the preview, before each round's guidance
/// (the maps see the whole image), before round 1's bands replace the preview's and at the end,
/// so every pixel is the sum of exactly the samples one rank traced, in the order one process
/// traces them: without an irradiance cache, the image is the single-process image.
/// How the ranks share a cache: ic_share_central.h, ic_share_component.h, and broadcast
/// (mpi_comm.h). Every wait for another rank is bounded (rank_watchdog.h); on a fault rank 0
/// writes the rows it finished (partial_rows.h). Without Open MPI at build time, or outside
/// mpirun, a process is a group of one (LocalGroup).
#pragma once

#include <memory>

#include "runtime/driver/process_group.h"

namespace crex {

/// How the ranks share an irradiance cache.
enum class IcShare {
    kNone,       ///< each rank its own
    kCentral,    ///< records go through rank 0, also during the render
    kBroadcast,  ///< records go to every rank after the preview and before each later round
    kComponent,  ///< the highest max(1, N/4) ranks answer every irradiance query with one cache
};

struct DistributedOptions {
    IcShare ic_share = IcShare::kComponent;
    double rank_timeout = 600;  ///< seconds a rank waits for another before the run is ended, naming it
};

/// Starts MPI when this process was launched by mpirun (Open MPI's environment says so) and
/// ends it with the session: first thing in main(), before any thread starts (MPI's, TBB's).
/// Without mpirun, one process and no MPI at all.
class DistributedSession {
public:
    DistributedSession(int& argc, char**& argv);
    ~DistributedSession();
    DistributedSession(const DistributedSession&) = delete;
    DistributedSession& operator=(const DistributedSession&) = delete;
    /// This process speaks for the run (rank 0, or the only process): it alone prints.
    static bool leads();
};

/// The group this process belongs to: an MpiGroup under mpirun, else a LocalGroup.
std::unique_ptr<ProcessGroup> make_process_group(const DistributedOptions& options);

}  // namespace crex
