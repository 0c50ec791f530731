#include "runtime/distributed/distributed.h"

#include "runtime/distributed/mpi_comm.h"
#include "runtime/distributed/rank_watchdog.h"

#ifdef CREX_WITH_MPI
#include "runtime/distributed/mpi_group.h"
#endif

namespace crex {

DistributedSession::DistributedSession(int& argc, char**& argv) { distributed::start_mpi(argc, argv); }
DistributedSession::~DistributedSession() { distributed::finish_mpi(); }
bool DistributedSession::leads() { return distributed::distribution().rank == 0; }

std::unique_ptr<ProcessGroup> make_process_group(const DistributedOptions& options) {
    distributed::set_rank_timeout(options.rank_timeout);
#ifdef CREX_WITH_MPI
    if (distributed::distribution().active()) return std::make_unique<distributed::MpiGroup>(options);
#endif
    return std::make_unique<LocalGroup>();
}

}  // namespace crex
