#include "compiler/crex/ast.h"

namespace crex::ast {

char group_open_char(GroupKind k) {
    switch (k) {
    case GroupKind::kInherit: return '(';
    case GroupKind::kDefer: return '<';
    case GroupKind::kModulate: return '{';
    case GroupKind::kBudget: return '[';
    }
    return '(';
}

char group_close_char(GroupKind k) {
    switch (k) {
    case GroupKind::kInherit: return ')';
    case GroupKind::kDefer: return '>';
    case GroupKind::kModulate: return '}';
    case GroupKind::kBudget: return ']';
    }
    return ')';
}

std::string_view group_kind_name(GroupKind k) {
    switch (k) {
    case GroupKind::kInherit: return "group";
    case GroupKind::kDefer: return "deferred group";
    case GroupKind::kModulate: return "importance-modulated group";
    case GroupKind::kBudget: return "time-constrained group";
    }
    return "group";
}

std::string print(const Sequence& seq) {
    std::string out;
    for (const auto& item : seq) {
        std::string text;
        switch (item.kind) {
        case ItemKind::kComponent: text += component_letter(item.component); break;
        case ItemKind::kGroup:
            text += group_open_char(item.group);
            text += print(item.body);
            text += group_close_char(item.group);
            break;
        case ItemKind::kError: text += '?'; break;
        }
        bool last_was_integer = false;
        for (const auto& r : item.repeats) {
            if (!r.star && last_was_integer) text = "(" + text + ")";
            text += r.star ? std::string("*") : std::to_string(r.count);
            last_was_integer = !r.star;
        }
        out += text;
    }
    return out;
}

std::string print(const Crex& crex) { return print(crex.body); }

bool same_structure(const Sequence& a, const Sequence& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
        const Item& x = a[i];
        const Item& y = b[i];
        if (x.kind != y.kind || x.repeats.size() != y.repeats.size()) return false;
        if (x.kind == ItemKind::kComponent && x.component != y.component) return false;
        if (x.kind == ItemKind::kGroup &&
            (x.group != y.group || !same_structure(x.body, y.body)))
            return false;
        for (size_t r = 0; r < x.repeats.size(); ++r)
            if (x.repeats[r].star != y.repeats[r].star || x.repeats[r].count != y.repeats[r].count)
                return false;
    }
    return true;
}

}  // namespace crex::ast
