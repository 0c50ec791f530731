/// \file obj_checks.h
/// What tinyobjloader takes without a word, checked on the text first and said where it is:
/// a vertex `v nan 0 0` (read as 0), a face index that names no vertex (`f -1 -2 -99` dropped
/// the whole mesh), an MTL colour with a negative channel (`Ke -10 10 10` became a light with
/// no red). Apart from import_obj.cpp, which maps what tinyobjloader read onto materials.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/diagnostic.h"
#include "base/source.h"

namespace crex {

/// E302 (not a number), E303 (non-finite value, index out of range), E306 (a face of fewer
/// than 3 vertices, a zero index), each at its line and column.
void check_obj_text(const SourceFile& obj, DiagnosticSink& sink);

/// The MTL files the OBJ's `mtllib` lines name, as paths beside the OBJ (`dir`), with the span
/// of each name for messages.
struct MaterialLibrary {
    std::string path;
    SourceSpan named_at;
};
std::vector<MaterialLibrary> material_libraries(const SourceFile& obj, const std::string& dir);

/// REST of a line `keyword REST` (leading blanks allowed), its blanks trimmed; nullopt when
/// the line's first word is not `keyword`.
std::optional<std::string_view> keyword_rest(std::string_view line, std::string_view keyword);

/// The first line `keyword REST` of `obj` (an OBJ or MTL text) whose REST, blanks trimmed, is
/// `name`, or holds it as a word when `as_word`: where `usemtl`, `newmtl` or `mtllib` names it.
/// The file's start when no line does.
SourceSpan first_line_naming(const SourceFile& obj, std::string_view keyword, const std::string& name, bool as_word);

/// E302/E303 for MTL values: Ka Kd Ks Ke Tf finite and >= 0, Ns >= 0, Ni finite, d and Tr in
/// [0, 1], illum a whole number from 0 to 10.
void check_mtl_text(const SourceFile& mtl, DiagnosticSink& sink);

/// tinyobjloader's warnings (`code` W301) or errors (E308), one diagnostic each, at the line
/// they name ("line 4") of `obj` when they name one, else at its start.
void report_obj_messages(const std::string& messages, const SourceFile& obj, const char* code, DiagnosticSink& sink);

}  // namespace crex
