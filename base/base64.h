/// \file base64.h
/// Base64 (RFC 4648, with padding): images inside report pages, and images carried inside
/// scene files (glTF data URIs, the native JSON's "images").
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace crex {

std::string base64(const std::string& bytes);

/// The bytes of `text`, or nullopt when it is not base64 (whitespace is skipped; padding is
/// optional).
std::optional<std::string> base64_decode(std::string_view text);

}  // namespace crex
