/// \file nearest_name.h
/// "did you mean ...?" for unknown names: the closest known name by edit distance, if close.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace crex {

size_t edit_distance(std::string_view a, std::string_view b);

/// "did you mean 'color'?", or "" when nothing is close enough (at most about a third of
/// the name's letters differ).
std::string did_you_mean(std::string_view name, const std::vector<std::string>& known);

}  // namespace crex
