/// \file stop_signals.h
/// SIGTERM, SIGINT and SIGHUP taken by one ordinary thread instead of a signal handler
/// (issue 19). When a rank dies, mpirun ends the others with SIGCONT and SIGTERM, then SIGKILL
/// a second later (Open MPI's odls_base_sigkill_timeout); rank 0 uses that second to write the
/// rows it finished (distributed_partial.h). Writing an image takes locks and allocates, which
/// a signal handler may not do, so the signals are blocked in every thread and one thread
/// waits for them with sigwait: whatever it runs is ordinary code.
#pragma once

namespace crex::distributed {

/// Blocks SIGTERM, SIGINT and SIGHUP in the calling thread and starts one thread that waits
/// for them. Call it before any other thread exists (first in main, before MPI_Init, TBB or
/// OpenEXR start theirs): threads inherit the mask, and a signal sent to the process goes to
/// a thread that does not block it, which must be that one. On a signal `on_stop(signal)` runs
/// on that thread; if it returns, the signal takes its default action (the process ends by
/// it, as it would without any of this). At most one call.
void take_stop_signals(void (*on_stop)(int signal));

}  // namespace crex::distributed
