#include "runtime/texture/tiled_copies.h"

#include <fmt/format.h>

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <signal.h>
#include <unistd.h>

#include "base/fnv1a.h"
#include "runtime/base/cache_folder.h"
#include "runtime/base/image_signature.h"

namespace crex {

namespace {

// textures/NAME-KEY.tx: the name's letters, digits, - and _ first, so a person can tell the copies apart.
std::string copy_path(const std::string& name, uint64_t key) {
    std::string stem;
    for (char c : name)
        if (stem.size() < 40) stem += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
    return (std::filesystem::path(crex_cache_folder()) / "textures" / fmt::format("{}-{}.tx", stem, hex16(key))).string();
}

}  // namespace

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
    return copy_path(absolute.stem().string(), fnv1a64(identity));
}

std::string embedded_tiled_copy_path(const std::string& name, const std::string& bytes) {
    return copy_path(std::filesystem::path(name).filename().string(), fnv1a64(bytes, fnv1a64("embedded tiled copy v1\n")));
}

void remove_stale_temporaries(const std::string& copy) {
    namespace fs = std::filesystem;
    const std::string prefix = fs::path(copy).filename().string() + ".";
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(fs::path(copy).parent_path(), ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(prefix, 0) != 0) continue;
        // NAME-KEY.tx.PID.part, .PID.levelN or .PID.source...: the maker's process id first.
        const std::string rest = name.substr(prefix.size());
        char* end = nullptr;
        const long pid = std::strtol(rest.c_str(), &end, 10);
        if (pid <= 0 || end == rest.c_str() || *end != '.') continue;
        if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // its maker still runs
        fs::remove(entry.path(), ec);
    }
}

std::string write_embedded_source(const std::string& copy, const std::string& bytes, std::string& error) {
    const std::string path = fmt::format("{}.{}.source{}", copy, ::getpid(), image_extension_of(bytes));
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
        error = "cannot write " + path;
        std::error_code ec;
        std::filesystem::remove(path, ec);
        return "";
    }
    return path;
}

}  // namespace crex
