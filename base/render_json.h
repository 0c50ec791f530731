/// \file render_json.h
/// Diagnostics for tools (`--format json`): one object per diagnostic with
/// {file, line, col, end_line, end_col, code, severity, message, notes, help}; a run's
/// diagnostics have "file": null and say "where" instead.
/// Lines and columns are 1-based, columns in code points; end_col is one past the span.
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "base/diagnostic.h"

namespace crex {

nlohmann::json to_json(const Diagnostic& d);
nlohmann::json to_json(const std::vector<Diagnostic>& ds);

}  // namespace crex
