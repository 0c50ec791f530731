/// \file parse_internal.h
/// Shared between parse.cpp and build_ast.cpp only: the decoded input and the builder entry.
#pragma once

#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "compiler/crex/ast.h"

namespace crex::grammar {
class CrexParser;
}

namespace crex::detail {

/// The crex text decoded to code points (malformed UTF-8 bytes become U+FFFD, one per byte),
/// with the file byte offset of every code point and of the end.
struct DecodedText {
    std::u32string code_points;
    std::vector<uint32_t> byte_offsets;  // size = code_points.size() + 1
};

DecodedText decode_utf8(std::string_view text, uint32_t base_offset);

/// Walks the parse tree of `parser`'s `crex` rule into our AST, reporting E001/E002/E008.
ast::Crex build_crex_ast(grammar::CrexParser& parser, const SourceFile& file,
                         const DecodedText& text, uint32_t begin, uint32_t end,
                         DiagnosticSink& sink);

}  // namespace crex::detail
