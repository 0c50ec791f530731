/// \file program.h
/// The schedule IR: what a crex *does*, in a small flat-enough form for the planner and the
/// runtime (spec/crex.md §3). Plain data (no pointers but the source span's file), so it can be
/// serialised into a plan and shipped to another process.
///
///   Exec(c)              execute component c over its bin
///   Seq[...]             run children in order; spawned rays are visible at once
///   Defer[...]           owns a deferral: rays spawned inside merge into the bins at its end
///   Modulate{n}[...]     importance-modulated: occurrence i runs a ray of pixel p iff
///                        i < ceil(I(p)·n)
///   Budgeted[...]        a time-constrained task (`[ ]`); owns its deferral unless nested in
///                        a `< >`
///   Repeat(k)[body]      run body k times
///   RepeatUntilEmpty(cap)[body]  run body, again while its last execution had work, at most
///                        cap times per entry (W401 at the cap)
///
/// Inside a Modulate, an Exec's occurrence index is `first_index + Σ iteration·stride` over the
/// Repeat nodes between it and the Modulate (a repeat inside `{ }` continues the numbering).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/source.h"
#include "base/components.h"

namespace crex::sched {

/// Default iteration cap of `*` per entry into the loop.
inline constexpr uint32_t kDefaultStarCap = 10000;
/// Map a bare crex modulates by.
inline constexpr const char* kDefaultModulationMap = "importance";

enum class Op : uint8_t { kExec, kSeq, kDefer, kModulate, kBudgeted, kRepeat, kRepeatUntilEmpty };

std::string_view op_name(Op op);

struct Node {
    Op op = Op::kSeq;
    Component component = Component::kD;  ///< kExec
    uint64_t count = 0;                   ///< kRepeat: k
    uint32_t cap = 0;                     ///< kRepeatUntilEmpty: iterations per entry
    double occurrences = 0;               ///< kModulate: n
    double first_index = -1;              ///< kExec inside a Modulate: index at iteration 0
    double stride = 0;                    ///< kRepeat inside a Modulate: occurrences per iteration
    bool owns_deferral = false;           ///< kDefer: true; kBudgeted: not nested in a deferral
    std::string map;                      ///< kModulate: the importance map's name
    SourceLocation where;                 ///< the crex text it came from (plain data: no pointers)
    std::vector<Node> children;
};

/// A lowered crex: the pre-selective part (leading top-level items with no `{ }`), then the
/// selective part; bins carry over from one to the other.
struct Program {
    Node preselective;  ///< kSeq
    Node selective;     ///< kSeq
};

/// Structural equality, ignoring source locations.
bool same_structure(const Node& a, const Node& b);
bool same_structure(const Program& a, const Program& b);

}  // namespace crex::sched
