/// \file read_plan.h
/// Reading a plan written by plan_to_json() back, so a compiled plan can be kept and run
/// later (`crex run plan.json`). Every field is checked; errors (E401) point at file, line and
/// column through the positioned JSON reader.
#pragma once

#include <optional>

#include "base/diagnostic.h"
#include "compiler/plan/emit_plan.h"

namespace crex {

std::optional<CrexPlan> read_plan(const SourceFile& file, DiagnosticSink& sink);

}  // namespace crex
