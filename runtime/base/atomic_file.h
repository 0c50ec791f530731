/// \file atomic_file.h
/// Writing outputs so that nothing is ever half-written: the bytes go to a temporary file in
/// the destination's directory, which is flushed and then renamed over the destination.
#pragma once

#include <functional>
#include <string>

namespace crex {

/// Writes `bytes` to `path` atomically. Returns an empty string on success, else the reason.
std::string write_file_atomically(const std::string& path, const std::string& bytes);

/// Lets `write_to(temp_path)` produce the file (e.g. an image writer that wants a path), then
/// renames it into place; removes the temporary file if writing fails.
std::string write_atomically_via(const std::string& path, const std::function<std::string(const std::string&)>& write_to);

}  // namespace crex
