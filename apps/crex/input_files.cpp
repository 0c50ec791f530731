#include "apps/crex/input_files.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "base/input_file.h"

namespace crex::app {

std::optional<std::string> read_input(const std::string& path, std::string& error) { return read_input_file(path, error, kMaxTextInputBytes); }

std::string input_kind(const std::string& path, const std::string& text) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".rad" || ext == ".obj" || ext == ".mtl") return "a scene";
    if (ext == ".vf") return "a RADIANCE view file";
    const size_t first = text.find_first_not_of(" \t\r\n");
    if (first == std::string::npos || text[first] != '{') return "";
    const auto j = nlohmann::json::parse(text, nullptr, false);
    if (!j.is_object()) return "";
    if (j.contains("format") && j["format"] == "crex-plan") return "a plan";
    if (j.contains("format") && j["format"] == "crex-profile") return "a profile";
    if (j.contains("shapes") || j.contains("materials")) return "a scene";
    return "";
}

}  // namespace crex::app
