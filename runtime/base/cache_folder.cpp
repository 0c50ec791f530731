#include "runtime/base/cache_folder.h"

#include <cstdlib>
#include <filesystem>

namespace crex {

std::string crex_cache_folder() {
    namespace fs = std::filesystem;
    if (const char* c = std::getenv("CREX_CACHE"); c && *c) return c;
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return (fs::path(x) / "crex").string();
    const char* home = std::getenv("HOME");
    return (fs::path(home && *home ? home : ".") / ".cache" / "crex").string();
}

}  // namespace crex
