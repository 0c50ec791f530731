#include "apps/crex/input_files.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace crex::app {

std::optional<std::string> read_input(const std::string& path, std::string& error) {
    std::ostringstream buffer;
    if (path == "-") {
        buffer << std::cin.rdbuf();
        return buffer.str();
    }
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
        error = "cannot read '" + path + "': it is a directory";
        return std::nullopt;
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = "cannot read '" + path + "': " + std::strerror(errno);
        return std::nullopt;
    }
    buffer << in.rdbuf();
    if (in.bad()) {
        error = "cannot read '" + path + "': read failed";
        return std::nullopt;
    }
    return buffer.str();
}

}  // namespace crex::app
