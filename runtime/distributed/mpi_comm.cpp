#include "runtime/distributed/mpi_comm.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <memory>

#ifdef CREX_WITH_MPI
#include <mpi.h>

#include "runtime/distributed/partial_rows.h"
#include "runtime/distributed/rank_watchdog.h"
#include "runtime/distributed/record_exchange.h"
#include "runtime/distributed/stop_signals.h"
#include "base/check.h"
#endif

namespace crex::distributed {

#ifdef CREX_WITH_MPI

namespace {

bool launched_by_mpirun() {
    // Open MPI sets these in every process it starts; a plain `crex run` has neither.
    return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr;
}

bool g_started = false;
// The ranks that render rows: all of them, or the PR ranks of --ic-share component.
MPI_Comm g_rows = MPI_COMM_NULL;
int g_row_exchanges = 0;  // names the sync point a late rank did not reach

MPI_Comm rows_comm() { return g_rows == MPI_COMM_NULL ? MPI_COMM_WORLD : g_rows; }

}  // namespace

void start_mpi(int& argc, char**& argv) {
    if (!launched_by_mpirun()) return;
    // Before MPI_Init starts its threads (and before TBB starts any): mpirun's SIGTERM, when
    // another rank dies, lets rank 0 write the rows it finished. A single process keeps the
    // signals' default actions (its outputs are atomic: an interrupted run writes nothing).
    take_stop_signals(write_finished_rows_on_stop);
    MPI_Init(&argc, &argv);
    g_started = true;
}

void finish_mpi() {
    if (!g_started) return;
    if (g_rows != MPI_COMM_NULL) MPI_Comm_free(&g_rows);
    MPI_Finalize();
}

Distribution distribution() {
    Distribution d;
    if (!g_started) return d;
    MPI_Comm_rank(MPI_COMM_WORLD, &d.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &d.size);
    d.band = d.rank, d.bands = d.size;
    return d;
}

Distribution render_rows_on_first(int renderers) {
    Distribution d = distribution();
    const bool renders = d.rank < renderers;
    MPI_Comm_split(MPI_COMM_WORLD, renders ? 0 : MPI_UNDEFINED, d.rank, &g_rows);
    d.band = renders ? d.rank : -1;
    d.bands = renderers;
    return d;
}

namespace {
// The same on every rank that computed the same split (FNV-1a of the bounds).
int fingerprint(const std::vector<int>& bounds) {
    uint32_t h = 2166136261u;
    for (int b : bounds) h = (h ^ static_cast<uint32_t>(b)) * 16777619u;
    return static_cast<int>(h & 0x7fffffffu);
}
}  // namespace

void share_rows(const Distribution& d, SharedRows& rows) {
    if (!d.active()) return;
    Film& film = rows.film;
    const std::vector<int>& bounds = rows.bounds;
    const int exchange = ++g_row_exchanges;
    stall_here_if_asked(exchange, rows.why == RowExchange::kEnd);
    const std::string point = fmt::format("the exchange of rows no. {} (after the preview, before each round, at the end)", exchange);
    // The ranks' tokens carry their splits: counts that differ would make MPI write past the
    // buffers, so a rank that split the rows otherwise (a bug) ends the run here instead.
    arrive(rows_comm(), point, fingerprint(bounds));
    // After the arrival: the tests of a failing rank need rank 0 waiting here with its band
    // finished. Before it, a rank that got here first under load failed while rank 0 still
    // rendered (1 run in 3 with the MPI tests at -j2), and rank 0 had no final row to write.
    fail_here_if_asked(exchange, rows.why == RowExchange::kEnd);
    CREX_CHECK_EQ(bounds.size(), static_cast<size_t>(d.bands) + 1);
    CREX_CHECK_EQ(bounds.front(), 0);
    CREX_CHECK_EQ(bounds.back(), film.height());
    const int width = film.width();
    // Each buffer in place: band b's rows go to every rank (MPI_IN_PLACE: a rank's own band
    // is already where it belongs). Non-blocking, so a rank stalling inside is caught too.
    std::vector<MPI_Request> requests;
    std::vector<std::vector<int>> counts, displs;
    auto gather = [&](void* data, size_t bytes_per_pixel) {
        counts.emplace_back(static_cast<size_t>(d.bands)), displs.emplace_back(static_cast<size_t>(d.bands));
        const size_t row_bytes = static_cast<size_t>(width) * bytes_per_pixel;
        for (size_t b = 0; b < static_cast<size_t>(d.bands); ++b) {
            counts.back()[b] = static_cast<int>(static_cast<size_t>(bounds[b + 1] - bounds[b]) * row_bytes);
            displs.back()[b] = static_cast<int>(static_cast<size_t>(bounds[b]) * row_bytes);
        }
        requests.emplace_back();
        MPI_Iallgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, data, counts.back().data(), displs.back().data(), MPI_BYTE, rows_comm(),
                        &requests.back());
    };
    film.for_each_buffer(gather);
    if (rows.ambient.size() == 3 * film.pixel_count()) gather(rows.ambient.data(), 3 * sizeof(double));
    for (std::vector<float>* left : rows.throughput_left)  // kept alike on every rank, or by none
        if (left->size() == 3 * film.pixel_count()) gather(left->data(), 3 * sizeof(float));
    wait_requests(requests, rank_timeout(), [&] { return "a rank stalled in " + point; });
}

