/// \file scene_text.h
/// RADIANCE scene text read as RADIANCE reads it: between primitives, `#` comments to the end
/// of the line and `!` commands (continued over lines with a backslash before the newline);
/// a primitive is `modifier type identifier` then its string, integer and real argument lists,
/// or `modifier alias identifier reference`. Words are separated by white space or enclosed in
/// '...' or "..." (a quoted word may hold spaces). Every word keeps its place in the file, so
/// every later error points at what the user wrote.
#pragma once

#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "base/diagnostic.h"
#include "base/source.h"

namespace crex::radiance {

struct Word {
    std::string text;
    SourceSpan span;
};

/// One primitive as written. Primitives made by a generator command (genbox, ...) carry the
/// command's span everywhere.
struct Primitive {
    Word modifier, type, id;
    std::vector<Word> strings;
    std::vector<double> reals;
    std::vector<SourceSpan> real_spans;  ///< one per real
    Word alias_of;                       ///< `alias` only: the reference
    SourceSpan span;                     ///< the whole primitive (or the command that made it)
    /// The `!` commands that brought it in, innermost first (empty in the main file).
    std::shared_ptr<const std::vector<SourceSpan>> via;

    bool is_alias() const { return type.text == "alias"; }
    /// The span of reals [first, last] (the primitive's span when there are none).
    SourceSpan reals_span(size_t first = 0, size_t last = SIZE_MAX) const;
};

/// A `!` line: the command without the `!`, continuation lines joined with a space.
struct Command {
    std::string text;
    SourceSpan span;  ///< from the `!` to the end of its last line
    /// For each byte of `text`, its offset in the file (words of the command are located).
    std::vector<uint32_t> offsets;
};

/// A `#@crex ...` comment: crex's own directives, which RADIANCE ignores.
struct Directive {
    std::string text;
    SourceSpan span;
};

using Item = std::variant<Primitive, Command, Directive>;

/// Every item of `file` in order. A primitive whose structure is lost (a count that is not a
/// number, a file that ends inside it) is reported and ends the reading: what follows would be
/// misread. Bad numbers inside an otherwise well-formed primitive are reported and the
/// primitive is dropped.
std::vector<Item> read_scene_text(const SourceFile& file, DiagnosticSink& sink);

/// Parses a real as RADIANCE's scene files write them (strtod, the whole word). False when it
/// is not a number or not finite.
bool parse_real(const std::string& text, double& out);

}  // namespace crex::radiance
