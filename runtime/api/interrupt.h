/// \file interrupt.h
/// Ctrl-C during a render (`crex run`, or a program of its own): the first SIGINT asks the
/// render to stop once the pass in flight is done (ConsoleProgress::stop_requested), so the
/// image so far can be written; a second ends the process at once.
#pragma once

namespace crex {

/// What a tool exits with after writing the image so far: 128 + SIGINT, as a shell reports
/// a program Ctrl-C ended.
inline constexpr int kExitInterrupted = 130;

/// Installs the SIGINT handler (one process: a distributed run keeps its own, stop_signals.h).
void catch_interrupt();

/// Has SIGINT arrived since catch_interrupt()?
bool interrupted();

}  // namespace crex
