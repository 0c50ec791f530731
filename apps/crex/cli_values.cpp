#include "apps/crex/cli_values.h"

#include <cstdint>
#include <string>

namespace crex::app {

CLI::Validator seed_value() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            bool digits = !text.empty() && text.size() <= 16 && text.find_first_not_of("0123456789") == std::string::npos;
            if (digits && std::stoull(text) <= (uint64_t{1} << 53)) return "";
            return "'" + text + "' is not a whole number from 0 to 9007199254740992";
        },
        "SEED");
}

bool parse_image_size(const std::string& text, int& width, int& height) {
    size_t x = text.find_first_of("xX");
    if (x == std::string::npos || x == 0 || x + 1 == text.size()) return false;
    auto whole = [](const std::string& s, int& v) {
        if (s.empty() || s.size() > 6 || s.find_first_not_of("0123456789") != std::string::npos) return false;
        v = std::stoi(s);
        return v >= 1 && v <= 16384;
    };
    return whole(text.substr(0, x), width) && whole(text.substr(x + 1), height);
}

}  // namespace crex::app
