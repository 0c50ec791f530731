/// \file sky_generators.h
/// gensky, built in: the sun and the sky it would print for a date, time and
/// place, as primitives (a `light` sun `source`, and the sky's `brightfunc` with the numbers
/// of RADIANCE's own sky model, which crex evaluates natively).
#pragma once

#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "runtime/scene/radiance/command_line.h"
#include "runtime/scene/radiance/scene_text.h"

namespace crex::radiance {

bool is_sky_generator(const std::string& name);
bool run_sky_generator(const CommandWords& argv, std::vector<Primitive>& out, DiagnosticSink& sink);

}  // namespace crex::radiance
