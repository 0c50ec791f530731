/// \file input_files.h
/// Reading user inputs for the CLI: a path, or `-` for standard input.
#pragma once

#include <optional>
#include <string>

namespace crex::app {

/// The whole file as bytes; nullopt with `error` set if it cannot be read.
std::optional<std::string> read_input(const std::string& path, std::string& error);

}  // namespace crex::app
