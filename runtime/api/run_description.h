/// \file run_description.h
/// What a run will do, said before it starts (`crex run -v`): the inputs as read, the plan,
/// and the settings in effect, with where the plan set a limit an option did not override.
#pragma once

#include <string>

#include "runtime/api/run_inputs.h"
#include "runtime/api/run_options.h"

namespace crex {

/// The settings that decide each pixel's value, as "size 64x64, spp 4, filter box, ...": what
/// a partial image records of its run (resume.h) and `crex run -v` says.
std::string pixel_settings_text(const RunSettings& settings);

/// Lines "PREFIXwhat: ...", one a topic (scene, plan, pixels, cache, budget, limits, threads,
/// memory), each ending in a newline.
std::string describe_run(const RunInputs& in, const ResolvedRun& run, int threads, const std::string& prefix = "");

}  // namespace crex
