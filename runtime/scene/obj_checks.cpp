#include "runtime/scene/obj_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string_view>

#include "base/render_text.h"

namespace crex {
namespace {

struct Word {
    std::string_view text;
    uint32_t begin = 0;
};

// The words of line `line` of `file`, `#` comments dropped, into `out` (one vector for all of
// a file's lines: a vector a line was a malloc per line of a 100 MB OBJ).
void words_of(const SourceFile& file, uint32_t line, std::vector<Word>& out) {
    std::string_view t = file.line_text(line);
    if (auto hash = t.find('#'); hash != std::string_view::npos) t = t.substr(0, hash);
    const uint32_t start = file.line_start(line);
    out.clear();
    size_t i = 0;
    while (i < t.size()) {
        while (i < t.size() && (t[i] == ' ' || t[i] == '\t' || t[i] == '\r')) ++i;
        size_t b = i;
        while (i < t.size() && t[i] != ' ' && t[i] != '\t' && t[i] != '\r') ++i;
        if (i > b) out.push_back({t.substr(b, i - b), start + static_cast<uint32_t>(b)});
    }
}
std::vector<Word> words_of(const SourceFile& file, uint32_t line) {
    std::vector<Word> out;
    words_of(file, line, out);
    return out;
}

SourceSpan span_of(const SourceFile& file, const Word& w) { return {&file, w.begin, w.begin + static_cast<uint32_t>(w.text.size())}; }

// The decimal exponent of a number word ("-0E3080": 3080), 0 without one. tinyobjloader
// computes mantissa x 5^e x 2^e, which for a finite number with |e| past a double's range is
// 0 x inf: its `Ns -0E3080` was NaN where strtod reads -0 (mtl_fuzzer).
long decimal_exponent(std::string_view text) {
    const size_t e = text.find_first_of("eE");
    if (e == std::string_view::npos || text.find_first_of("xX") != std::string_view::npos) return 0;  // hex: 'e' is a digit
    size_t i = e + 1;
    const bool negative = i < text.size() && text[i] == '-';
    if (i < text.size() && (text[i] == '-' || text[i] == '+')) ++i;
    long value = 0;
    for (; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i) value = std::min(value * 10 + (text[i] - '0'), 1000000L);
    return negative ? -value : value;
}

// A number word: false (and said) unless the whole word is a finite number in [lo, hi] with a
// decimal exponent tinyobjloader reads as written (within a double's +-308).
bool number(const SourceFile& file, const Word& w, std::string_view what, double lo, double hi, DiagnosticSink& sink) {
    const long exponent = decimal_exponent(w.text);
    if (exponent > 308 || exponent < -308) {
        sink.report("E303", span_of(file, w), fmt::format("{}: '{}' has a decimal exponent beyond a double's (-308 to 308)", what,
                                                          printable(std::string(w.text))));
        return false;
    }
    // from_chars first (no copy, no locale): a word it reads whole strtod reads to the same
    // value; any other (a '+', hex, out of range) goes to strtod, which says what is wrong.
    double v = 0;
    const auto [stop, ec] = std::from_chars(w.text.data(), w.text.data() + w.text.size(), v);
    if (ec == std::errc{} && stop == w.text.data() + w.text.size() && std::isfinite(v) && v >= lo && v <= hi) return true;
    const std::string text(w.text);
    char* end = nullptr;
    v = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size() || text.empty()) {
        sink.report("E302", span_of(file, w), fmt::format("{}: '{}' is not a number", what, printable(text)));
        return false;
    }
    if (!std::isfinite(v)) {
        sink.report("E303", span_of(file, w), fmt::format("{}: '{}' is not a finite number", what, printable(text)));
        return false;
    }
    if (v < lo || v > hi) {
        sink.report("E303", span_of(file, w), fmt::format("{}: {} is out of range: expected {}", what, text,
                                                          std::isinf(hi) ? fmt::format("at least {:g}", lo) : fmt::format("{:g} to {:g}", lo, hi)));
        return false;
    }
    return true;
}

// One index of a face corner: 1..count, or -count..-1 counting back from this line.
void face_index(const SourceFile& file, const Word& corner, std::string_view part, uint32_t offset, const char* kind, size_t defined,
                size_t total, DiagnosticSink& sink) {
    const SourceSpan at{&file, corner.begin + offset, corner.begin + offset + static_cast<uint32_t>(part.size())};
    long long i = 0;
    auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), i);
    if (ec != std::errc{} || end != part.data() + part.size()) {
        sink.report("E302", at, fmt::format("face: {} index '{}' is not a whole number", kind, printable(part)));
        return;
    }
    if (i == 0) {
        sink.report("E306", at, fmt::format("face: {} index 0 names nothing (OBJ counts from 1, or back from -1)", kind));
        return;
    }
    // -(i + 1) + 1: -i without overflow at the most negative long long.
    if (i > 0 ? static_cast<unsigned long long>(i) > total : static_cast<unsigned long long>(-(i + 1)) + 1 > defined)
        sink.report("E303", at,
                    i > 0 ? fmt::format("face: {} index {} names no {}: the file has {}", kind, i, kind, total)
                          : fmt::format("face: {} index {} names no {}: {} are defined above this line", kind, i, kind, defined));
}

}  // namespace

