/// \file file_extension.h
/// A file name's extension in lower case (".EXR" -> ".exr"): what readers and writers choose
/// a format by.
#pragma once

#include <cctype>
#include <filesystem>
#include <string>

namespace crex {

inline std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

}  // namespace crex
