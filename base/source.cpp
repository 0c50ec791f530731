#include "base/source.h"

#include <algorithm>

namespace crex {

SourceFile::SourceFile(std::string name, std::string text)
    : name_(std::move(name)), text_(std::move(text)) {
    line_starts_.push_back(0);
    line_ascii_.push_back(true);
    for (uint32_t i = 0; i < text_.size(); ++i) {
        if (text_[i] == '\n') line_starts_.push_back(i + 1), line_ascii_.push_back(true);
        else if (static_cast<unsigned char>(text_[i]) >= 0x80) line_ascii_.back() = false;
    }
}

LineCol SourceFile::position(uint32_t offset) const {
    offset = std::min<uint32_t>(offset, static_cast<uint32_t>(text_.size()));
    auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(), offset);
    uint32_t line = static_cast<uint32_t>(it - line_starts_.begin());  // 1-based
    uint32_t start = line_starts_[line - 1];
    // A column is a count of code points; on an ASCII line that is the byte distance (counting
    // made every diagnostic and lowered step of a 300k-character crex cost its whole line).
    if (line_ascii_[line - 1]) return {line, offset - start + 1};
    std::string_view before(text_.data() + start, offset - start);
    return {line, count_code_points(before) + 1};
}

uint32_t SourceFile::line_start(uint32_t line) const {
    if (line == 0) return 0;
    if (line > line_starts_.size()) return static_cast<uint32_t>(text_.size());
    return line_starts_[line - 1];
}

uint32_t SourceFile::offset_of(uint32_t line, uint32_t col) const {
    uint32_t start = line_start(line);
    std::string_view text = line_text(line);
    uint32_t i = 0, seen = 1;
    while (i < text.size() && seen < col) {
        ++i;
        while (i < text.size() && (static_cast<unsigned char>(text[i]) & 0xC0) == 0x80) ++i;
        ++seen;
    }
    return start + i;
}

std::string_view SourceFile::line_text(uint32_t line) const {
    if (line == 0 || line > line_starts_.size()) return {};
    uint32_t start = line_starts_[line - 1];
    uint32_t end = line < line_starts_.size() ? line_starts_[line] - 1
                                              : static_cast<uint32_t>(text_.size());
    if (end > start && text_[end - 1] == '\r') --end;
    return std::string_view(text_).substr(start, end - start);
}

SourceSpan SourceSpan::merge(const SourceSpan& other) const {
    if (!valid()) return other;
    if (!other.valid()) return *this;
    return {file, std::min(begin, other.begin), std::max(end, other.end)};
}

std::string_view SourceSpan::text() const {
    if (!valid()) return {};
    return std::string_view(file->text()).substr(begin, end - begin);
}

SourceLocation SourceLocation::of(const SourceSpan& span) {
    SourceLocation loc;
    if (!span.valid()) return loc;
    LineCol b = span.file->position(span.begin), e = span.file->position(span.end);
    loc.file = span.file->name();
    loc.line = b.line;
    loc.col = b.col;
    loc.end_line = e.line;
    loc.end_col = e.col;
    return loc;
}

SourceSpan SourceLocation::in(const SourceFile& f) const {
    if (!known()) return {&f, 0, 0};
    return {&f, f.offset_of(line, col), f.offset_of(end_line, end_col)};
}

std::string SourceLocation::to_string() const {
    if (!known()) return "<unknown>";
    return file + ":" + std::to_string(line) + ":" + std::to_string(col);
}

uint32_t count_code_points(std::string_view utf8) {
    uint32_t n = 0;
    for (unsigned char c : utf8)
        if ((c & 0xC0) != 0x80) ++n;
    return n;
}

}  // namespace crex
