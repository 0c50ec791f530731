/// \file library_files.h
/// The function files RADIANCE's own tools name in what they write, which RADIANCE finds in
/// its library directory: `source.cal` (ies2rad's luminaire distributions) and `illum.cal`
/// (mkillum's). crex carries its own definitions of them, written from their documented
/// meaning, so that such scenes load without a RADIANCE installation; a file of the same name
/// next to the scene or on RAYPATH is read instead.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace crex::radiance {

/// The built-in text of the function file `name`, or nullopt when crex has none.
std::optional<std::string> builtin_function_file(std::string_view name);

}  // namespace crex::radiance
