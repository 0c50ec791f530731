/// \file exit_codes.h
/// Exit codes shared by every subcommand (spec/pipeline.md §7).
#pragma once

namespace crex::app {

enum ExitCode : int {
    kExitOk = 0,        ///< success, or warnings only
    kExitInputErrors = 1,  ///< the input has errors (diagnostics on stderr)
    kExitUsage = 2,     ///< bad command line
    kExitFailure = 3,   ///< I/O or runtime failure
};

}  // namespace crex::app
