/// \file parse.h
/// parse_pipeline_file(): pipeline text -> ast::File, syntax errors as E201 with positions.
#pragma once

#include <optional>

#include "base/diagnostic.h"
#include "compiler/pipeline/ast.h"

namespace crex::pipeline {

std::optional<ast::File> parse_pipeline_file(const SourceFile& file, DiagnosticSink& sink);

}  // namespace crex::pipeline
