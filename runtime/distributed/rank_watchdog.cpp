#include "runtime/distributed/rank_watchdog.h"

namespace crex::distributed {
namespace {
double g_timeout = 600;
}
void set_rank_timeout(double seconds) { g_timeout = seconds; }
double rank_timeout() { return g_timeout; }
}  // namespace crex::distributed

#ifdef CREX_WITH_MPI

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <stdexcept>
#include <thread>
#include <utility>

#include "base/exit_codes.h"

namespace crex::distributed {
namespace {

using Clock = std::chrono::steady_clock;

double g_waiting = 0;
std::function<void()> g_serve;
bool g_serving = false;  // serve_while_waiting does not run inside itself

constexpr int kArriveTag = 7301;
constexpr int kFaultTag = 7302;  // a rank's fault reported to rank 0 (its exit code), MPI_COMM_WORLD

std::function<void()> g_fault_writer;

int world_rank() {
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    return rank;
}

// Rank 0: write what is finished (once), then abort the job. MPI_Abort makes mpirun end
// every rank (SIGTERM, then SIGKILL), stopped ones too.
[[noreturn]] void write_then_abort(int exit_code) {
    if (auto writer = std::exchange(g_fault_writer, nullptr)) {
        try {
            writer();
        } catch (const std::exception& e) {  // the abort must happen whatever the writer did
            std::cerr << "crex run: error: writing the finished rows failed: " << e.what() << "\n";
        }
    }
    std::cerr << std::flush;
    MPI_Abort(MPI_COMM_WORLD, exit_code);
    std::_Exit(exit_code);  // MPI_Abort does not return; should it, nothing may carry on
}

// Rank 0, in every wait: another rank reported a fault (end_all_ranks), whose message it
// printed itself.
void take_fault_reports() {
    int flag = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kFaultTag, MPI_COMM_WORLD, &flag, &status);
    if (!flag) return;
    int exit_code = kExitFailure;
    MPI_Recv(&exit_code, 1, MPI_INT, status.MPI_SOURCE, kFaultTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    write_then_abort(exit_code);
}

int world_rank_of(MPI_Comm comm, int rank) {
    MPI_Group group, world;
    MPI_Comm_group(comm, &group);
    MPI_Comm_group(MPI_COMM_WORLD, &world);
    int out = rank;
    MPI_Group_translate_ranks(group, 1, &rank, world, &out);
    MPI_Group_free(&group);
    MPI_Group_free(&world);
    return out;
}

}  // namespace

double seconds_waiting() { return g_waiting; }
void set_fault_writer(std::function<void()> writer) { g_fault_writer = std::move(writer); }

void end_all_ranks(const std::string& message, int exit_code) {
    std::cerr << message << std::flush;
    if (world_rank() == 0) write_then_abort(exit_code);
    // Rank 0 ends the job once it takes the report, in its next wait: at once when it is
    // waiting for this rank or another. It has finished rows only then (its band complete, or
    // after the last exchange), so a bounded grace loses nothing it could write; the grace
    // is long enough for it to write them (this rank's abort would kill it mid-write, leaving
    // a staged file), short enough not to matter beside --rank-timeout.
    MPI_Request request;
    MPI_Isend(&exit_code, 1, MPI_INT, 0, kFaultTag, MPI_COMM_WORLD, &request);
    const double grace = 10;
    std::this_thread::sleep_for(std::chrono::duration<double>(grace));
    std::cerr << fmt::format("crex run: rank 0, which holds the image, did not end the run within {:g} s of rank {}'s fault (it "
                             "hung, died or was still rendering its rows): rank {} ends it; rank 0 writes the rows it finished "
                             "only if it is alive to take mpirun's SIGTERM\n",
                             grace, world_rank(), world_rank())
              << std::flush;
    MPI_Abort(MPI_COMM_WORLD, exit_code);
    std::_Exit(exit_code);
}
void set_serve_while_waiting(std::function<void()> serve) { g_serve = std::move(serve); }

void wait_until(const std::function<bool()>& done, double timeout, const std::function<std::string()>& late) {
    const auto start = Clock::now();
    // Short sleeps that grow to 1 ms: a message answered within microseconds costs little
    // latency, and a long wait costs no core.
    std::chrono::microseconds nap(5);
    const bool rank0 = world_rank() == 0;
    while (!done()) {
        if (rank0) take_fault_reports();
        const double waited = std::chrono::duration<double>(Clock::now() - start).count();
        if (waited > timeout)
            end_all_ranks(fmt::format("crex run: error: {} within {:g} s (rank {} waited; --rank-timeout)\n", late(), timeout, world_rank()),
                          kExitFailure);
        if (g_serve && !g_serving) {
            g_serving = true;
            g_serve();
            g_serving = false;
        }
        std::this_thread::sleep_for(nap);
        nap = std::min(nap * 2, std::chrono::microseconds(200));
    }
    g_waiting += std::chrono::duration<double>(Clock::now() - start).count();
}

void wait_requests(std::vector<MPI_Request>& requests, double timeout, const std::function<std::string()>& late) {
    if (requests.empty()) return;
    wait_until(
        [&] {
            int flag = 0;
            MPI_Testall(static_cast<int>(requests.size()), requests.data(), &flag, MPI_STATUSES_IGNORE);
            return flag != 0;
        },
        timeout, late);
}

void arrive(MPI_Comm comm, const std::string& point, int agreed) {
    int rank = 0, size = 1;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    if (size < 2) return;
    // A token to and from every other rank: N^2 messages of 4 bytes at a handful of points a
    // render, and unlike MPI_Ibarrier it tells who is missing. The token is `agreed`.
    std::vector<int> got(static_cast<size_t>(size), agreed);
    std::vector<MPI_Request> recv, send;
    std::vector<int> from;
    for (int r = 0; r < size; ++r) {
        if (r == rank) continue;
        recv.emplace_back();
        send.emplace_back();
        from.push_back(r);
        MPI_Irecv(&got[static_cast<size_t>(r)], 1, MPI_INT, r, kArriveTag, comm, &recv.back());
        MPI_Isend(&agreed, 1, MPI_INT, r, kArriveTag, comm, &send.back());
    }
    auto late = [&] {
        std::string who;
        for (size_t k = 0; k < recv.size(); ++k) {
            int flag = 0;
            if (recv[k] != MPI_REQUEST_NULL) MPI_Test(&recv[k], &flag, MPI_STATUS_IGNORE);
            if (recv[k] != MPI_REQUEST_NULL) who += (who.empty() ? "" : ", ") + std::to_string(world_rank_of(comm, from[k]));
        }
        return fmt::format("rank {} did not reach {}", who.empty() ? std::string("?") : who, point);
    };
    wait_requests(recv, rank_timeout(), late);
    wait_requests(send, rank_timeout(), [&] { return fmt::format("a rank took no token at {}", point); });
    for (int r = 0; r < size; ++r)
        if (got[static_cast<size_t>(r)] != agreed)
            end_all_ranks(fmt::format("crex run: internal error: ranks {} and {} computed different data for {} (a bug in crex: "
                                      "please report it with the command that caused it)\n",
                                      world_rank(), world_rank_of(comm, r), point),
                          kExitFailure);
}

#ifdef CREX_TEST_HOOKS
namespace {
// The test hook named by `variable` is for this rank, at this exchange of rows (a number, or
// `end`: the last, however many came before it).
bool hook_here(const char* variable, int exchange, bool last) {
    const char* rank = std::getenv(variable);
    if (!rank || std::atoi(rank) != world_rank()) return false;
    const char* at = std::getenv("CREX_TEST_FAULT_EXCHANGE");
    if (at && std::string(at) == "end") return last;
    return exchange == (at ? std::atoi(at) : 1);
}
}  // namespace
#endif

void fail_here_if_asked(int exchange, bool last) {
#ifdef CREX_TEST_HOOKS
    if (hook_here("CREX_TEST_FAIL_RANK", exchange, last)) throw std::runtime_error("test hook: this rank fails (CREX_TEST_FAIL_RANK)");
#else
    (void)exchange, (void)last;
#endif
}

void stall_here_if_asked(int exchange, bool last) {
#ifdef CREX_TEST_HOOKS
    static bool stalled = false;
    if (stalled || !hook_here("CREX_TEST_STALL_RANK", exchange, last)) return;
    stalled = true;
    std::raise(SIGSTOP);
#else
    (void)exchange, (void)last;
#endif
}

}  // namespace crex::distributed

#endif
