#include "apps/crex/rank_watchdog.h"

namespace crex::app {
namespace {
double g_timeout = 600;
}
void set_rank_timeout(double seconds) { g_timeout = seconds; }
double rank_timeout() { return g_timeout; }
}  // namespace crex::app

#ifdef CREX_WITH_MPI

#include <fmt/format.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <thread>

#include "apps/crex/exit_codes.h"

namespace crex::app {
namespace {

using Clock = std::chrono::steady_clock;

double g_waiting = 0;
std::function<void()> g_serve;
bool g_serving = false;  // serve_while_waiting does not run inside itself

constexpr int kArriveTag = 7301;

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
void set_serve_while_waiting(std::function<void()> serve) { g_serve = std::move(serve); }

void wait_until(const std::function<bool()>& done, double timeout, const std::function<std::string()>& late) {
    const auto start = Clock::now();
    // Short sleeps that grow to 1 ms: a message answered within microseconds costs little
    // latency, and a long wait costs no core.
    std::chrono::microseconds nap(5);
    while (!done()) {
        const double waited = std::chrono::duration<double>(Clock::now() - start).count();
        if (waited > timeout) {
            int rank = 0;
            MPI_Comm_rank(MPI_COMM_WORLD, &rank);
            std::cerr << fmt::format("crex run: error: {} within {:g} s (rank {} waited; --rank-timeout)\n", late(), timeout, rank)
                      << std::flush;
            MPI_Abort(MPI_COMM_WORLD, kExitFailure);
            std::_Exit(kExitFailure);  // MPI_Abort does not return; should it, nothing may carry on
        }
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

void arrive(MPI_Comm comm, const std::string& point) {
    int rank = 0, size = 1;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    if (size < 2) return;
    // A token to and from every other rank: N^2 messages of 4 bytes at a handful of points a
    // render, and unlike MPI_Ibarrier it tells who is missing.
    static int sequence = 0;
    ++sequence;
    std::vector<int> got(static_cast<size_t>(size), 0);
    std::vector<MPI_Request> recv, send;
    std::vector<int> from;
    for (int r = 0; r < size; ++r) {
        if (r == rank) continue;
        recv.emplace_back();
        send.emplace_back();
        from.push_back(r);
        MPI_Irecv(&got[static_cast<size_t>(r)], 1, MPI_INT, r, kArriveTag, comm, &recv.back());
        MPI_Isend(&sequence, 1, MPI_INT, r, kArriveTag, comm, &send.back());
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
}

void stall_here_if_asked() {
#ifdef CREX_TEST_HOOKS
    static bool stalled = false;
    const char* env = std::getenv("CREX_TEST_STALL_RANK");
    if (stalled || !env) return;
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (std::atoi(env) != rank) return;
    stalled = true;
    std::raise(SIGSTOP);
#endif
}

}  // namespace crex::app

#endif
