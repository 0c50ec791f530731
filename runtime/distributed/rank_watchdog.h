/// \file rank_watchdog.h
/// Bounded waits between ranks under mpirun (issue 19): a rank that hangs (stopped, stuck in a
/// loop, its machine gone quiet) must end the run within a bounded time with an error naming
/// it, not leave the others blocked in MPI forever. Open MPI itself aborts the job when a rank
/// dies, but a stopped rank is alive to it. So every wait for another rank here is a
/// non-blocking operation polled against a deadline (--rank-timeout): on expiry the waiting
/// rank prints `crex run: error: rank K did not reach <point> within S s` and ends the run
/// (end_all_ranks below: rank 0 writes its finished rows, then MPI_Abort), and mpirun ends every
/// rank (SIGCONT and, a second later, SIGTERM, then SIGKILL, which a stopped process cannot
/// ignore). A rank that dies is seen by mpirun itself, which ends the others the same way:
/// rank 0 writes its finished rows on that SIGTERM (stop_signals.h).
/// Polling with short sleeps has a second purpose: a rank blocked in MPI_Recv spins at 100 %
/// of a core in Open MPI, which on a machine with fewer cores than ranks takes the core from
/// the rank doing the work; a sleeping poll gives it back. The seconds spent waiting are the
/// rank's idle time.
/// A fault found on any rank ends the run through end_all_ranks(): before the job is aborted,
/// rank 0 (which holds the image) writes the rows it finished (distributed_partial.h). A rank
/// other than 0 therefore reports its fault to rank 0 first and gives it a moment to do so;
/// rank 0 picks such reports up in every wait here.
#pragma once

namespace crex::distributed {
/// Seconds a rank waits for another before the run is aborted (--rank-timeout).
void set_rank_timeout(double seconds);
double rank_timeout();
}  // namespace crex::distributed

#ifdef CREX_WITH_MPI
#include <mpi.h>

#include <functional>
#include <string>
#include <vector>

namespace crex::distributed {

/// Seconds this process has waited for other ranks so far.
double seconds_waiting();

/// Polls `done` (a non-blocking MPI test) until it returns true. After `timeout` seconds
/// `late()` names who was waited for and what they did not do (e.g. "rank 2 did not reach the
/// end of the render"), which is printed with the timeout before MPI_Abort. `serve_while_waiting`,
/// when set, runs between polls (rank 0 of --ic-share central forwards records meanwhile).
void wait_until(const std::function<bool()>& done, double timeout, const std::function<std::string()>& late);

/// Completes `requests` (wait_until on MPI_Testall).
void wait_requests(std::vector<MPI_Request>& requests, double timeout, const std::function<std::string()>& late);

/// Work to do while this rank waits for others (nullptr: none).
void set_serve_while_waiting(std::function<void()> serve);

/// Prints `message` and ends every rank with `exit_code`, rank 0 writing the rows it finished
/// first (set_fault_writer). On a rank other than 0: reports to rank 0 and waits a bounded
/// time for rank 0 to end the job (it polls in its waits); if it does not (it hung, died or is
/// still rendering), says so and aborts itself; mpirun then continues a stopped rank 0 and
/// sends it SIGTERM, on which it still writes its finished rows (distributed_partial.h), unless
/// it is dead. Does not return.
[[noreturn]] void end_all_ranks(const std::string& message, int exit_code);

/// Rank 0: what to do before the job is aborted on a fault (write the finished rows); it
/// says on stderr what it wrote. Runs at most once.
void set_fault_writer(std::function<void()> writer);

/// Every rank of `comm` says it reached `point` (its name in the error); returns once all
/// have, else aborts naming the ranks (of MPI_COMM_WORLD) that did not arrive in time. The
/// collective that follows then finds every rank in it. `agreed`: what every rank must bring
/// (data each computed alike, e.g. a fingerprint of the bands of rows the collective's counts
/// come from); a rank that brings another ends the run as an internal error.
void arrive(MPI_Comm comm, const std::string& point, int agreed = 0);

/// Tests only: with CREX_TEST_HOOKS compiled in (builds with CREX_TESTS) and the environment
/// variable CREX_TEST_STALL_RANK equal to this process's world rank, the first call at
/// exchange no. CREX_TEST_FAULT_EXCHANGE (default 1; `exchange` is the caller's count; `end`:
/// the call whose `last` is true) stops the process (SIGSTOP), as a hung rank would be.
void stall_here_if_asked(int exchange = 1, bool last = false);
/// Tests only, likewise: CREX_TEST_FAIL_RANK equal to this rank throws (a render that fails).
void fail_here_if_asked(int exchange = 1, bool last = false);

}  // namespace crex::distributed

#endif
