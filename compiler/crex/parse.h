/// \file parse.h
/// parse_crex(): crex text -> ast::Crex, reporting E001, E002, E008, E010 and E011.
/// The text may be a whole SourceFile (`<expr>`) or a byte range of one (a line of a crex
/// file, or a string literal inside a pipeline file): spans stay in file coordinates.
#pragma once

#include <optional>

#include "base/diagnostic.h"
#include "base/source.h"
#include "compiler/crex/ast.h"

namespace crex {

/// Deepest group nesting accepted (E010 beyond): keeps every recursive pass's stack bounded.
inline constexpr uint32_t kMaxCrexNesting = 256;
/// Longest crex accepted, in bytes (E011 beyond).
inline constexpr uint32_t kMaxCrexBytes = 1u << 20;

/// Parses bytes [begin, end) of `file`. Returns a tree whenever the text could be tokenised
/// and nested within the limits, even if it has errors (they are in `sink`); nullopt otherwise.
std::optional<ast::Crex> parse_crex(const SourceFile& file, uint32_t begin, uint32_t end,
                                    DiagnosticSink& sink);
std::optional<ast::Crex> parse_crex(const SourceFile& file, DiagnosticSink& sink);

}  // namespace crex
