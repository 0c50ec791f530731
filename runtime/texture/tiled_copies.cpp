#include "runtime/texture/tiled_copies.h"

#include <fmt/format.h>

#include <cctype>
#include <filesystem>

#include "base/fnv1a.h"
#include "runtime/base/cache_folder.h"

namespace crex {

std::string tiled_copy_path(const std::string& file) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path absolute = fs::absolute(file, ec);
    if (ec) return "";
    const auto size = fs::file_size(absolute, ec);
    if (ec) return "";
    const auto time = fs::last_write_time(absolute, ec);
    if (ec) return "";
    const std::string identity = fmt::format("{}\n{}\n{}\ntiled copy v1", absolute.lexically_normal().string(), size,
                                             static_cast<long long>(time.time_since_epoch().count()));
    // The file's own name first (its letters, digits, - and _), so a person can tell the copies apart.
    std::string stem;
    for (char c : absolute.stem().string())
        if (stem.size() < 40) stem += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
    return (fs::path(crex_cache_folder()) / "textures" / fmt::format("{}-{}.tx", stem, hex16(fnv1a64(identity)))).string();
}

}  // namespace crex
