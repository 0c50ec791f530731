#include "compiler/plan/bin_occupancy.h"

#include <fmt/format.h>

#include <map>

namespace crex {
namespace {

using sched::Node;
using sched::Op;

// Abstract state: bins that may be non-empty, and (inside a deferral) bins that may receive
// held-back rays.
struct State {
    BinSet may;
    BinSet pending;
    bool deferring = false;
};

class Analysis {
public:
    explicit Analysis(const BinSet& spawnable) : spawnable_(spawnable) {}

    /// Live Exec nodes, by address.
    std::map<const Node*, bool> live;

    void run(const Node& n, State& s) {
        switch (n.op) {
        case Op::kExec: {
            bool has_work = s.may.test(static_cast<size_t>(n.component));
            live[&n] = live[&n] || has_work;
            if (has_work) (s.deferring ? s.pending : s.may) |= spawnable_;
            return;
        }
        case Op::kSeq:
        case Op::kModulate:
            for (const auto& c : n.children) run(c, s);
            return;
        case Op::kDefer:
        case Op::kBudgeted: {
            bool owns = (n.op == Op::kDefer || n.owns_deferral) && !s.deferring;
            if (!owns) {
                for (const auto& c : n.children) run(c, s);
                return;
            }
            s.deferring = true;
            for (const auto& c : n.children) run(c, s);
            s.deferring = false;
            s.may |= s.pending;
            s.pending.reset();
            return;
        }
        case Op::kRepeat:
        case Op::kRepeatUntilEmpty: {
            // Iterate to a fixpoint: the lattice has 2^6 points, so this ends quickly. A repeat
            // of k runs at most k times, but more iterations only add possibilities.
            uint64_t bound = n.op == Op::kRepeat ? n.count : UINT64_MAX;
            for (uint64_t k = 0; k < bound; ++k) {
                State before = s;
                run(n.children.front(), s);
                if (s.may == before.may && s.pending == before.pending && k > 0) break;
            }
            return;
        }
        }
    }

private:
    BinSet spawnable_;
};

void collect_dead(const Node& n, const std::map<const Node*, bool>& live, std::vector<DeadStep>& out) {
    if (n.op == Op::kExec) {
        auto it = live.find(&n);
        if (it == live.end() || !it->second) out.push_back({n.component, n.where, dead_step_reason(n.component)});
        return;
    }
    for (const auto& c : n.children) collect_dead(c, live, out);
}

// Copy of `n` without dead Exec nodes; nullopt when nothing is left of it.
std::optional<Node> without_dead(const Node& n, const std::map<const Node*, bool>& live) {
    if (n.op == Op::kExec) {
        auto it = live.find(&n);
        if (it == live.end() || !it->second) return std::nullopt;
        return n;
    }
    Node copy = n;
    copy.children.clear();
    for (const auto& c : n.children)
        if (auto kept = without_dead(c, live)) copy.children.push_back(std::move(*kept));
    if (copy.children.empty() && !n.children.empty()) return std::nullopt;
    if (copy.children.empty() && n.op != Op::kSeq) return std::nullopt;  // empty groups do nothing
    // A repeat of a one-child sequence repeats that child.
    if ((n.op == Op::kRepeat || n.op == Op::kRepeatUntilEmpty) && copy.children.front().op == Op::kSeq &&
        copy.children.front().children.size() == 1) {
        Node only = std::move(copy.children.front().children.front());
        copy.children.front() = std::move(only);
    }
    return copy;
}

Node prune_stage(const Node& stage, const BinSet& spawnable, State& state) {
    Analysis a(spawnable);
    a.run(stage, state);
    auto kept = without_dead(stage, a.live);
    if (kept) return *kept;
    Node empty;
    empty.op = Op::kSeq;
    return empty;
}

}  // namespace

std::string dead_step_reason(Component c) {
    const ComponentInfo& info = component_info(c);
    return fmt::format("bin {} can never be non-empty: no material in use spawns {} rays ({} comes from {})", info.letter,
                       info.name, info.letter, info.spawned_by);
}

std::vector<DeadStep> find_dead_steps(const sched::Program& program, const BinSet& spawnable) {
    std::vector<DeadStep> out;
    State s;
    s.may = spawnable;  // camera rays may fill every spawnable bin
    for (const Node* stage : {&program.preselective, &program.selective}) {
        Analysis a(spawnable);
        a.run(*stage, s);
        collect_dead(*stage, a.live, out);
    }
    return out;
}

sched::Program prune_dead_steps(const sched::Program& program, const BinSet& spawnable) {
    State s;
    s.may = spawnable;
    sched::Program out;
    out.preselective = prune_stage(program.preselective, spawnable, s);
    out.selective = prune_stage(program.selective, spawnable, s);
    return out;
}

}  // namespace crex
