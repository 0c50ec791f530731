/// \file cli_values.h
/// Values the command line gives as text, parsed strictly (nothing trailing, ranges said).
#pragma once

#include <string>

namespace crex::app {

/// "WIDTHxHEIGHT" with 1..16384 each, nothing else.
bool parse_image_size(const std::string& text, int& width, int& height);

}  // namespace crex::app
