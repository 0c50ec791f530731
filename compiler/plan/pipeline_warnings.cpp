#include "compiler/plan/pipeline_warnings.h"

#include <fmt/format.h>

#include <algorithm>
#include <functional>

#include "base/components.h"

namespace crex {
namespace {

bool executes(const sched::Node& node, Component c) {
    if (node.op == sched::Op::kExec) return node.component == c;
    return std::any_of(node.children.begin(), node.children.end(), [&](const sched::Node& n) { return executes(n, c); });
}

void each_call(const pipeline::ast::Expr& e, const std::function<void(const pipeline::ast::Expr&)>& f) {
    if (e.kind != pipeline::ast::Expr::Kind::kCall) return;
    f(e);
    for (const auto& a : e.args) each_call(a.expr, f);
}

}  // namespace

void warn_scene_mismatches(const pipeline::ResolvedPipeline& p, const PipelinePlan& plan, const std::vector<std::string>* scene_tags,
                           DiagnosticSink& sink) {
    static const std::vector<std::string> none;
    const std::vector<std::string>& tags = scene_tags ? *scene_tags : none;
    std::vector<const pipeline::ast::Expr*> roots;
    for (const auto& [name, e] : p.maps) roots.push_back(&e);
    for (const auto& v : p.vary) roots.push_back(&v.by);
    if (p.selective.crex_by) roots.push_back(&*p.selective.crex_by);
    for (const auto* root : roots)
        each_call(*root, [&](const pipeline::ast::Expr& call) {
            if (scene_tags && call.name == "tagged" && !call.args.empty() && call.args[0].expr.kind == pipeline::ast::Expr::Kind::kLiteral) {
                const auto& tag = call.args[0].expr.literal;
                if (std::find(tags.begin(), tags.end(), tag.text) == tags.end()) {
                    std::string known;
                    for (const auto& t : tags) known += (known.empty() ? "" : ", ") + ("'" + t + "'");
                    sink.report("W203", tag.span, fmt::format("no object of the scene is tagged '{}': the task map is 0 everywhere", tag.text))
                        .help = tags.empty() ? "tag the task objects in the scene (docs/scene-format.md: \"tag\")"
                                             : "the scene's tags: " + known;
                }
            }
            if (call.name == "component" && !call.args.empty() && call.args[0].expr.kind == pipeline::ast::Expr::Kind::kReference &&
                call.args[0].expr.name.size() == 1) {
                auto c = component_from_letter(call.args[0].expr.name[0]);
                if (c && !executes(plan.program.preselective, *c))
                    sink.report("W204", call.span,
                                fmt::format("component({}) is read by guidance, but the pre-selective crex never executes {}: the "
                                            "buffer is 0 everywhere",
                                            call.args[0].expr.name, call.args[0].expr.name))
                        .help = fmt::format("let the pre-selective crex execute {} (or the scene cannot produce it)", call.args[0].expr.name);
            }
        });
}

}  // namespace crex
