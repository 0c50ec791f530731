#include "apps/crex/cli_values.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "base/number_range.h"
#include "compiler/pipeline/settings_table.h"

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

std::string parse_budget(const std::string& text, PlanBudget& budget) {
    std::string t = text;
    budget = {};
    double scale = 1;
    const std::string expected = "expected a time with its unit, e.g. 10s, 500ms or 25%";  // as in the pipeline language
    if (t.size() > 2 && t.substr(t.size() - 2) == "ms") t.resize(t.size() - 2), scale = 1e-3;
    else if (!t.empty() && t.back() == 's') t.pop_back();
    else if (!t.empty() && t.back() == '%') t.pop_back(), budget.percent = true;
    else return expected;
    auto v = parse_number_text(t);
    if (!v) return expected;
    budget.amount = *v * scale;
    if (std::string range = pipeline::budget_range_error(budget.amount, budget.percent); !range.empty())
        return fmt::format("{}: expected {}", std::isnan(budget.amount)   ? "nan is not a number"
                                              : std::isinf(budget.amount) ? "it is infinite"
                                                                          : "out of range",
                           range);
    return "";
}

bool parse_ambient(const std::string& text, AmbientStandIn& ambient) {
    ambient = {};
    if (text == "auto") {
        ambient.automatic = true;
        return true;
    }
    try {
        size_t used = 0;
        ambient.value = std::stod(text, &used);
        return used == text.size() && std::isfinite(ambient.value) && ambient.value >= 0 && ambient.value <= 1e30;
    } catch (const std::exception&) {
        return false;
    }
}

}  // namespace crex::app
