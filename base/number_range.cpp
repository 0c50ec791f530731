#include "base/number_range.h"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

namespace crex {
namespace {

// 1e+30 -> 1e30, 1048576.000000 -> 1048576, 0.001 stays.
std::string plain(double v) {
    if (v == std::floor(v) && std::fabs(v) < 1e16) return fmt::format("{:.0f}", v);
    std::string s = fmt::format("{:g}", v);
    if (auto e = s.find("e+"); e != std::string::npos) s.erase(e + 1, 1);
    if (auto e = s.find("e0"); e != std::string::npos) s.erase(e + 1, 1);
    if (auto e = s.find("e-0"); e != std::string::npos) s.erase(e + 2, 1);
    return s;
}

std::string quoted(std::string_view text) {
    std::string out = "'";
    for (char c : text.substr(0, 40)) {
        unsigned char u = static_cast<unsigned char>(c);
        out += u < 0x20 || u == 0x7F ? '?' : c;
    }
    if (text.size() > 40) out += "...";
    return out + "'";
}

std::string with_range(const std::string& what, const NumberRange& range) {
    return fmt::format("{}: expected {}", what, describe(range));
}

}  // namespace

std::string describe(const NumberRange& range) {
    return fmt::format("{} from {} to {}", range.whole ? "a whole number" : "a number", plain(range.lo), plain(range.hi));
}

std::string number_range_error(double v, const NumberRange& range) {
    if (std::isnan(v)) return with_range("nan is not a number", range);
    if (std::isinf(v)) return with_range(fmt::format("{} is infinite", v < 0 ? "-inf" : "inf"), range);
    if (range.whole && v != std::floor(v)) return with_range(fmt::format("{} is not a whole number", plain(v)), range);
    if (v < range.lo || v > range.hi) return with_range(fmt::format("{} is out of range", plain(v)), range);
    return "";
}

std::optional<double> parse_number_text(std::string_view text) {
    std::string s(text);
    if (s.empty() || std::isspace(static_cast<unsigned char>(s.front()))) return std::nullopt;
    char* end = nullptr;
    double v = std::strtod(s.c_str(), &end);
    if (end != s.c_str() + s.size()) return std::nullopt;
    return v;
}

std::string number_text_error(std::string_view text, const NumberRange& range) {
    auto v = parse_number_text(text);
    if (!v) return with_range(fmt::format("{} is not a number", quoted(text)), range);
    if (std::isnan(*v)) return with_range(fmt::format("{} is not a number", quoted(text)), range);
    if (std::isinf(*v)) return with_range(fmt::format("{} is infinite", quoted(text)), range);
    if (range.whole) {
        // Digits are compared exactly: as a double, 9007199254740993 is 9007199254740992.
        std::string_view digits = text;
        const bool negative = digits.front() == '-';
        if (negative) digits.remove_prefix(1);
        const bool plain_digits = !digits.empty() && digits.find_first_not_of("0123456789") == std::string_view::npos;
        if (plain_digits) {
            uint64_t exact = 0;
            auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), exact);
            (void)end;
            bool in = ec == std::errc{};
            if (in && negative) in = exact == 0 || -static_cast<double>(exact) >= range.lo;
            if (in && !negative) in = static_cast<double>(exact) >= range.lo &&
                                      (range.hi >= 18446744073709551615.0 || exact <= static_cast<uint64_t>(range.hi));
            return in ? "" : with_range(fmt::format("{} is out of range", quoted(text)), range);
        }
        if (*v != std::floor(*v)) return with_range(fmt::format("{} is not a whole number", quoted(text)), range);
        // 1e3, 2.0, +2: whole numbers are written in plain digits, so that what is read is what is written.
        return with_range(fmt::format("{} is not written in plain digits", quoted(text)), range);
    }
    if (*v < range.lo || *v > range.hi) return with_range(fmt::format("{} is out of range", quoted(text)), range);
    return "";
}

}  // namespace crex
