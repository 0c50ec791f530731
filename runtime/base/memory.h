/// \file memory.h
/// How much memory this machine can still give a process: what a render that cannot fit is
/// refused by, before it allocates (an allocation the kernel overcommits is not refused: the
/// process is killed later, or another one is).
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace crex {

/// MemAvailable plus SwapFree of /proc/meminfo, in bytes; nullopt where that file cannot be
/// read (not Linux): then nothing is refused.
std::optional<size_t> memory_available_bytes();

/// The same from the text of a /proc/meminfo (values in kB), for tests.
std::optional<size_t> memory_available_bytes(const std::string& meminfo);

}  // namespace crex
