#include "compiler/plan/emit_plan.h"

#include <fmt/format.h>

#include "compiler/sched/print.h"

namespace crex {
namespace {

using sched::Node;
using sched::Op;

nlohmann::json node_json(const Node& n) {
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
        for (const auto& c : n.children) j["children"].push_back(node_json(c));
    }
    return j;
}

// Quotes and backslashes escaped, except the "\n" line breaks our labels use.
std::string escape(const std::string& s) {
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

struct DotWriter {
    std::string out;
    int next_id = 0;
    std::string last;  // id of the last step emitted, for the execution-order chain

    std::string step(const std::string& label, const std::string& tooltip, bool dead) {
        std::string id = fmt::format("n{}", next_id++);
        out += fmt::format("    {} [label=\"{}\", tooltip=\"{}\"{}];\n", id, escape(label), escape(tooltip),
                           dead ? ", style=\"dashed\", color=\"gray50\", fontcolor=\"gray50\"" : ", style=\"filled\", fillcolor=\"#e8f0fe\"");
        if (!last.empty()) out += fmt::format("    {} -> {};\n", last, id);
        last = id;
        return id;
    }

    void node(const Node& n) {
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
            std::string first_before = last;
            int first_id = next_id;
            node(n.children.front());
            if (next_id > first_id) {  // back edge from the loop's last step to its first
                std::string label = n.op == Op::kRepeat ? fmt::format("x{}", n.count) : "* while work";
                out += fmt::format("    {} -> n{} [label=\"{}\", style=\"bold\", color=\"#c5221f\", constraint=false];\n", last,
                                   first_id, label);
            }
            (void)first_before;
            return;
        }
        case Op::kDefer:
        case Op::kBudgeted:
        case Op::kModulate: {
            std::string title = n.op == Op::kDefer       ? "< > deferred"
                                : n.op == Op::kBudgeted ? "[ ] time-constrained task"
                                                         : fmt::format("{{ }} modulated by {} (n = {})", n.map, n.occurrences);
            out += fmt::format("    subgraph cluster_{} {{\n    label=\"{}\"; style=\"rounded\";\n", next_id, escape(title));
            for (const auto& c : n.children) node(c);
            out += "    }\n";
            return;
        }
        }
    }
};

}  // namespace

nlohmann::json plan_to_json(const CrexPlan& plan) {
    nlohmann::json j;
    j["format"] = "crex-plan";
    j["version"] = kPlanFormatVersion;
    j["crex"] = {{"source", plan.source}, {"canonical", sched::to_crex(plan.program)}};
    if (plan.where.known()) j["crex"]["at"] = plan.where.to_string();
    j["scene"] = plan.scene.empty() ? nlohmann::json(nullptr)
                                    : nlohmann::json{{"spec", plan.scene}, {"census_hash", plan.census_hash}};
    j["stages"] = {{"preselective", node_json(plan.program.preselective)}, {"selective", node_json(plan.program.selective)}};
    j["pruned"] = nlohmann::json::array();
    for (const auto& d : plan.pruned)
        j["pruned"].push_back({{"what", fmt::format("step {}", component_letter(d.component))},
                               {"at", d.where.to_string()},
                               {"reason", d.reason}});
    return j;
}

std::string plan_to_dot(const CrexPlan& plan) {
    DotWriter w;
    w.out = "digraph crex_plan {\n  rankdir=LR;\n  node [shape=box, fontname=\"Helvetica\"];\n";
    w.out += fmt::format("  label=\"{}\"; labelloc=t;\n", escape("crex " + plan.source + (plan.scene.empty() ? "" : " on " + plan.scene)));
    w.out += "  camera [label=\"camera rays\", shape=ellipse];\n";
    w.last = "camera";
    const char* names[] = {"pre-selective", "selective"};
    const Node* stages[] = {&plan.program.preselective, &plan.program.selective};
    for (int s = 0; s < 2; ++s) {
        w.out += fmt::format("  subgraph cluster_stage{} {{\n    label=\"{}\"; style=\"filled\"; fillcolor=\"#f8f9fa\";\n", s, names[s]);
        w.node(*stages[s]);
        if (s == 1 && stages[s]->children.empty()) w.out += "    none [label=\"(none)\", shape=plaintext];\n";
        w.out += "  }\n";
    }
    if (!plan.pruned.empty()) {
        w.out += "  subgraph cluster_pruned {\n    label=\"pruned for this scene\"; style=\"dashed\";\n";
        std::string keep_last = w.last;
        w.last.clear();
        for (const auto& d : plan.pruned) {
            w.last.clear();  // pruned steps run in no order: no edges between them
            w.step(fmt::format("{}\\n{}", component_letter(d.component), d.where.to_string()), d.reason, true);
        }
        w.last = keep_last;
        w.out += "  }\n";
    }
    w.out += "}\n";
    return w.out;
}

std::string plan_to_text(const CrexPlan& plan) {
    std::string out = fmt::format("plan of {}{}\n", plan.source.empty() ? "(empty crex)" : plan.source,
                                  plan.scene.empty() ? "" : " for " + plan.scene);
    std::string pre = sched::to_crex(plan.program.preselective), sel = sched::to_crex(plan.program.selective);
    out += fmt::format("  executes:      {}\n", sched::to_crex(plan.program).empty() ? "camera rays only" : sched::to_crex(plan.program));
    out += fmt::format("  pre-selective: {}\n", pre.empty() ? "camera rays only" : pre);
    out += fmt::format("  selective:     {}\n", sel.empty() ? "none" : sel);
    if (!plan.census_hash.empty()) out += fmt::format("  census hash:   {}\n", plan.census_hash);
    for (const auto& d : plan.pruned) out += fmt::format("  pruned {} at {}: {}\n", component_letter(d.component), d.where.to_string(), d.reason);
    return out;
}

}  // namespace crex
