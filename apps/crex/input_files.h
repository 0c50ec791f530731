/// \file input_files.h
/// Reading user inputs for the CLI: a path, or `-` for standard input, bounded
/// (base/input_file.h); and telling a file given to the wrong command what it holds.
#pragma once

#include <optional>
#include <string>

namespace crex::app {

/// The whole file as bytes; nullopt with `error` set if it cannot be read.
std::optional<std::string> read_input(const std::string& path, std::string& error);

/// What a file holds when it is not what the command reads, from its name and text: "a plan"
/// (the JSON of 'crex plan --format json'), "a scene" (.rad, .obj, .mtl, .vf, or JSON with
/// shapes), or "" when it is neither (then the command's own reader says what is wrong).
std::string input_kind(const std::string& path, const std::string& text);

}  // namespace crex::app
