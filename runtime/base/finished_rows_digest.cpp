#include "runtime/base/finished_rows_digest.h"

#include <cstdint>
#include <cstdio>
#include <cstring>

namespace crex {

std::string finished_rows_digest(const std::vector<float>& rgb, int width, const std::vector<char>& rows) {
    uint64_t h = 1469598103934665603ull;
    const size_t row = 3 * static_cast<size_t>(width);
    for (size_t r = 0; r < rows.size(); ++r) {
        if (!rows[r] || (r + 1) * row > rgb.size()) continue;
        for (size_t i = r * row; i < (r + 1) * row; ++i) {
            uint32_t bits = 0;
            std::memcpy(&bits, &rgb[i], sizeof bits);
            for (int b = 0; b < 4; ++b) h = (h ^ ((bits >> (8 * b)) & 0xFFu)) * 1099511628211ull;
        }
    }
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

}  // namespace crex
