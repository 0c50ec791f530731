/// \file check.h
/// check_pipeline_file(): the static rules of a pipeline file (docs/pipeline-language.md):
/// known sections, settings and selective variables, guidance operators with their signatures
/// (the stdlib table below), names defined before use, value ranges, budget units, embedded
/// crex compiled at their file position, the pre-selective crex without `{ }`, `extends` of a
/// known pipeline, and maps nothing uses (W201).
#pragma once

#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "compiler/pipeline/ast.h"

namespace crex::pipeline {

/// The guidance operators the checker knows (registry.h; for docs, `--help` and did-you-mean).
std::vector<std::string> guidance_operator_names();

void check_pipeline_file(const ast::File& file, DiagnosticSink& sink);

}  // namespace crex::pipeline