void sum_over_row_ranks(const Distribution& d, std::vector<double>& values) {
    if (!d.active()) return;
    std::vector<MPI_Request> request(1);
    MPI_Iallreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM, rows_comm(), &request[0]);
    wait_requests(request, rank_timeout(), [] { return std::string("a rank did not reach the sums for --ambient auto's stand-ins"); });
}

void share_cache_records(const Distribution& d, IrradianceCache& cache, size_t& shared) {
    if (d.active()) allgather_new_records(rows_comm(), cache, shared, "the exchange of irradiance records (--ic-share broadcast)");
}

void all_ranks_arrive(const std::string& point) {
    if (g_started) arrive(MPI_COMM_WORLD, point);
}

namespace {
constexpr size_t kBytesPiece = size_t{1} << 30;  // MPI counts are ints
}  // namespace

void send_bytes(int to, const std::string& bytes, const std::string& what, int tag) {
    unsigned long long size = bytes.size();
    std::vector<MPI_Request> requests(1);
    MPI_Isend(&size, 1, MPI_UNSIGNED_LONG_LONG, to, tag, MPI_COMM_WORLD, &requests[0]);
    for (size_t at = 0; at < bytes.size(); at += kBytesPiece) {
        requests.emplace_back();
        MPI_Isend(bytes.data() + at, static_cast<int>(std::min(kBytesPiece, bytes.size() - at)), MPI_CHAR, to, tag, MPI_COMM_WORLD,
                  &requests.back());
    }
    wait_requests(requests, rank_timeout(), [&] { return fmt::format("rank {} did not take {}", to, what); });
}

std::string receive_bytes(int from, const std::string& what, int tag) {
    auto late = [&] { return fmt::format("rank {} did not send {}", from, what); };
    unsigned long long size = 0;
    std::vector<MPI_Request> request(1);
    MPI_Irecv(&size, 1, MPI_UNSIGNED_LONG_LONG, from, tag, MPI_COMM_WORLD, &request[0]);
    wait_requests(request, rank_timeout(), late);
    std::string bytes(static_cast<size_t>(size), '\0');
    for (size_t at = 0; at < bytes.size(); at += kBytesPiece) {  // in order: same source and tag
        request.assign(1, MPI_REQUEST_NULL);
        MPI_Irecv(bytes.data() + at, static_cast<int>(std::min(kBytesPiece, bytes.size() - at)), MPI_CHAR, from, tag,
                  MPI_COMM_WORLD, &request[0]);
        wait_requests(request, rank_timeout(), late);
    }
    return bytes;
}

namespace {
// Sends posted and not yet known to be taken: their sizes and bytes must live until then.
struct PostedSend {
    unsigned long long size = 0;
    std::string bytes;
    std::vector<MPI_Request> requests;
};
std::vector<std::unique_ptr<PostedSend>> g_posted;
}  // namespace

void post_bytes(int to, const std::string& bytes, int tag) {
    if (!g_started) return;
    auto send = std::make_unique<PostedSend>();
    send->size = bytes.size();
    send->bytes = bytes;
    send->requests.resize(1);
    MPI_Isend(&send->size, 1, MPI_UNSIGNED_LONG_LONG, to, tag, MPI_COMM_WORLD, &send->requests[0]);
    for (size_t at = 0; at < send->bytes.size(); at += kBytesPiece) {
        send->requests.emplace_back();
        MPI_Isend(send->bytes.data() + at, static_cast<int>(std::min(kBytesPiece, send->bytes.size() - at)), MPI_CHAR, to, tag,
                  MPI_COMM_WORLD, &send->requests.back());
    }
    g_posted.push_back(std::move(send));
}

void wait_for_posted(const std::string& what) {
    for (auto& send : g_posted) wait_requests(send->requests, rank_timeout(), [&] { return "rank 0 did not take " + what; });
    g_posted.clear();
}

