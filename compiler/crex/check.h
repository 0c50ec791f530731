/// \file check.h
/// check_crex(): the static rules of spec/crex.md §4 that need the whole tree:
/// E003 (repeat range), E004–E007 (what may nest in `{ }` and `[ ]`), E009 (integer after
/// integer), and warnings W101, W102, W104, W105. Runs after parse_crex(), on trees with
/// parse errors too, so all errors come out in one pass. W103 needs a scene (planner).
#pragma once

#include "base/diagnostic.h"
#include "compiler/crex/ast.h"

namespace crex {

/// Largest repeat count (E003 beyond).
inline constexpr uint64_t kMaxRepeatCount = 2147483647;

void check_crex(const ast::Crex& crex, DiagnosticSink& sink);

}  // namespace crex
