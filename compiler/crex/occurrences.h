/// \file occurrences.h
/// Counting component occurrences after expanding integer repeats (spec/crex.md §3, `{ }`):
/// `{T2}` has n = 2, `{(TR)2}` has n = 4, `{<RS>G}` has n = 3. Counts are doubles because the
/// spec computes `ceil(I(p)·n)` in double and nested repeats can exceed any integer type.
/// A '*' counts once (it is an error inside `{ }` anyway, E004).
#pragma once

#include "compiler/crex/ast.h"

namespace crex {

/// Occurrences contributed by one item, repeats included.
double count_occurrences(const ast::Item& item);
/// Occurrences of a whole sequence.
double count_occurrences(const ast::Sequence& seq);
/// Product of an item's integer repeats ('*' counts as 1).
double repeat_multiplier(const ast::Item& item);

}  // namespace crex
