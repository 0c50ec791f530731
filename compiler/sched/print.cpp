#include "compiler/sched/print.h"

#include <fmt/format.h>

namespace crex::sched {
namespace {

bool contains_modulate(const Node& n) {
    if (n.op == Op::kModulate) return true;
    for (const auto& c : n.children)
        if (contains_modulate(c)) return true;
    return false;
}

void print_children(std::string& out, const Node& n);

// Prints `n` as one crex atom (something a repeat can follow).
void print_atom(std::string& out, const Node& n) {
    switch (n.op) {
    case Op::kExec: out += component_letter(n.component); return;
    case Op::kSeq: out += '('; print_children(out, n); out += ')'; return;
    case Op::kDefer: out += '<'; print_children(out, n); out += '>'; return;
    case Op::kBudgeted: out += '['; print_children(out, n); out += ']'; return;
    case Op::kModulate: out += '{'; print_children(out, n); out += '}'; return;
    case Op::kRepeat:
    case Op::kRepeatUntilEmpty: {
        const Node& body = n.children.front();
        // `D2 3` is E009, so a count directly after a count needs parentheses.
        bool wrap = n.op == Op::kRepeat && body.op == Op::kRepeat;
        if (wrap) out += '(';
        print_atom(out, body);
        if (wrap) out += ')';
        out += n.op == Op::kRepeat ? std::to_string(n.count) : std::string("*");
        return;
    }
    }
}

void print_children(std::string& out, const Node& n) {
    for (const auto& c : n.children) {
        if (c.op == Op::kSeq) print_children(out, c);  // a bare sequence needs no brackets
        else print_atom(out, c);
    }
}

}  // namespace

std::string to_crex(const Node& node) {
    std::string out;
    if (node.op == Op::kSeq) print_children(out, node);
    else print_atom(out, node);
    return out;
}

std::string to_crex(const Program& program) {
    std::string pre = to_crex(program.preselective);
    std::string sel = to_crex(program.selective);
    // The split is re-derived from the text: a selective part that starts with steps outside
    // any `{ }` must stay one top-level item, or they would be read as pre-selective.
    if (!program.selective.children.empty() && !contains_modulate(program.selective.children.front()))
        sel = "(" + sel + ")";
    return pre + sel;
}

namespace {

void dump_node(std::string& out, const Node& n, int depth) {
    out += std::string(static_cast<size_t>(depth) * 2, ' ');
    out += op_name(n.op);
    switch (n.op) {
    case Op::kExec:
        out += fmt::format(" {}", component_letter(n.component));
        if (n.first_index >= 0) out += fmt::format(" index={}", n.first_index);
        break;
    case Op::kRepeat:
        out += fmt::format(" {}", n.count);
        if (n.stride > 0) out += fmt::format(" stride={}", n.stride);
        break;
    case Op::kRepeatUntilEmpty: out += fmt::format(" cap={}", n.cap); break;
    case Op::kModulate: out += fmt::format(" n={} map={}", n.occurrences, n.map); break;
    case Op::kBudgeted: out += n.owns_deferral ? " defers" : " (deferral of the enclosing group)"; break;
    default: break;
    }
    out += '\n';
    for (const auto& c : n.children) dump_node(out, c, depth + 1);
}

std::string fraction(double num, double den) {
    if (num == 0) return "0";
    if (num < 1e15 && den < 1e15 && num == static_cast<double>(static_cast<uint64_t>(num)) &&
        den == static_cast<double>(static_cast<uint64_t>(den))) {
        uint64_t a = static_cast<uint64_t>(num), b = static_cast<uint64_t>(den);
        uint64_t x = a, y = b;
        while (y) { uint64_t t = x % y; x = y; y = t; }
        a /= x, b /= x;
        return b == 1 ? std::to_string(a) : fmt::format("{}/{}", a, b);
    }
    return fmt::format("{:.6g}", num / den);
}

struct Explainer {
    std::string out;
    double modulate_n = 0;
    std::vector<double> strides;  // of the repeats between the current node and its Modulate

