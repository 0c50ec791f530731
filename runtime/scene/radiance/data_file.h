/// \file data_file.h
/// RADIANCE's data files (the tables of `brightdata`, `colordata` and the `*data` materials):
/// whitespace-separated numbers, `#` comments to the end of a line, in the layout
///
///     N                      dimensions
///     begin end count        per dimension: an even grid ...
///     0 0 count p1 .. pn     ... or its points listed
///     values ...             the last dimension varying fastest
#pragma once

#include <string>

#include "runtime/scene/scene.h"

namespace crex::radiance {

/// Where a data file went wrong: what, and the line and column (1-based) of the word.
struct DataFileError {
    std::string message;
    int line = 0, column = 0;
};

/// Parses `text` into `out`; false with `error` on a malformed file.
bool parse_data_file(const std::string& text, DataTable& out, DataFileError& error);

}  // namespace crex::radiance
