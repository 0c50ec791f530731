#include "compiler/crex/occurrences.h"

namespace crex {

double repeat_multiplier(const ast::Item& item) {
    double m = 1.0;
    for (const auto& r : item.repeats)
        if (!r.star) m *= static_cast<double>(r.count);
    return m;
}

double count_occurrences(const ast::Item& item) {
    double base = 0.0;
    if (item.kind == ast::ItemKind::kComponent) base = 1.0;
    if (item.kind == ast::ItemKind::kGroup) base = count_occurrences(item.body);
    return base * repeat_multiplier(item);
}

double count_occurrences(const ast::Sequence& seq) {
    double n = 0.0;
    for (const auto& item : seq) n += count_occurrences(item);
    return n;
}

}  // namespace crex
