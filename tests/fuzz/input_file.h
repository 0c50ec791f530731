// The fuzzer's input as a file, for readers that take a path (images): one file a process,
// rewritten at every run.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

namespace crex::fuzz {

/// Writes the input to /tmp/crex_NAME_PID (NAME with its extension, which readers may go by)
/// and returns that path.
inline std::string input_file(const uint8_t* data, size_t size, const std::string& name) {
    const std::string path = "/tmp/crex_" + std::to_string(::getpid()) + "_" + name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    return path;
}

}  // namespace crex::fuzz
