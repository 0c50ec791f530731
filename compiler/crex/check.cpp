#include "compiler/crex/check.h"

#include <fmt/format.h>

#include "compiler/crex/occurrences.h"

namespace crex {
namespace {

using ast::GroupKind;
using ast::Item;
using ast::ItemKind;
using ast::Sequence;

// One component occurrence inside a deferred execution, for W102. `threshold` is the
// importance a pixel must exceed for the step to run there: -1 when not modulated (runs
// everywhere, also where I = 0), i/n for occurrence i of a `{ }` with n occurrences.
struct DeferredOccurrence {
    Component component;
    double threshold;
};

struct Context {
    const Item* modulate = nullptr;  // innermost enclosing { }
    const Item* budget = nullptr;    // innermost enclosing [ ]
    const Item* deferral = nullptr;  // outermost enclosing < > or [ ]: owns the deferral
    double modulate_n = 0;           // occurrences of `modulate`
    double* modulate_offset = nullptr;  // running occurrence index inside `modulate`
    std::vector<DeferredOccurrence>* deferred = nullptr;
};

bool ends_in_star(const Item& item) {
    if (!item.repeats.empty()) return item.repeats.back().star;
    if (item.kind == ItemKind::kGroup && !item.body.empty()) return ends_in_star(item.body.back());
    return false;
}

class Checker {
public:
    explicit Checker(DiagnosticSink& sink) : sink_(sink) {}

    void check_sequence(const Sequence& seq, Context ctx) {
        for (const auto& item : seq) check_item(item, ctx);
    }

private:
    DiagnosticNote opens_here(const Item& group) {
        return {group.open_span, fmt::format("the {} opens here", ast::group_kind_name(group.group))};
    }

    void check_item(const Item& item, Context ctx) {
        check_repeats(item, ctx);
        if (item.kind == ItemKind::kComponent) check_deferred_occurrence(item, ctx);
        if (item.kind == ItemKind::kGroup) check_group(item, ctx);
    }

    void check_repeats(const Item& item, const Context& ctx) {
        bool previous_integer = false;
        bool previous_star = false;
        for (size_t i = 0; i < item.repeats.size(); ++i) {
            const ast::Repeat& r = item.repeats[i];
            if (!r.star && (r.count < 1 || r.count > kMaxRepeatCount)) {
                std::string text(r.span.text());
                sink_.report("E003", r.span,
                             fmt::format("repeat count {} is out of range: it must be an integer in "
                                         "1 .. 2147483647", text));
            }
            if (!r.star && previous_integer) {
                Item head = item;
                head.repeats.resize(i);
                std::string atom = ast::print(Sequence{head});
                sink_.report("E009", r.span, "an integer repeat directly after an integer repeat")
                    .help = fmt::format("write '({}){}' to repeat the repeated item", atom,
                                        std::string(r.span.text()));
            }
            if (r.star && ctx.modulate) {
                Diagnostic& d = sink_.report(
                    "E004", r.span, "'*' inside '{ }': unbounded work cannot be importance-modulated");
                d.notes.push_back(opens_here(*ctx.modulate));
            }
            if (r.star && ctx.budget) {
                Diagnostic& d = sink_.report(
                    "E005", r.span, "'*' inside '[ ]': a time-constrained group needs a predictable cost");
                d.notes.push_back(opens_here(*ctx.budget));
            }
            bool repeats_a_star = previous_star || (i == 0 && item.kind == ItemKind::kGroup &&
                                                    !item.body.empty() && ends_in_star(item.body.back()));
            if (repeats_a_star)
                sink_.report("W101", r.span,
                             fmt::format("repeat '{}' of an item that already ends in '*'",
                                         std::string(r.span.text())))
                    .help = "a '*' loop already runs until it has no work; the outer repeat adds little";
            // A '*' in `{ }` or `[ ]` is already an error (E004/E005); W102 would only repeat it.
            bool runs_twice = (r.star && !ctx.modulate && !ctx.budget) || (!r.star && r.count >= 2);
            if (ctx.deferral && runs_twice) {
                Diagnostic& d = sink_.report(
                    "W102", r.span,
                    fmt::format("repeat '{}' inside a deferred group finds no work after the first "
                                "execution", std::string(r.span.text())));
                d.notes.push_back({ctx.deferral->open_span,
                                   "rays spawned inside this group are held back until it ends"});
            }
            previous_integer = !r.star;
            previous_star = r.star;
        }
    }

