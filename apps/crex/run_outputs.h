/// \file run_outputs.h
/// What `crex run` leaves behind once the driver is done: the images (every -o), the profile,
/// the maps and pictures, the report with its error curve, and the summary on stdout.
#pragma once

#include "apps/crex/run_input.h"
#include "apps/crex/run_options.h"
#include "apps/crex/run_setup.h"
#include "runtime/driver/run_plan.h"
#include "runtime/report/checkpoints.h"

namespace crex::app {

/// The checkpoints of the same render under another budget policy (--compare-policies).
using PolicyRun = std::pair<std::string, std::vector<Checkpoint>>;

/// Returns the exit code of the run.
int write_run_outputs(const RunOptions& opt, const RunInput& in, const RunSetup& setup, const RunResult& result,
                      const CheckpointRecorder* recorder, const std::vector<PolicyRun>& other_policies = {});

}  // namespace crex::app
