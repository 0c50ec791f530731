#include "runtime/base/output_folder.h"

#include <filesystem>

namespace crex {
namespace fs = std::filesystem;

namespace {

// "report/" names the folder "report": its folder is the one above.
fs::path folder_of(const std::string& path) {
    fs::path p(path);
    if (p.filename().empty()) p = p.parent_path();
    return p.parent_path();
}

}  // namespace

std::string missing_output_folder(const std::string& path) {
    const fs::path dir = folder_of(path);
    if (dir.empty()) return "";
    std::error_code ec;
    if (fs::is_directory(dir, ec)) return "";
    if (fs::exists(dir, ec)) return "cannot write '" + path + "': '" + dir.string() + "' is not a folder";
    return "cannot write '" + path + "': its folder '" + dir.string() + "' does not exist";
}

std::string make_output_folder(const std::string& path) {
    const fs::path dir = folder_of(path);
    if (dir.empty()) return "";
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) return "cannot make the folder '" + dir.string() + "' for '" + path + "': " + ec.message();
    return "";
}

}  // namespace crex
