/// \file shared_inputs.h
/// A run's inputs on every process of a group (distributed rendering, issue 19): the lead alone
/// reads, checks and plans them, since on a cluster the input files may exist on its machine
/// only, and N processes reading them printed every diagnostic N times. The others get what it
/// read as data: the plan as its JSON (the kept-plan format, which the plan reader checks
/// again), the scene as its native JSON (meshes of OBJ files inline, the view already applied
/// to its camera), the profile and the cache file's bytes. Options stay as each process was
/// given them (every process of `mpirun` has the same command line).
#pragma once

#include <functional>

#include "runtime/api/run_inputs.h"
#include "runtime/driver/process_group.h"

namespace crex {

/// What `read` returns on the lead, on every process of `group`. `read` runs on the lead only:
/// it reads, says what is wrong and checks what the run needs (outputs writable, options that
/// resolve); its `status` (0: go on) is every process's. On the others the lead's inputs are
/// rebuilt from data; failing to is a bug, and ends every process. One process: just `read()`.
/// Collective; the others wait for the lead as long as the group lets them.
RunInputs share_run_inputs(ProcessGroup& group, const std::function<RunInputs()>& read);

}  // namespace crex
