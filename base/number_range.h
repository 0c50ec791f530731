/// \file number_range.h
/// The one check of a number a user gives: on the command line, in a pipeline file, in a plan
/// JSON. NaN and infinities are named as such (NaN passes every `v < lo || v > hi` test, so a
/// range check alone let `--lw nan` run for ever), whole numbers are read exactly (2^53 + 1 must
/// not become 2^53), and every refusal says the range.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace crex {

struct NumberRange {
    double lo = 0;
    double hi = 0;
    bool whole = false;  ///< integers only, read exactly from text
};

/// "a number from 0 to 1", "a whole number from 1 to 1024" (ends as people write them:
/// 1e+30 as 1e30, 1048576 in full).
std::string describe(const NumberRange& range);

/// "" when `v` is in the range, else why not: "nan is not a number: expected a number from 0
/// to 1", "inf is infinite: ...", "2 is out of range: ...", "1.5 is not a whole number: ...".
std::string number_range_error(double v, const NumberRange& range);

/// The same for a number as text (a flag's value, a literal as written): the whole text must be
/// the number. A whole number's digits are compared exactly, not as a double. Quotes the text.
std::string number_text_error(std::string_view text, const NumberRange& range);

/// The value of text that passed number_text_error.
std::optional<double> parse_number_text(std::string_view text);

}  // namespace crex
