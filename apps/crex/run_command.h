/// \file run_command.h
/// What `crex run` does with its flags: they become the library's typed inputs, options and
/// files (runtime/api/), then it reads, checks, renders and writes as the library says, and says
/// what happened: diagnostics, notes and the summary, with the exit status.
#pragma once

#include "apps/crex/run_flags.h"

namespace crex::app {

/// Returns the exit status (base/exit_codes.h).
int run_command(const RunFlags& flags);

}  // namespace crex::app
