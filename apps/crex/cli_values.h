/// \file cli_values.h
/// Values the command line gives as text, parsed strictly (nothing trailing, ranges said).
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace crex::app {

/// A seed: a whole number from 0 to 2^53, as the pipeline language takes it (`--seed -1` and
/// `--seed 1e23` both became 2^64 - 1).
CLI::Validator seed_value();

/// "WIDTHxHEIGHT" with 1..16384 each, nothing else.
bool parse_image_size(const std::string& text, int& width, int& height);

}  // namespace crex::app
