#include "compiler/plan/emit_plan.h"

#include <fmt/format.h>

#include "compiler/plan/dot_writer.h"
#include "compiler/plan/dot_writer.h"
#include "compiler/sched/print.h"

namespace crex {

using sched::Node;
using sched::Op;

nlohmann::json plan_to_json(const CrexPlan& plan) {
    nlohmann::json j;
    j["format"] = "crex-plan";
    j["version"] = kPlanFormatVersion;
    j["crex"] = {{"source", plan.source}, {"canonical", sched::to_crex(plan.program)}};
    if (plan.where.known()) j["crex"]["at"] = plan.where.to_string();
    j["scene"] = plan.scene.empty() ? nlohmann::json(nullptr)
                                    : nlohmann::json{{"spec", plan.scene}, {"census_hash", plan.census_hash}};
    j["stages"] = {{"preselective", schedule_to_json(plan.program.preselective)}, {"selective", schedule_to_json(plan.program.selective)}};
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
    w.out += fmt::format("  label=\"{}\"; labelloc=t;\n", escape_dot("crex " + plan.source + (plan.scene.empty() ? "" : " on " + plan.scene)));
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
