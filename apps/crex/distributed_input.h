/// \file distributed_input.h
/// Under mpirun, rank 0 alone reads, checks and plans (issue 19): on a cluster the input files
/// may exist on rank 0's machine only, and N ranks reading them printed every diagnostic N
/// times. The other ranks get what rank 0 read as data: the plan as its JSON (the kept-plan
/// format, which the plan reader checks again), the scene as its native JSON (meshes of OBJ
/// files inline; --view already applied to its camera), the --profile's contents and the
/// --ic-file's bytes. Command-line options are parsed by every rank alike and stay as they are.
/// Rank 0 alone writes files: the outputs (-o, --maps, --save-profile) and --ic-file (under
/// --ic-share component the first PA rank, which holds the records, sends them to rank 0).
#pragma once

#include <optional>

#include "apps/crex/run_input.h"
#include "apps/crex/run_options.h"
#include "apps/crex/run_setup.h"

namespace crex::app {

/// Fills `in` and `setup` as read_run_input() and make_run_setup() do. Not under mpirun:
/// exactly those. Under mpirun, rank 0 runs them (diagnostics printed once, with their
/// locations), refuses what a distributed run cannot do yet, and sends every other rank either
/// its exit code or the data above; every rank then returns the same exit code, or none.
/// Collective under mpirun; the other ranks wait at most --rank-timeout for rank 0.
std::optional<int> read_run_input_on_rank0(RunOptions& opt, RunInput& in, RunSetup& setup);

}  // namespace crex::app