void check_obj_text(const SourceFile& obj, DiagnosticSink& sink) {
    size_t total_v = 0, total_vt = 0, total_vn = 0;
    for (uint32_t line = 1; line <= obj.line_count(); ++line) {
        std::string_view t = obj.line_text(line);
        size_t b = t.find_first_not_of(" \t");
        if (b == std::string_view::npos) continue;
        t = t.substr(b);
        total_v += t.rfind("v ", 0) == 0 || t.rfind("v\t", 0) == 0;
        total_vt += t.rfind("vt ", 0) == 0 || t.rfind("vt\t", 0) == 0;
        total_vn += t.rfind("vn ", 0) == 0 || t.rfind("vn\t", 0) == 0;
    }
    size_t v = 0, vt = 0, vn = 0;
    const size_t errors_before = sink.error_count();
    std::vector<Word> w;
    for (uint32_t line = 1; line <= obj.line_count() && sink.error_count() - errors_before < 100; ++line) {
        words_of(obj, line, w);
        if (w.empty()) continue;
        const std::string_view key = w[0].text;
        if (key == "v" || key == "vt" || key == "vn") {
            const char* what = key == "v" ? "vertex" : key == "vt" ? "texture coordinate" : "normal";
            const size_t need = key == "vt" ? 1 : 3;
            if (w.size() < need + 1)
                sink.report("E302", span_of(obj, w.back()), fmt::format("{}: expected {} numbers", what, need));
            for (size_t k = 1; k < w.size(); ++k) number(obj, w[k], what, -HUGE_VAL, HUGE_VAL, sink);
            (key == "v" ? v : key == "vt" ? vt : vn) += 1;
        } else if (key == "f") {
            if (w.size() < 4)
                sink.report("E306", span_of(obj, w[0]), fmt::format("face: {} corner{}; a face needs at least 3", w.size() - 1,
                                                                    w.size() == 2 ? "" : "s"));
            for (size_t k = 1; k < w.size(); ++k) {
                // v, v/vt, v//vn or v/vt/vn
                std::string_view c = w[k].text;
                uint32_t offset = 0;
                const char* kinds[3] = {"vertex", "texture coordinate", "normal"};
                const size_t defined[3] = {v, vt, vn}, totals[3] = {total_v, total_vt, total_vn};
                for (int part = 0; part < 3; ++part) {
                    const size_t slash = c.find('/');
                    std::string_view p = c.substr(0, slash);
                    if (!p.empty() || part == 0) face_index(obj, w[k], p, offset, kinds[part], defined[part], totals[part], sink);
                    if (slash == std::string_view::npos) break;
                    offset += static_cast<uint32_t>(slash + 1);
                    c = c.substr(slash + 1);
                }
            }
        }
    }
}

std::vector<MaterialLibrary> material_libraries(const SourceFile& obj, const std::string& dir) {
    std::vector<MaterialLibrary> out;
    std::vector<Word> w;
    for (uint32_t line = 1; line <= obj.line_count(); ++line) {
        if (obj.line_text(line).find("mtllib") == std::string_view::npos) continue;
        words_of(obj, line, w);
        if (w.empty() || w[0].text != "mtllib") continue;
        for (size_t k = 1; k < w.size(); ++k)
            out.push_back({(std::filesystem::path(dir) / std::string(w[k].text)).string(), span_of(obj, w[k])});
    }
    return out;
}

