/// \file fnv1a.h
/// FNV-1a, 64 bit: a content hash that is the same on every platform and run (std::hash is
/// not), for the census of a scene, a scene's content and a plan's identity in a header.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace crex {

inline constexpr uint64_t kFnv1aOffset = 0xcbf29ce484222325ull;

/// `h` continues an earlier hash, so several pieces hash as one.
inline uint64_t fnv1a64(std::string_view bytes, uint64_t h = kFnv1aOffset) {
    for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ull;
    return h;
}

/// 16 lower-case hex digits.
inline std::string hex16(uint64_t h) {
    std::string out(16, '0');
    for (int i = 15; i >= 0; --i, h >>= 4) out[static_cast<size_t>(i)] = "0123456789abcdef"[h & 0xF];
    return out;
}

}  // namespace crex
