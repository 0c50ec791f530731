/// \file compile.h
/// The crex front end in one call: parse_crex -> check_crex -> lower_crex.
/// Also reads crex files: one crex per line, blank lines and `#` lines skipped (spec §2).
#pragma once

#include <optional>
#include <vector>

#include "base/diagnostic.h"
#include "compiler/crex/ast.h"
#include "compiler/crex/lower.h"
#include "compiler/sched/program.h"

namespace crex {

struct CompiledCrex {
    SourceSpan span;                        ///< the crex text
    std::optional<ast::Crex> ast;           ///< when it could be parsed
    std::optional<sched::Program> program;  ///< when it had no errors
};

/// Compiles bytes [begin, end) of `file`; diagnostics go to `sink`.
CompiledCrex compile_crex(const SourceFile& file, uint32_t begin, uint32_t end, DiagnosticSink& sink,
                          const LowerOptions& options = {});
CompiledCrex compile_crex(const SourceFile& file, DiagnosticSink& sink, const LowerOptions& options = {});

/// Compiles every crex line of a crex file.
std::vector<CompiledCrex> compile_crex_file(const SourceFile& file, DiagnosticSink& sink,
                                            const LowerOptions& options = {});

}  // namespace crex
