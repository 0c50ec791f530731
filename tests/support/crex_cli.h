/// \file crex_cli.h
/// Runs the `crex` binary under test (CLI tests only: CREX_BINARY is set for them).
#pragma once

#include <string>
#include <vector>

#include "tests/support/run_command.h"

namespace crex::testing {

inline CommandResult crex_cli(std::vector<std::string> args, const std::string& input = "") {
    args.insert(args.begin(), CREX_BINARY);
    return run_command(args, input);
}

}  // namespace crex::testing
