/// \file exit_codes.h
/// Exit codes of every `crex` subcommand (spec/pipeline.md §7); also what a distributed run
/// ends every process with when one fails (runtime/distributed/).
#pragma once

namespace crex {

enum ExitCode : int {
    kExitOk = 0,        ///< success, or warnings only
    kExitInputErrors = 1,  ///< the input has errors (diagnostics on stderr)
    kExitUsage = 2,     ///< bad command line
    kExitFailure = 3,   ///< I/O or runtime failure
};

}  // namespace crex