void check_mtl_text(const SourceFile& mtl, DiagnosticSink& sink) {
    const size_t errors_before = sink.error_count();
    for (uint32_t line = 1; line <= mtl.line_count() && sink.error_count() - errors_before < 100; ++line) {
        const std::vector<Word> w = words_of(mtl, line);
        if (w.empty()) continue;
        const std::string key(w[0].text);
        auto values = [&](double lo, double hi, const std::string& what) {
            if (w.size() < 2) sink.report("E302", span_of(mtl, w[0]), fmt::format("{}: expected a number", what));
            for (size_t k = 1; k < w.size(); ++k) number(mtl, w[k], what, lo, hi, sink);
        };
        if (key == "Ka" || key == "Kd" || key == "Ks" || key == "Ke" || key == "Tf") {
            if (w.size() > 1 && (w[1].text == "spectral" || w[1].text == "xyz")) continue;  // tinyobjloader ignores these
            values(0, HUGE_VAL, key + " (a colour, each channel >= 0)");
        } else if (key == "Ns") {
            values(0, HUGE_VAL, "Ns (the Phong exponent)");
        } else if (key == "Ni") {
            // Any finite number: exporters write `Ni 0` on opaque materials, where it means
            // nothing; a glass with an Ni not above 0 is warned about where it is made (import_obj).
            if (w.size() >= 2) number(mtl, w[1], "Ni (the index of refraction)", -HUGE_VAL, HUGE_VAL, sink);
        } else if (key == "d" || key == "Tr") {
            values(0, 1, key == "d" ? "d (opacity)" : "Tr (transparency)");
        } else if (key == "illum") {
            if (w.size() >= 2 && number(mtl, w[1], "illum", 0, 10, sink) && std::string(w[1].text).find_first_not_of("0123456789") != std::string::npos)
                sink.report("E302", span_of(mtl, w[1]), "illum: expected a whole number from 0 to 10");
        }
    }
}

std::optional<std::string_view> keyword_rest(std::string_view line, std::string_view keyword) {
    const size_t at = line.find_first_not_of(" \t");
    if (at == std::string_view::npos || line.substr(at, keyword.size()) != keyword) return std::nullopt;
    std::string_view rest = line.substr(at + keyword.size());
    if (rest.empty() || (rest[0] != ' ' && rest[0] != '\t')) return std::nullopt;
    rest.remove_prefix(std::min(rest.find_first_not_of(" \t"), rest.size()));
    while (!rest.empty() && (rest.back() == ' ' || rest.back() == '\t' || rest.back() == '\r')) rest.remove_suffix(1);
    return rest;
}

SourceSpan first_line_naming(const SourceFile& obj, std::string_view keyword, const std::string& name, bool as_word) {
    for (uint32_t line = 1; line <= obj.line_count(); ++line) {
        const std::string_view t = obj.line_text(line);
        const std::optional<std::string_view> found = keyword_rest(t, keyword);
        if (!found) continue;
        const std::string_view rest = *found;
        bool named = rest == name;
        for (size_t b = 0; as_word && !named && b < rest.size();) {
            const size_t e = std::min(rest.find_first_of(" \t", b), rest.size());
            named = rest.substr(b, e - b) == name;
            b = std::min(rest.find_first_not_of(" \t", e), rest.size());
        }
        if (!named) continue;
        const uint32_t b = obj.line_start(line);
        return {&obj, b, b + static_cast<uint32_t>(t.size())};
    }
    return {&obj, 0, 0};
}

void report_obj_messages(const std::string& warnings, const SourceFile& obj, const char* code, DiagnosticSink& sink) {
    static const std::regex line_number(R"(line:? ?([0-9]+))");
    // tinyobjloader names no line for these: the first usemtl or mtllib line naming it.
    static const std::regex missing_material(R"(material \[ '(.*)' \] not found)");
    static const std::regex missing_library(R"(Material file \[ (.*) \] not found)");
    size_t at = 0;
    while (at < warnings.size()) {
        size_t end = warnings.find('\n', at);
        if (end == std::string::npos) end = warnings.size();
        std::string w = warnings.substr(at, end - at);
        at = end + 1;
        if (w.find_first_not_of(" .\t\r") == std::string::npos) continue;
        SourceSpan span{&obj, 0, 0};
        std::smatch m;
        if (std::regex_search(w, m, line_number)) {
            const unsigned long n = std::strtoul(m[1].str().c_str(), nullptr, 10);
            if (n >= 1 && n <= obj.line_count()) {
                const uint32_t b = obj.line_start(static_cast<uint32_t>(n));
                span = {&obj, b, b + static_cast<uint32_t>(obj.line_text(static_cast<uint32_t>(n)).size())};
            }
        } else if (std::regex_search(w, m, missing_material)) {
            span = first_line_naming(obj, "usemtl", m[1].str(), false);
        } else if (std::regex_search(w, m, missing_library)) {
            span = first_line_naming(obj, "mtllib", m[1].str(), true);
        }
        sink.report(code, span, fmt::format("OBJ: {}", w));
    }
}

}  // namespace crex
