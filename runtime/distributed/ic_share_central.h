/// \file ic_share_central.h
/// --ic-share central (thesis 6.3.1, after Robertson et al.): every rank renders rows and
/// answers its own D queries with its own cache, and the records it makes go to rank 0, which
/// merges them and passes each rank the ones it has not seen. Unlike broadcast, this happens
/// during the render too: after a D step of a rank's has made 50 new records or more (the
/// thesis's threshold, from Koholka et al.) it sends them to rank 0 without waiting, and takes
/// whatever rank 0 has passed it so far; rank 0 merges and passes on what has arrived whenever
/// it answers its own D queries or waits for other ranks. Nothing mid-render is collective,
/// so nothing can deadlock; the price is that what a rank has seen by a given query depends on
/// timing, so the image varies slightly from run to run (within the cache's accuracy).
/// At each point where broadcast exchanges (after the preview, before each later round) every
/// rank flushes to rank 0, which takes them in rank order and passes the rest on, so there
/// every rank holds every record, as with broadcast.
#pragma once

#ifdef CREX_WITH_MPI
#include <mpi.h>

#include <list>
#include <vector>

#include "runtime/cache/irradiance_cache.h"

namespace crex::distributed {

class CentralShare {
public:
    /// Collective over all ranks (every rank renders rows in this mode).
    CentralShare();
    /// A D batch answered by `cache`, then records sent and taken as above.
    void answer(IrradianceCache& cache, const std::vector<IcQuery>& queries, std::vector<Vec3>& irradiance);
    /// Every rank holds every record made so far. Collective.
    void exchange(IrradianceCache& cache);
    /// After the render (its cache is gone): records still in flight are taken and dropped, so
    /// no message is left unmatched at MPI_Finalize. Collective.
    void finish();

private:
    void pump();  // the mid-render part: send past the threshold, take what arrived
    void flush(IrradianceCache* cache, const char* what);
    void send(std::vector<IrradianceRecord> records, int to);
    void forward(const std::vector<IrradianceRecord>& records, int except);
    std::vector<IrradianceRecord> receive(const MPI_Status& status);
    void insert(const std::vector<IrradianceRecord>& records);

    MPI_Comm comm_ = MPI_COMM_NULL;
    int rank_ = 0, size_ = 1;
    IrradianceCache* cache_ = nullptr;  // the render's, while it runs
    std::vector<IrradianceRecord> outbox_;  // made here, not sent yet
    struct Pending {
        std::vector<IrradianceRecord> records;
        MPI_Request request;
    };
    std::list<Pending> pending_;  // sends in flight (their buffers live until they complete)
    bool flushing_ = false;
    int flushes_ = 0;
};

}  // namespace crex::distributed

#endif
