/// \file input_file.h
/// Reading a file a user names, bounded: only regular files (or `-`, standard input) are read,
/// and at most a stated number of bytes. `/dev/zero` given as a plan read until memory ran out
/// ("internal error: std::bad_alloc"), and a FIFO with no writer hung `crex check` for ever.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace crex {

/// The languages' texts (crex, pipeline, plan, view, profile): far beyond any real one.
inline constexpr size_t kMaxTextInputBytes = size_t{64} << 20;
/// Scenes, meshes, irradiance caches, images: what a large scene may need, and under the 4 GiB
/// a SourceFile can address.
inline constexpr size_t kMaxDataInputBytes = size_t{1} << 30;

/// The whole file as bytes; nullopt with `error` set ("cannot read 'X': it is a character
/// device, not a file") if it is not a regular file, cannot be read, or holds more than
/// `limit` bytes. `-` reads standard input (up to `limit` bytes too).
std::optional<std::string> read_input_file(const std::string& path, std::string& error, size_t limit = kMaxTextInputBytes);

/// "" if `path` names a regular file of at most `limit` bytes that can be opened for reading,
/// else why not, as read_input_file says it. For readers that open the file themselves
/// (images through OpenImageIO). Opens without blocking, so a FIFO is refused, not waited on.
std::string check_input_file(const std::string& path, size_t limit = kMaxDataInputBytes);

/// "64 MiB", "1 GiB", "312 KiB" (for messages about sizes).
std::string byte_size_text(double bytes);

}  // namespace crex
