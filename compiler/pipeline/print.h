/// \file print.h
/// The pipeline language printed back as source, canonically (one statement a line, two-space
/// indents): the literal and expression text the planner puts in labels, a parsed file
/// (`crex plan --dump-after parse|check`), and a resolved pipeline with its `extends` chain
/// applied (`--dump-after resolve`), which parses and checks as the same pipeline.
#pragma once

#include <string>

#include "compiler/pipeline/ast.h"
#include "compiler/pipeline/resolve.h"

namespace crex::pipeline {

/// `2 deg`, `"text"`, `true`, `x`.
std::string value_text(const ast::Value& v);
/// `importance(task 0.5, sal 0.5, op "+")`.
std::string expr_text(const ast::Expr& e);

std::string print_file(const ast::File& file);
std::string print_resolved(const ResolvedPipeline& p);

}  // namespace crex::pipeline
