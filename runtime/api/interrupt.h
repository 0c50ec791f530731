/// \file interrupt.h
/// Ctrl-C (SIGINT) or SIGTERM during a render (`crex run`, or a program of its own): the first
/// asks the render to stop once the pass in flight is done (ConsoleProgress::stop_requested), so
/// the image so far can be written; a second ends the process at once. SIGTERM is what `kill`
/// and a batch scheduler reaching a job's time limit send before they kill it outright.
#pragma once

namespace crex {

/// Installs the handler of SIGINT and SIGTERM (one process: a distributed run keeps its own,
/// stop_signals.h).
void catch_interrupt();

/// Has SIGINT or SIGTERM arrived since catch_interrupt()?
bool interrupted();

/// What a tool exits with after writing the image so far: 128 + the signal, as a shell reports
/// a program the signal ended (130 for Ctrl-C, 143 for SIGTERM).
int interrupted_exit_code();

}  // namespace crex
