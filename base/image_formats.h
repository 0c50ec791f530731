/// \file image_formats.h
/// The image files crex writes, told by their extension: one list for `-o`, a pipeline's
/// `output { image ... }` and the Python module, so none of them accepts a name another refuses.
#pragma once

#include <string>
#include <string_view>

namespace crex {

/// True when `path` ends in an extension crex writes images to (.exr, .png, ..., any case).
bool is_image_file_name(std::string_view path);

/// The path's extension, lower case ("" when it has none): what the format is told by.
std::string image_extension(std::string_view path);

/// The formats, as said in an error: ".exr (float), .hdr, .png, ...".
std::string_view image_formats_text();

}  // namespace crex
