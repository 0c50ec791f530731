/// \file bin_occupancy.h
/// Scene-aware analysis of a lowered crex (spec/crex.md §5): an abstract interpretation over
/// "which bins may be non-empty", driven by the scene's spawn graph, that finds every step
/// that can never have work, and prune_dead_steps() that removes them (with the reason).
///
/// Runs after lower_crex(). The spawn graph is conservative (no visibility): camera rays and
/// every executed step may fill any bin some material in use spawns into.
#pragma once

#include <bitset>
#include <string>
#include <vector>

#include "base/components.h"
#include "compiler/sched/program.h"

namespace crex {

using BinSet = std::bitset<kComponentCount>;

/// A step that can never take a ray, and why.
struct DeadStep {
    Component component;
    SourceLocation where;
    std::string reason;
};

/// Steps of `program` (pre-selective, then selective) that can never have work when the
/// scene's materials can spawn only into `spawnable`, in program order.
std::vector<DeadStep> find_dead_steps(const sched::Program& program, const BinSet& spawnable);

/// The program without its dead steps; groups and repeats left empty disappear. Occurrence
/// numbering inside `{ }` is kept as it was (n and each step's index are unchanged), so what
/// the remaining steps execute does not change.
sched::Program prune_dead_steps(const sched::Program& program, const BinSet& spawnable);

/// "bin T can never be non-empty: no material in use spawns T (T comes from glass, dielectric; ...)".
std::string dead_step_reason(Component c);

}  // namespace crex
