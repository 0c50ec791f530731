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

/// RADIANCE's local frame for the functions of plasfunc, metfunc and transfunc (what its
/// rayinit.cal defines for them): U and V across the surface from the last three real
/// arguments (an up vector), Ldx/Ldy/Ldz(x, y, z) a direction in (U, V, normal), and
/// Idx/Idy/Idz the direction back along the incoming ray.
const std::string& local_frame_definitions();

}  // namespace crex::radiance