    // W102 for a second occurrence: an earlier occurrence of the same component in the same
    // deferred execution already took every ray this one could run on.
    void check_deferred_occurrence(const Item& item, Context& ctx) {
        double threshold = -1.0;
        if (ctx.modulate && ctx.modulate_n > 0) threshold = *ctx.modulate_offset / ctx.modulate_n;
        if (ctx.modulate_offset) *ctx.modulate_offset += repeat_multiplier(item);
        if (!ctx.deferred) return;
        for (const auto& earlier : *ctx.deferred) {
            if (earlier.component == item.component && earlier.threshold <= threshold) {
                Diagnostic& d = sink_.report(
                    "W102", item.span,
                    fmt::format("'{}' finds no work: an earlier '{}' in this deferred group already "
                                "took its rays", component_letter(item.component),
                                component_letter(item.component)));
                d.notes.push_back({ctx.deferral->open_span,
                                   "rays spawned inside this group are held back until it ends"});
                break;
            }
        }
        ctx.deferred->push_back({item.component, threshold});
    }

    void check_group(const Item& item, Context ctx) {
        if (item.body.empty() && item.closed)
            sink_.report("W104", item.span,
                         fmt::format("empty {} '{}{}' does nothing", ast::group_kind_name(item.group),
                                     ast::group_open_char(item.group), ast::group_close_char(item.group)));

        double outer_offset_advance = count_occurrences(item);
        double* outer_offset = ctx.modulate_offset;
        double inner_offset = 0;
        std::vector<DeferredOccurrence> deferred;

        switch (item.group) {
        case GroupKind::kInherit: break;
        case GroupKind::kDefer: break;
        case GroupKind::kModulate:
            if (ctx.modulate) {
                Diagnostic& d = sink_.report("E006", item.open_span, "'{ }' nested inside '{ }'");
                d.notes.push_back(opens_here(*ctx.modulate));
                d.help = "merge the components into the outer '{ }'";
            }
            break;
        case GroupKind::kBudget:
            if (ctx.modulate) {
                Diagnostic& d = sink_.report("E007", item.open_span, "'[ ]' nested inside '{ }'");
                d.notes.push_back(opens_here(*ctx.modulate));
                d.help = "a '{ }' may sit inside a '[ ]', not the other way round";
            }
            if (ctx.budget) {
                Diagnostic& d = sink_.report("W105", item.open_span, "'[ ]' nested in '[ ]' adds nothing");
                d.notes.push_back(opens_here(*ctx.budget));
            }
            ctx.budget = &item;
            break;
        }
        if (item.group == GroupKind::kModulate && !ctx.modulate) {
            ctx.modulate = &item;
            ctx.modulate_n = count_occurrences(item.body);
            ctx.modulate_offset = &inner_offset;
        } else if (ctx.modulate_offset) {
            // Inside a `{ }` a nested group numbers its occurrences on from the running offset;
            // the outer counter advances by everything the group (with repeats) contributes.
            inner_offset = *ctx.modulate_offset;
            ctx.modulate_offset = &inner_offset;
        }
        if ((item.group == GroupKind::kDefer || item.group == GroupKind::kBudget) && !ctx.deferral) {
            ctx.deferral = &item;
            ctx.deferred = &deferred;
        }
        check_sequence(item.body, ctx);
        if (outer_offset && ctx.modulate_offset != outer_offset) *outer_offset += outer_offset_advance;
    }

    DiagnosticSink& sink_;
};

}  // namespace

void check_crex(const ast::Crex& crex, DiagnosticSink& sink) {
    Checker(sink).check_sequence(crex.body, Context{});
}

}  // namespace crex
