#include "runtime/distributed/record_exchange.h"

#ifdef CREX_WITH_MPI

#include <algorithm>
#include <type_traits>
#include <vector>

#include "runtime/distributed/rank_watchdog.h"

namespace crex::distributed {

void allgather_new_records(MPI_Comm comm, IrradianceCache& cache, size_t& shared, const std::string& point) {
    static_assert(std::is_trivially_copyable_v<IrradianceRecord>);
    int rank = 0, ranks = 1;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &ranks);
    if (ranks < 2) return;
    const std::vector<IrradianceRecord>& all = cache.records();
    const size_t made = static_cast<size_t>(cache.stats().records);
    const size_t mine = std::min(made - std::min(shared, made), all.size());
    const int bytes = static_cast<int>(mine * sizeof(IrradianceRecord));
    std::vector<int> counts(static_cast<size_t>(ranks)), displs(static_cast<size_t>(ranks));
    arrive(comm, point);
    auto late = [&] { return "a rank stalled in " + point; };
    std::vector<MPI_Request> request(1);
    MPI_Iallgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, comm, &request[0]);
    wait_requests(request, rank_timeout(), late);
    long long total = 0;
    for (int r = 0; r < ranks; ++r) displs[static_cast<size_t>(r)] = static_cast<int>(total), total += counts[static_cast<size_t>(r)];
    std::vector<IrradianceRecord> received(static_cast<size_t>(total) / sizeof(IrradianceRecord));
    std::vector<IrradianceRecord> own(all.end() - static_cast<std::ptrdiff_t>(mine), all.end());
    request.assign(1, MPI_REQUEST_NULL);
    MPI_Iallgatherv(own.data(), bytes, MPI_BYTE, received.data(), counts.data(), displs.data(), MPI_BYTE, comm, &request[0]);
    wait_requests(request, rank_timeout(), late);
    for (int r = 0; r < ranks; ++r) {
        if (r == rank) continue;
        const size_t first = static_cast<size_t>(displs[static_cast<size_t>(r)]) / sizeof(IrradianceRecord);
        const size_t n = static_cast<size_t>(counts[static_cast<size_t>(r)]) / sizeof(IrradianceRecord);
        for (size_t k = 0; k < n; ++k) cache.insert(received[first + k]);
    }
    shared = made;
}

}  // namespace crex::distributed

#endif
