#include "apps/crex/cli_values.h"

#include <string>

namespace crex::app {

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
