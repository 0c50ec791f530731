#include "compiler/crex/lower.h"

#include "compiler/crex/occurrences.h"

namespace crex {
namespace {

using ast::GroupKind;
using ast::Item;
using ast::ItemKind;
using sched::Node;
using sched::Op;

bool contains_modulate(const Item& item) {
    if (item.kind != ItemKind::kGroup) return false;
    if (item.group == GroupKind::kModulate) return true;
    for (const auto& child : item.body)
        if (contains_modulate(child)) return true;
    return false;
}

class Lowerer {
public:
    explicit Lowerer(const LowerOptions& options) : options_(options) {}

    Node lower_top(const ast::Sequence& items, size_t begin, size_t end) {
        Node seq;
        seq.op = Op::kSeq;
        Scope scope;
        for (size_t i = begin; i < end; ++i) append(seq, lower_item(items[i], scope));
        if (begin < end) seq.where = SourceLocation::of(items[begin].span.merge(items[end - 1].span));
        return seq;
    }

private:
    struct Scope {
        bool in_deferral = false;
        bool in_budget = false;
        bool in_modulate = false;
        double* modulate_offset = nullptr;  // running first-pass occurrence index
    };

    // Appends `node` to `seq`, flattening nested sequences.
    static void append(Node& seq, Node node) {
        if (node.op == Op::kSeq) {
            for (auto& child : node.children) seq.children.push_back(std::move(child));
        } else {
            seq.children.push_back(std::move(node));
        }
    }

    static Node unwrap_single(Node seq) {
        if (seq.op == Op::kSeq && seq.children.size() == 1) return std::move(seq.children[0]);
        return seq;
    }

    Node lower_item(const Item& item, Scope scope) {
        Node node;
        double per_iteration = scope.in_modulate ? count_occurrences(item) / repeat_multiplier(item) : 0;
        double first = scope.modulate_offset ? *scope.modulate_offset : 0;
        if (item.kind == ItemKind::kComponent) {
            node.op = Op::kExec;
            node.component = item.component;
            node.where = SourceLocation::of(item.span);
            if (scope.in_modulate) node.first_index = first;
        } else {
            node = lower_group(item, scope);
        }
        // Repeats wrap from the innermost outwards; inside `{ }` each continues the numbering.
        double stride = per_iteration;
        for (const auto& r : item.repeats) {
            if (!r.star && r.count == 1) continue;
            Node wrap;
            wrap.op = r.star ? Op::kRepeatUntilEmpty : Op::kRepeat;
            wrap.count = r.star ? 0 : r.count;
            wrap.cap = r.star ? options_.star_cap : 0;
            wrap.stride = scope.in_modulate && !r.star ? stride : 0;
            wrap.where = SourceLocation::of(item.span.merge(r.span));
            wrap.children.push_back(unwrap_single(std::move(node)));
            node = std::move(wrap);
            if (!r.star) stride *= static_cast<double>(r.count);
        }
        if (scope.modulate_offset) *scope.modulate_offset = first + count_occurrences(item);
        return node;
    }

    Node lower_group(const Item& item, Scope scope) {
        Node node;
        node.op = Op::kSeq;
        node.where = SourceLocation::of(item.span);
        double inner_offset = scope.modulate_offset ? *scope.modulate_offset : 0;
        switch (item.group) {
        case GroupKind::kInherit: break;
        case GroupKind::kDefer:
            if (!scope.in_deferral) node.op = Op::kDefer, node.owns_deferral = true;
            scope.in_deferral = true;
            break;
        case GroupKind::kBudget:
            if (!scope.in_budget) node.op = Op::kBudgeted, node.owns_deferral = !scope.in_deferral;
            scope.in_deferral = true;
            scope.in_budget = true;
            break;
        case GroupKind::kModulate:
            node.op = Op::kModulate;
            node.occurrences = count_occurrences(item.body);
            node.map = options_.modulation_map;
            scope.in_modulate = true;
            inner_offset = 0;
            break;
        }
        if (scope.in_modulate) scope.modulate_offset = &inner_offset;
        for (const auto& child : item.body) append(node, lower_item(child, scope));
        return node;
    }

    const LowerOptions& options_;
};

}  // namespace

size_t preselective_item_count(const ast::Sequence& top) {
    size_t n = 0;
    while (n < top.size() && !contains_modulate(top[n])) ++n;
    return n;
}

sched::Program lower_crex(const ast::Crex& crex, const LowerOptions& options) {
    // Without `{ }` everything is pre-selective and the selective stage is empty (spec §3).
    size_t split = preselective_item_count(crex.body);
    sched::Program program;
    program.preselective = Lowerer(options).lower_top(crex.body, 0, split);
    program.selective = Lowerer(options).lower_top(crex.body, split, crex.body.size());
    return program;
}

}  // namespace crex
