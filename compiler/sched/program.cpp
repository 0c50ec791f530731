#include "compiler/sched/program.h"

namespace crex::sched {

std::string_view op_name(Op op) {
    switch (op) {
    case Op::kExec: return "exec";
    case Op::kSeq: return "seq";
    case Op::kDefer: return "defer";
    case Op::kModulate: return "modulate";
    case Op::kBudgeted: return "budgeted";
    case Op::kRepeat: return "repeat";
    case Op::kRepeatUntilEmpty: return "repeat_until_empty";
    }
    return "seq";
}

bool same_structure(const Node& a, const Node& b) {
    if (a.op != b.op || a.component != b.component || a.count != b.count || a.cap != b.cap ||
        a.occurrences != b.occurrences || a.first_index != b.first_index || a.stride != b.stride ||
        a.owns_deferral != b.owns_deferral || a.map != b.map || a.children.size() != b.children.size())
        return false;
    for (size_t i = 0; i < a.children.size(); ++i)
        if (!same_structure(a.children[i], b.children[i])) return false;
    return true;
}

bool same_structure(const Program& a, const Program& b) {
    return same_structure(a.preselective, b.preselective) && same_structure(a.selective, b.selective);
}

}  // namespace crex::sched
