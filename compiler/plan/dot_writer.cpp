#include "compiler/plan/dot_writer.h"

#include <fmt/format.h>

namespace crex {

using sched::Node;
using sched::Op;

nlohmann::json schedule_to_json(const Node& n) {
    nlohmann::json j;
    j["op"] = std::string(sched::op_name(n.op));
    if (n.where.known()) j["at"] = n.where.to_string();
    switch (n.op) {
    case Op::kExec:
        j["component"] = std::string(1, component_letter(n.component));
        if (n.first_index >= 0) j["occurrence"] = n.first_index;
        break;
    case Op::kRepeat:
        j["count"] = n.count;
        if (n.stride > 0) j["stride"] = n.stride;
        break;
    case Op::kRepeatUntilEmpty: j["cap"] = n.cap; break;
    case Op::kModulate:
        j["occurrences"] = n.occurrences;
        j["map"] = n.map;
        break;
    case Op::kBudgeted: j["owns_deferral"] = n.owns_deferral; break;
    default: break;
    }
    if (!n.children.empty()) {
        j["children"] = nlohmann::json::array();
        for (const auto& c : n.children) j["children"].push_back(schedule_to_json(c));
    }
    return j;
}

// Quotes and backslashes escaped, except the "\n" line breaks our labels use.
std::string escape_dot(const std::string& s) {
    std::string out;
    for (size_t i = 0; i < s.size(); ++i) {
        char c = s[i];
        if (c == '\\' && i + 1 < s.size() && s[i + 1] == 'n') {
            out += "\\n";
            ++i;
            continue;
        }
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out;
}

std::string DotWriter::step(const std::string& label, const std::string& tooltip, bool dead) {
        std::string id = fmt::format("n{}", next_id++);
        out += fmt::format("    {} [label=\"{}\", tooltip=\"{}\"{}];\n", id, escape_dot(label), escape_dot(tooltip),
                           dead ? ", style=\"dashed\", color=\"gray50\", fontcolor=\"gray50\"" : ", style=\"filled\", fillcolor=\"#e8f0fe\"");
        if (!last.empty()) out += fmt::format("    {} -> {};\n", last, id);
        last = id;
        return id;
    }

void DotWriter::node(const Node& n) {
        switch (n.op) {
        case Op::kExec: {
            std::string label = std::string(1, component_letter(n.component));
            if (n.first_index >= 0) label += fmt::format("\\n#{}", n.first_index);
            step(label, n.where.to_string(), false);
            return;
        }
        case Op::kSeq:
            for (const auto& c : n.children) node(c);
            return;
        case Op::kRepeat:
        case Op::kRepeatUntilEmpty: {
            int first_id = next_id;
            node(n.children.front());
            if (next_id > first_id) {  // back edge from the loop's last step to its first
                std::string label = n.op == Op::kRepeat ? fmt::format("x{}", n.count) : "* while work";
                out += fmt::format("    {} -> n{} [label=\"{}\", style=\"bold\", color=\"#c5221f\", constraint=false];\n", last,
                                   first_id, label);
            }
            return;
        }
        case Op::kDefer:
        case Op::kBudgeted:
        case Op::kModulate: {
            std::string title = n.op == Op::kDefer       ? "< > deferred"
                                : n.op == Op::kBudgeted ? "[ ] time-constrained task"
                                                         : fmt::format("{{ }} modulated by {} (n = {})", n.map, n.occurrences);
            out += fmt::format("    subgraph cluster_{} {{\n    label=\"{}\"; style=\"rounded\";\n", next_id, escape_dot(title));
            for (const auto& c : n.children) node(c);
            out += "    }\n";
            return;
        }
        }
    }



}  // namespace crex
