/// \file source.h
/// Source text and positions. A SourceFile owns the text of one input (a file, or `<expr>` for
/// an inline expression); a SourceSpan is a half-open byte range in it. Lines and columns are
/// derived on demand, 1-based, with columns counted in Unicode code points (so a caret lines up
/// under the character a user sees, and a crex embedded in a pipeline file keeps file columns).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace crex {

struct LineCol {
    uint32_t line = 1;  ///< 1-based
    uint32_t col = 1;   ///< 1-based, in code points
};

class SourceFile {
public:
    SourceFile(std::string name, std::string text);

    const std::string& name() const { return name_; }
    const std::string& text() const { return text_; }

    /// Line and column of a byte offset (offsets past the end map to the end).
    LineCol position(uint32_t offset) const;
    /// Byte offset of a 1-based line and code-point column (clamped to the line).
    uint32_t offset_of(uint32_t line, uint32_t col) const;
    /// The text of the 1-based line `line`, without its line terminator.
    std::string_view line_text(uint32_t line) const;
    /// Byte offset at which 1-based line `line` starts.
    uint32_t line_start(uint32_t line) const;
    uint32_t line_count() const { return static_cast<uint32_t>(line_starts_.size()); }

private:
    std::string name_;
    std::string text_;
    std::vector<uint32_t> line_starts_;
    std::vector<bool> line_ascii_;  // per line: no byte >= 0x80, so columns are byte distances
};

/// A half-open byte range [begin, end) of one SourceFile. An empty span marks a point
/// (e.g. "a ')' was expected here").
struct SourceSpan {
    const SourceFile* file = nullptr;
    uint32_t begin = 0;
    uint32_t end = 0;

    bool valid() const { return file != nullptr; }
    /// The smallest span covering both (same file).
    SourceSpan merge(const SourceSpan& other) const;
    std::string_view text() const;
};

/// A resolved position, plain data: what plans and lowered programs keep (a SourceSpan points
/// into a SourceFile and must not outlive it).
struct SourceLocation {
    std::string file;
    uint32_t line = 0, col = 0;        ///< 1-based; 0 = unknown
    uint32_t end_line = 0, end_col = 0;  ///< end_col is one past the span

    static SourceLocation of(const SourceSpan& span);
    /// Back to a span in `file` (which must be the file it names).
    SourceSpan in(const SourceFile& file) const;
    bool known() const { return line > 0; }
    std::string to_string() const;  ///< "file:line:col", or "<unknown>"
};

/// Number of Unicode code points in UTF-8 text (a continuation byte counts as nothing;
/// malformed bytes count as one each, matching how the parsers decode them).
uint32_t count_code_points(std::string_view utf8);

}  // namespace crex