    void line(const std::string& number, int depth, const std::string& text) {
        out += fmt::format("{}{}. {}\n", std::string(static_cast<size_t>(depth) * 3, ' '), number, text);
    }

    void children(const Node& n, const std::string& prefix, int depth) {
        int i = 1;
        for (const auto& c : n.children)
            node(c, prefix.empty() ? std::to_string(i++) : fmt::format("{}.{}", prefix, i++), depth);
    }

    void node(const Node& n, const std::string& number, int depth) {
        switch (n.op) {
        case Op::kExec: {
            std::string what = fmt::format("{}: execute the {} rays waiting in bin {}",
                                           component_letter(n.component), component_info(n.component).name,
                                           component_letter(n.component));
            if (n.first_index >= 0) {
                std::string cond = fmt::format("needs I > {}", fraction(n.first_index, modulate_n));
                if (!strides.empty()) {
                    std::string terms;
                    for (size_t k = 0; k < strides.size(); ++k)
                        terms += fmt::format(" + {}·j{}", strides[k], k + 1);
                    cond = fmt::format("needs I > ({}{})/{} in iteration j of the enclosing repeats",
                                       n.first_index, terms, modulate_n);
                }
                what += "; " + cond;
            }
            line(number, depth, what);
            return;
        }
        case Op::kSeq:
            line(number, depth, "in order:");
            children(n, number, depth + 1);
            return;
        case Op::kDefer:
            line(number, depth, "deferred: these steps read only rays that exist now; rays they "
                                "spawn are merged into the bins when the group ends:");
            children(n, number, depth + 1);
            return;
        case Op::kBudgeted:
            line(number, depth,
                 std::string("time-constrained task: under a budget it runs only if predicted to "
                             "finish in time; ") +
                     (n.owns_deferral ? "otherwise deferred like < >:"
                                      : "its spawned rays wait for the enclosing deferred group:"));
            children(n, number, depth + 1);
            return;
        case Op::kModulate: {
            double saved = modulate_n;
            auto saved_strides = strides;
            modulate_n = n.occurrences;
            strides.clear();
            line(number, depth,
                 fmt::format("modulated by the map '{}' (n = {}): occurrence i runs a ray of pixel p "
                             "only if I(p) > i/{}:", n.map, n.occurrences, n.occurrences));
            children(n, number, depth + 1);
            modulate_n = saved;
            strides = saved_strides;
            return;
        }
        case Op::kRepeat:
            line(number, depth, fmt::format("repeat {} times:", n.count));
            if (n.stride > 0) strides.push_back(n.stride);
            node(n.children.front(), number + ".1", depth + 1);
            if (n.stride > 0) strides.pop_back();
            return;
        case Op::kRepeatUntilEmpty:
            line(number, depth, fmt::format("repeat while the last iteration had work (at least once, "
                                            "at most {} times):", n.cap));
            node(n.children.front(), number + ".1", depth + 1);
            return;
        }
    }
};

}  // namespace

std::string dump(const Program& program) {
    std::string out = "preselective:\n";
    dump_node(out, program.preselective, 1);
    out += "selective:\n";
    dump_node(out, program.selective, 1);
    return out;
}

std::string explain(const Program& program) {
    Explainer e;
    e.out += "camera rays are traced first (always; not written in the crex)\n";
    if (program.preselective.children.empty()) {
        e.out += "pre-selective stage: camera rays only\n";
    } else {
        e.out += "pre-selective stage:\n";
        e.children(program.preselective, "", 1);
    }
    if (program.selective.children.empty()) {
        e.out += "selective stage: none (the crex has no '{ }')\n";
    } else {
        e.out += "selective stage (after guidance):\n";
        int first = static_cast<int>(program.preselective.children.size()) + 1;
        for (const auto& c : program.selective.children) e.node(c, std::to_string(first++), 1);
    }
    e.out += "rays still in bins when the crex ends are dropped (the ambient value stands in for D)\n";
    return e.out;
}

}  // namespace crex::sched
