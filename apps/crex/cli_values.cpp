#include "apps/crex/cli_values.h"

#include <string>

#include "base/number_range.h"

namespace crex::app {
namespace {

CLI::Validator ranged(NumberRange range) {
    std::string what = describe(range);
    return CLI::Validator([range](std::string& text) { return number_text_error(text, range); },
                          what.substr(what.find(' ') + 1),  // "number from 0 to 1" after the option's type
                          "number_in");
}

}  // namespace

CLI::Validator number_in(double lo, double hi) { return ranged({lo, hi, false}); }
CLI::Validator whole_number_in(double lo, double hi) { return ranged({lo, hi, true}); }

CLI::Validator seed_value() { return ranged({0, 9007199254740992.0, true}); }

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
