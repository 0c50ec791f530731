/// \file ast.h
/// The crex syntax tree, as written (spec/crex.md §2). Built by parse_crex() from the ANTLR
/// parse tree; nothing downstream sees ANTLR. Every node keeps its source span. Erroneous
/// input still yields a tree (with kError items) so that every check can run in one pass.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/source.h"
#include "base/components.h"

namespace crex::ast {

enum class GroupKind : uint8_t {
    kInherit,   ///< ( )  grouping only
    kDefer,     ///< < >  spawned rays held back until the group ends
    kModulate,  ///< { }  importance-modulated
    kBudget,    ///< [ ]  time-constrained (deferred; admitted as one task under a budget)
};

char group_open_char(GroupKind k);
char group_close_char(GroupKind k);
std::string_view group_kind_name(GroupKind k);  ///< "deferred group", ...

struct Repeat {
    bool star = false;   ///< '*' (else an integer)
    uint64_t count = 0;  ///< integer value, saturated at UINT64_MAX; 0 for '*'
    SourceSpan span;
};

enum class ItemKind : uint8_t { kComponent, kGroup, kError };

struct Item {
    ItemKind kind = ItemKind::kError;
    Component component = Component::kD;  ///< kComponent
    GroupKind group = GroupKind::kInherit;  ///< kGroup
    std::vector<Item> body;                 ///< kGroup: the enclosed sequence
    SourceSpan span;        ///< the atom: letter, or group from opener to closer
    SourceSpan open_span;   ///< kGroup: the opening bracket
    bool closed = true;     ///< kGroup: false when the closer was missing or mismatched
    std::vector<Repeat> repeats;  ///< in source order; the first binds tightest
};

using Sequence = std::vector<Item>;

struct Crex {
    Sequence body;
    SourceSpan span;  ///< the whole expression
};

/// Canonical text of a tree: no whitespace, `(D2)3` for an integer repeat after an integer
/// repeat. Parsing it back gives an equal tree (ignoring spans).
std::string print(const Crex& crex);
std::string print(const Sequence& seq);

/// Structural equality, ignoring spans.
bool same_structure(const Sequence& a, const Sequence& b);

}  // namespace crex::ast
