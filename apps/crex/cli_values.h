/// \file cli_values.h
/// Values the command line gives as text, parsed strictly (nothing trailing, ranges said).
#pragma once

#include <CLI/CLI.hpp>

#include <string>

#include "compiler/plan/pipeline_plan.h"
#include "runtime/api/frame_sequence.h"
#include "runtime/api/run_options.h"

namespace crex::app {

/// Every numeric flag's check (base/number_range.h): the whole text a number in [lo, hi];
/// NaN and infinities refused by name with the range. CLI::Range let NaN through.
CLI::Validator number_in(double lo, double hi);
/// The same for whole numbers, read exactly (`--star-cap -1` is out of range, not "Could not
/// convert"; 2^53 + 1 is not 2^53).
CLI::Validator whole_number_in(double lo, double hi);

/// A seed: a whole number from 0 to 2^53, as the pipeline language takes it (`--seed -1` and
/// `--seed 1e23` both became 2^64 - 1).
CLI::Validator seed_value();

/// "WIDTHxHEIGHT" with 1..16384 each, nothing else.
bool parse_image_size(const std::string& text, int& width, int& height);

/// --budget: "10s", "500ms" or "25%" (of the full render time in the profile); a unit is
/// required, and its range is the pipeline language's (settings_table.h). "" or what is wrong.
std::string parse_budget(const std::string& text, PlanBudget& budget);

/// --ambient: "auto", or a radiance from 0 to 1e30.
bool parse_ambient(const std::string& text, AmbientStandIn& ambient);

}  // namespace crex::app