std::vector<std::string> all_gather_bytes(const std::string& bytes, const std::string& point) {
    if (!g_started) return {bytes};
    int ranks = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    arrive(MPI_COMM_WORLD, point);
    auto late = [&] { return "a rank stalled in " + point; };
    const long long mine = static_cast<long long>(bytes.size());
    std::vector<long long> sizes(static_cast<size_t>(ranks));
    std::vector<MPI_Request> request(1);
    MPI_Iallgather(&mine, 1, MPI_LONG_LONG, sizes.data(), 1, MPI_LONG_LONG, MPI_COMM_WORLD, &request[0]);
    wait_requests(request, rank_timeout(), late);
    // Each rank's bytes broadcast from it in turn (any size: MPI counts are ints, so in pieces).
    std::vector<std::string> out(static_cast<size_t>(ranks));
    int me = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &me);
    for (int r = 0; r < ranks; ++r) {
        std::string& b = out[static_cast<size_t>(r)];
        b = r == me ? bytes : std::string(static_cast<size_t>(sizes[static_cast<size_t>(r)]), '\0');
        for (size_t at = 0; at < b.size(); at += kBytesPiece) {
            request.assign(1, MPI_REQUEST_NULL);
            MPI_Ibcast(b.data() + at, static_cast<int>(std::min(kBytesPiece, b.size() - at)), MPI_CHAR, r, MPI_COMM_WORLD, &request[0]);
            wait_requests(request, rank_timeout(), late);
        }
    }
    return out;
}

std::optional<std::string> receive_bytes_from_any(int tag, bool wait, const std::string& what) {
    if (!g_started) return std::nullopt;
    int flag = 0;
    MPI_Status status;
    auto arrived = [&] { return MPI_Iprobe(MPI_ANY_SOURCE, tag, MPI_COMM_WORLD, &flag, &status), flag != 0; };
    if (wait) wait_until(arrived, rank_timeout(), [&] { return fmt::format("no rank sent {}", what); });
    else if (!arrived()) return std::nullopt;
    // The size and then the bytes, from the one sender: messages of one source and tag keep their order.
    return receive_bytes(status.MPI_SOURCE, what, tag);
}

std::string share_from_rank0(std::string text, const std::string& what) {
    if (!g_started) return text;
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    // Non-blocking, so that a rank 0 stuck reading its inputs is named, not waited for forever.
    auto late = [&] { return rank == 0 ? "a rank did not take " + what : "rank 0 did not send " + what; };
    unsigned long long size = text.size();
    std::vector<MPI_Request> request(1);
    MPI_Ibcast(&size, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD, &request[0]);
    wait_requests(request, rank_timeout(), late);
    text.resize(static_cast<size_t>(size));
    // In pieces: MPI counts are ints, and a scene's meshes can pass 2 GiB.
    constexpr size_t kPiece = size_t{1} << 30;
    for (size_t at = 0; at < text.size(); at += kPiece) {
        request.assign(1, MPI_REQUEST_NULL);
        MPI_Ibcast(text.data() + at, static_cast<int>(std::min(kPiece, text.size() - at)), MPI_CHAR, 0, MPI_COMM_WORLD, &request[0]);
        wait_requests(request, rank_timeout(), late);
    }
    return text;
}

namespace {
double reduce(double value, MPI_Op op) {
    if (!g_started) return value;
    double out = 0;
    MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, op, MPI_COMM_WORLD);
    return out;
}
}  // namespace

double sum_over_ranks(double value) { return reduce(value, MPI_SUM); }
double max_over_ranks(double value) { return reduce(value, MPI_MAX); }
double seconds_waiting_for_ranks() { return g_started ? seconds_waiting() : 0; }

void abort_all_ranks(const std::string& message, int exit_code) {
    if (!g_started) {
        std::cerr << message << std::flush;
        return;
    }
    end_all_ranks(message, exit_code);  // rank 0 writes its finished rows first
}

#else

void start_mpi(int&, char**&) {}
void finish_mpi() {}
Distribution distribution() { return {}; }
Distribution render_rows_on_first(int) { return {}; }
void share_rows(const Distribution&, SharedRows&) {}
void sum_over_row_ranks(const Distribution&, std::vector<double>&) {}
void share_cache_records(const Distribution&, IrradianceCache&, size_t&) {}
void all_ranks_arrive(const std::string&) {}
std::string share_from_rank0(std::string text, const std::string&) { return text; }
void send_bytes(int, const std::string&, const std::string&, int) {}
std::string receive_bytes(int, const std::string&, int) { return {}; }
std::optional<std::string> receive_bytes_from_any(int, bool, const std::string&) { return std::nullopt; }
std::vector<std::string> all_gather_bytes(const std::string& bytes, const std::string&) { return {bytes}; }
void post_bytes(int, const std::string&, int) {}
void wait_for_posted(const std::string&) {}
double sum_over_ranks(double value) { return value; }
double max_over_ranks(double value) { return value; }
double seconds_waiting_for_ranks() { return 0; }
void abort_all_ranks(const std::string& message, int) { std::cerr << message << std::flush; }

#endif

}  // namespace crex::distributed
