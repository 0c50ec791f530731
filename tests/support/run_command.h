/// \file run_command.h
/// Runs a program with arguments (no shell), feeding `input` on stdin, and captures its
/// exit code, stdout and stderr. For CLI tests.
#pragma once

#include <string>
#include <vector>

namespace crex::testing {

struct CommandResult {
    int exit_code = -1;  ///< -1 if it did not exit normally (signal)
    std::string out;
    std::string err;
};

CommandResult run_command(const std::vector<std::string>& argv, const std::string& input = "");

}  // namespace crex::testing
