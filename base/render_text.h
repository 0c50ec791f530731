/// \file render_text.h
/// Diagnostics as a C compiler prints them:
///
///     file:line:col: error[E004]: message
///        14 |     crex "{TTD*}2"
///           |               ^
///     file:line:col: note: the importance-modulated group opens here
///     ...
///           = help: suggested fix
#pragma once

#include <string>
#include <vector>

#include "base/diagnostic.h"

namespace crex {

std::string render_text(const Diagnostic& d);

/// Each of `ds` in turn, but a warning code's first kWarningsShownPerCode only, then one line
/// saying how many more there are (errors and notes are all shown).
inline constexpr size_t kWarningsShownPerCode = 5;
std::string render_text(const std::vector<Diagnostic>& ds);

/// "file:line:col" of the span's start ("<unknown>" without a file).
std::string format_location(const SourceSpan& span);

/// `text` safe for a terminal: control characters (ESC of a binary file quoted in a message
/// would drive the terminal) as \xHH; tab, and UTF-8, as they are.
std::string printable(std::string_view text);

}  // namespace crex
