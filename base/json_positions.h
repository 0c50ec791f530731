/// \file json_positions.h
/// JSON with source positions. nlohmann-json 3.11 keeps no positions, so the document is read
/// with json::sax_parse over an iterator that counts the bytes the lexer has consumed; at each
/// SAX event the token just read ends there, and its start is found by scanning back. Every
/// value and every object key gets a span, keyed by its JSON pointer ("/materials/2/roughness").
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "base/diagnostic.h"
#include "base/source.h"

namespace crex {

struct PositionedJson {
    nlohmann::json value;
    std::map<std::string, SourceSpan> value_spans;  ///< JSON pointer -> the value's text
    std::map<std::string, SourceSpan> key_spans;    ///< JSON pointer -> the key naming it

    /// Span of the value at `pointer`, else of its key, else of the nearest enclosing value.
    SourceSpan span(const std::string& pointer) const;
    SourceSpan key_span(const std::string& pointer) const;
};

/// Parses `file` as JSON. Syntax errors, duplicate keys and numbers out of range are reported
/// with `syntax_code` (e.g. "E301"); returns false if the document is unusable.
bool parse_json_with_positions(const SourceFile& file, PositionedJson& out, DiagnosticSink& sink,
                               const char* syntax_code);

/// A key as a JSON-pointer token ("a/b" -> "a~1b").
std::string escape_pointer_token(const std::string& key);

/// "/materials/2/roughness" -> "materials[2].roughness" (for messages).
std::string readable_json_path(const std::string& pointer);

}  // namespace crex
