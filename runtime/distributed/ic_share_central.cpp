#include "runtime/distributed/ic_share_central.h"

#ifdef CREX_WITH_MPI

#include <fmt/format.h>

#include <type_traits>

#include "runtime/distributed/rank_watchdog.h"

namespace crex::distributed {
namespace {
constexpr int kRecords = 1, kEnd = 2;
constexpr size_t kThreshold = 50;  // records a rank makes before it sends them mid-render
static_assert(std::is_trivially_copyable_v<IrradianceRecord>);
}  // namespace

CentralShare::CentralShare() {
    MPI_Comm_dup(MPI_COMM_WORLD, &comm_);
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
    // Rank 0 is the centre: while it waits for others (at an exchange of rows, or the end of
    // the render) it keeps merging and passing records on.
    if (rank_ == 0) set_serve_while_waiting([this] { pump(); });
}

void CentralShare::answer(IrradianceCache& cache, const std::vector<IcQuery>& queries, std::vector<Vec3>& irradiance) {
    cache_ = &cache;
    const size_t before = cache.records().size();
    cache.irradiance(queries, 0, irradiance);
    // The records this batch made are the cache's last ones: others' are inserted only in pump().
    const auto& all = cache.records();
    outbox_.insert(outbox_.end(), all.begin() + static_cast<std::ptrdiff_t>(before), all.end());
    pump();
}

void CentralShare::send(std::vector<IrradianceRecord> records, int to) {
    pending_.push_back({std::move(records), MPI_REQUEST_NULL});
    Pending& p = pending_.back();
    MPI_Isend(p.records.data(), static_cast<int>(p.records.size() * sizeof(IrradianceRecord)), MPI_BYTE, to, kRecords, comm_, &p.request);
}

void CentralShare::forward(const std::vector<IrradianceRecord>& records, int except) {
    if (records.empty()) return;
    for (int r = 1; r < size_; ++r)
        if (r != except) send(records, r);
}

std::vector<IrradianceRecord> CentralShare::receive(const MPI_Status& status) {
    int bytes = 0;
    MPI_Get_count(&status, MPI_BYTE, &bytes);
    std::vector<IrradianceRecord> records(static_cast<size_t>(bytes) / sizeof(IrradianceRecord));
    MPI_Recv(records.data(), bytes, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, comm_, MPI_STATUS_IGNORE);
    return records;
}

void CentralShare::insert(const std::vector<IrradianceRecord>& records) {
    if (cache_) cache_->insert(records);
}

void CentralShare::pump() {
    // An exchange takes messages in its own order; before the first D batch there is no cache
    // to put records in yet (they wait in MPI's queue).
    if (flushing_ || !cache_) return;
    if (outbox_.size() >= kThreshold) {
        if (rank_ == 0) forward(outbox_, 0);
        else send(outbox_, 0);
        outbox_.clear();
    }
    // What has arrived: at rank 0 from any rank (merged here, passed on), elsewhere from rank 0.
    for (;;) {
        int flag = 0;
        MPI_Status status;
        MPI_Iprobe(rank_ == 0 ? MPI_ANY_SOURCE : 0, kRecords, comm_, &flag, &status);
        if (!flag) break;
        std::vector<IrradianceRecord> records = receive(status);
        insert(records);
        if (rank_ == 0) forward(records, status.MPI_SOURCE);
    }
    for (auto it = pending_.begin(); it != pending_.end();) {
        int done = 0;
        MPI_Test(&it->request, &done, MPI_STATUS_IGNORE);
        it = done ? pending_.erase(it) : std::next(it);
    }
}

void CentralShare::flush(IrradianceCache* cache, const char* what) {
    cache_ = cache;
    flushing_ = true;
    const std::string point = fmt::format("{} no. {} (--ic-share central)", what, ++flushes_);
    if (rank_ == 0) {
        forward(outbox_, 0);
        outbox_.clear();
        // Each rank's records in rank order, up to its end marker; passed on at once.
        for (int r = 1; r < size_; ++r) {
            for (bool end = false; !end;) {
                MPI_Status status;
                int flag = 0;
                wait_until([&] { return MPI_Iprobe(r, MPI_ANY_TAG, comm_, &flag, &status), flag != 0; }, rank_timeout(),
                           [&] { return fmt::format("rank {} did not reach {}", r, point); });
                std::vector<IrradianceRecord> records = receive(status);
                end = status.MPI_TAG == kEnd;
                insert(records);
                forward(records, r);
            }
        }
        for (int r = 1; r < size_; ++r) {
            pending_.push_back({{}, MPI_REQUEST_NULL});
            MPI_Isend(nullptr, 0, MPI_BYTE, r, kEnd, comm_, &pending_.back().request);
        }
    } else {
        if (!outbox_.empty()) send(outbox_, 0);
        outbox_.clear();
        pending_.push_back({{}, MPI_REQUEST_NULL});
        MPI_Isend(nullptr, 0, MPI_BYTE, 0, kEnd, comm_, &pending_.back().request);
        for (bool end = false; !end;) {
            MPI_Status status;
            int flag = 0;
            wait_until([&] { return MPI_Iprobe(0, MPI_ANY_TAG, comm_, &flag, &status), flag != 0; }, rank_timeout(),
                       [&] { return fmt::format("rank 0 did not reach {}", point); });
            std::vector<IrradianceRecord> records = receive(status);
            end = status.MPI_TAG == kEnd;
            insert(records);
        }
    }
    // Every message of this exchange has been received: the sends complete.
    std::vector<MPI_Request> requests;
    for (auto& p : pending_) requests.push_back(p.request);
    wait_requests(requests, rank_timeout(), [&] { return "a rank stalled in " + point; });
    pending_.clear();
    flushing_ = false;
}

void CentralShare::exchange(IrradianceCache& cache) { flush(&cache, "the exchange of irradiance records"); }

void CentralShare::finish() {
    if (rank_ == 0) set_serve_while_waiting(nullptr);
    flush(nullptr, "the end of the exchanges of irradiance records");
    MPI_Comm_free(&comm_);
}

}  // namespace crex::distributed

#endif
