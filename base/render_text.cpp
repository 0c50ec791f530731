#include "base/render_text.h"

#include <fmt/format.h>

#include <algorithm>

namespace crex {
namespace {

// The source line as shown under a diagnostic: one display character per code point, so the
// caret line can be built by counting code points. Tabs and control characters become one
// visible character; malformed UTF-8 bytes become '?'.
std::string displayable_line(std::string_view line) {
    std::string out;
    for (size_t i = 0; i < line.size();) {
        unsigned char c = static_cast<unsigned char>(line[i]);
        if (c == '\t') {
            out += ' ';
            ++i;
        } else if (c < 0x20 || c == 0x7F) {
            out += '?';
            ++i;
        } else if (c < 0x80) {
            out += static_cast<char>(c);
            ++i;
        } else {
            size_t len = (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : (c & 0xF8) == 0xF0 ? 4 : 0;
            bool ok = len > 0 && i + len <= line.size();
            for (size_t k = 1; ok && k < len; ++k)
                ok = (static_cast<unsigned char>(line[i + k]) & 0xC0) == 0x80;
            if (ok) {
                out.append(line.substr(i, len));
                i += len;
            } else {
                out += '?';
                ++i;
                while (i < line.size() && (static_cast<unsigned char>(line[i]) & 0xC0) == 0x80) {
                    out += '?';
                    ++i;
                }
            }
        }
    }
    return out;
}

// Code points [from, from + count) of a displayable line (whole code points, never bytes).
std::string code_points(std::string_view line, uint32_t from, uint32_t count) {
    size_t i = 0, start = line.size();
    for (uint32_t k = 0; i <= line.size(); ++k) {
        if (k == from) start = i;
        if (k == from + count || i == line.size()) return std::string(line.substr(std::min(start, i), i - std::min(start, i)));
        ++i;
        while (i < line.size() && (static_cast<unsigned char>(line[i]) & 0xC0) == 0x80) ++i;
    }
    return {};
}

// Longer source lines (a minified glTF is one line of megabytes) are shown as this many code
// points around the span's start, cut ends marked with "...".
constexpr uint32_t kShownColumns = 120;

void render_snippet(std::string& out, const SourceSpan& span) {
    if (!span.valid()) return;
    const SourceFile& f = *span.file;
    LineCol begin = f.position(span.begin);
    LineCol end = f.position(span.end);
    std::string line = displayable_line(f.line_text(begin.line));
    uint32_t width = begin.line == end.line && end.col > begin.col ? end.col - begin.col : 1;
    if (begin.line != end.line) {  // multi-line span: underline to the end of the first line
        uint32_t line_len = count_code_points(line);
        width = line_len >= begin.col ? line_len - begin.col + 1 : 1;
    }
    uint32_t caret = begin.col - 1;  // code points before the caret, as shown
    if (const uint32_t length = count_code_points(line); length > kShownColumns) {
        const uint32_t from = caret > kShownColumns / 3 ? std::min(caret - kShownColumns / 3, length - kShownColumns) : 0;
        const bool head_cut = from > 0, tail_cut = from + kShownColumns < length;
        line = (head_cut ? "..." : "") + code_points(line, from, kShownColumns) + (tail_cut ? "..." : "");
        const uint32_t into = caret - from;  // the caret's place in the window
        width = std::min(width, kShownColumns > into ? kShownColumns - into : 1);
        caret = into + (head_cut ? 3 : 0);
    }
    std::string gutter = fmt::format("{:>5}", begin.line);
    std::string blank(gutter.size(), ' ');
    out += fmt::format("{} | {}\n", gutter, line);
    out += fmt::format("{} | {}^{}\n", blank, std::string(caret, ' '), std::string(width > 0 ? width - 1 : 0, '~'));
}

}  // namespace

std::string printable(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (char ch : text) {
        const unsigned char c = static_cast<unsigned char>(ch);
        if ((c < 0x20 && c != '\t') || c == 0x7F) out += fmt::format("\\x{:02X}", static_cast<unsigned>(c));
        else out += ch;
    }
    return out;
}

std::string format_location(const SourceSpan& span) {
    if (!span.valid()) return "<unknown>";
    LineCol p = span.file->position(span.begin);
    return fmt::format("{}:{}:{}", printable(span.file->name()), p.line, p.col);
}

std::string render_text(const Diagnostic& d) {
    std::string out;
    std::string head = d.code.empty() ? std::string(severity_name(d.severity))
                                      : fmt::format("{}[{}]", severity_name(d.severity), d.code);
    const std::string where = d.span.valid() || d.where.empty() ? format_location(d.span) : printable(d.where);
    out += fmt::format("{}: {}: {}\n", where, head, printable(d.message));
    render_snippet(out, d.span);
    for (const auto& note : d.notes) {
        if (!note.span.valid()) {  // a note about the whole diagnostic, not a place
            out += fmt::format("      = note: {}\n", printable(note.message));
            continue;
        }
        out += fmt::format("{}: note: {}\n", format_location(note.span), printable(note.message));
        render_snippet(out, note.span);
    }
    if (!d.help.empty()) out += fmt::format("      = help: {}\n", printable(d.help));
    return out;
}

std::string render_text(const std::vector<Diagnostic>& ds) {
    // A model of 300 meshes each with a zero-area triangle said W303 300 times, four lines
    // each, and buried the one error among them: a warning code is shown kWarningsShownPerCode
    // times, then counted.
    std::string out;
    std::vector<std::pair<std::string, size_t>> seen;  // warning code, times; in first-seen order
    for (const auto& d : ds) {
        if (d.severity == Severity::kWarning && !d.code.empty()) {
            auto it = std::find_if(seen.begin(), seen.end(), [&](const auto& s) { return s.first == d.code; });
            if (it == seen.end()) it = seen.insert(seen.end(), {d.code, 0});
            if (++it->second > kWarningsShownPerCode) continue;
        }
        out += render_text(d);
    }
    for (const auto& [code, times] : seen)
        if (times > kWarningsShownPerCode)
            out += fmt::format("warning[{}]: {} more like it not shown ({} in all)\n", code, times - kWarningsShownPerCode, times);
    return out;
}

}  // namespace crex
