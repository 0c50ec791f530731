#include "runtime/base/memory.h"

#include <fstream>
#include <sstream>

namespace crex {

std::optional<size_t> memory_available_bytes(const std::string& meminfo) {
    std::istringstream in(meminfo);
    std::string key, unit;
    unsigned long long kb = 0;
    std::optional<unsigned long long> available, swap;
    while (in >> key >> kb) {
        std::getline(in, unit);  // " kB"
        if (key == "MemAvailable:") available = kb;
        else if (key == "SwapFree:") swap = kb;
    }
    if (!available) return std::nullopt;  // kernels before 3.14 do not say it
    return static_cast<size_t>((*available + swap.value_or(0)) * 1024ull);
}

std::optional<size_t> memory_available_bytes() {
    std::ifstream f("/proc/meminfo");
    if (!f) return std::nullopt;
    std::stringstream text;
    text << f.rdbuf();
    return memory_available_bytes(text.str());
}

}  // namespace crex
