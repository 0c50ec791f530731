/// \file lower.h
/// lower_crex(): ast::Crex -> sched::Program. Runs only on trees check_crex() accepted.
///
/// Normalisations (none changes what executes): `( )` disappears into its parent sequence;
/// a `< >` or `[ ]` inside a deferral stops owning one (deferral belongs to the outermost,
/// spec §3), and a `[ ]` inside a `[ ]` is no separate task (W105), so it becomes a sequence;
/// a repeat of 1 is dropped. The pre-selective/selective split is taken on the tree as
/// written (spec §3: leading top-level items with no `{` at any depth).
#pragma once

#include "compiler/crex/ast.h"
#include "compiler/sched/program.h"

namespace crex {

struct LowerOptions {
    uint32_t star_cap = sched::kDefaultStarCap;
    std::string modulation_map = sched::kDefaultModulationMap;
};

sched::Program lower_crex(const ast::Crex& crex, const LowerOptions& options = {});

/// Index of the first top-level item that belongs to the selective stage.
size_t preselective_item_count(const ast::Sequence& top);

}  // namespace crex
