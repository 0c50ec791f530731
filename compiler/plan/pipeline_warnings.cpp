#include "compiler/plan/pipeline_warnings.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <unordered_map>
#include <unordered_set>

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

// The largest value a map can take, from its definition (1 when it cannot be told): constants,
// thresholds, weighted importance and what they are built from. Maps are defined above their
// use and chains are at most 256 long (E214), so the recursion ends.
// The maps by name, and the bound of each one already found: a map read twice by each of a
// chain of maps would otherwise be bounded 2^256 times.
struct MapIndex {
    std::unordered_map<std::string, const pipeline::ast::Expr*> defs;
    std::unordered_map<std::string, double> bound;
};

double upper_bound(const pipeline::ast::Expr& e, MapIndex& p, int depth = 0) {
    using K = pipeline::ast::Expr::Kind;
    if (depth > 300) return 1;
    if (e.kind == K::kReference) {
        if (auto b = p.bound.find(e.name); b != p.bound.end()) return b->second;
        auto it = p.defs.find(e.name);
        if (it == p.defs.end()) return 1;  // preview, buffers: not maps
        const double u = upper_bound(*it->second, p, depth + 1);
        p.bound[e.name] = u;
        return u;
    }
    if (e.kind != K::kCall) return 1;
    auto positional = [&](size_t i) -> const pipeline::ast::Expr* {
        size_t k = 0;
        for (const auto& a : e.args)
            if (a.name.empty() && k++ == i) return &a.expr;
        return nullptr;
    };
    auto named = [&](const std::string& n) -> const pipeline::ast::Value* {
        for (const auto& a : e.args)
            if (a.name == n) return &a.value;
        return nullptr;
    };
    if (e.name == "constant") {
        const auto* v = positional(0);
        return v && v->kind == K::kLiteral ? std::clamp(v->literal.number, 0.0, 1.0) : 1;
    }
    if (e.name == "blur" || e.name == "normalise") {
        const auto* m = positional(0);
        double u = m ? upper_bound(*m, p, depth + 1) : 1;
        return e.name == "normalise" && u > 0 ? 1 : u;
    }
    if (e.name == "threshold") {
        const auto* m = positional(0);
        const auto* at = named("at");
        return m && upper_bound(*m, p, depth + 1) < (at ? at->number : 0.5) ? 0 : 1;
    }
    if (e.name == "importance") {
        const auto* opv = named("op");
        const std::string op = opv ? opv->text : "+";
        double sum = 0, mx = 0, prod = 1;
        bool any = false;
        for (const auto& a : e.args) {
            if (a.name == "op") continue;
            pipeline::ast::Expr ref;
            ref.name = a.name;
            double u = a.name.empty() ? upper_bound(a.expr, p, depth + 1) : a.value.number * upper_bound(ref, p, depth + 1);
            sum += u, mx = std::max(mx, u), prod *= u, any = true;
        }
        if (!any) return 0;
        return std::clamp(op == "max" ? mx : op == "*" ? prod : sum, 0.0, 1.0);
    }
    return 1;
}

// Every executed component occurrence inside a `{ }` with its index at the first iteration.
void modulated_steps(const sched::Node& node, const sched::Node* modulate, std::vector<std::pair<const sched::Node*, const sched::Node*>>& out) {
    if (node.op == sched::Op::kModulate) modulate = &node;
    if (node.op == sched::Op::kExec && modulate && node.first_index >= 0) out.push_back({modulate, &node});
    for (const auto& c : node.children) modulated_steps(c, modulate, out);
}

}  // namespace

void warn_unreachable_modulated_steps(const pipeline::ResolvedPipeline& p, const PipelinePlan& plan, DiagnosticSink& sink) {
    if (!p.selective.crex_by) return;
    MapIndex maps;
    for (const auto& [name, def] : p.maps) maps.defs[name] = &def;
    const double u = upper_bound(*p.selective.crex_by, maps);
    if (!(u < 1)) return;
    std::vector<std::pair<const sched::Node*, const sched::Node*>> steps;
    modulated_steps(plan.program.selective, nullptr, steps);
    std::string never;
    double n = 0;
    for (const auto& [mod, exec] : steps) {
        // Occurrence i runs in pixel p only if i < ceil(I(p) n) (spec/crex.md §3).
        if (exec->first_index >= std::ceil(u * mod->occurrences)) {
            if (never.find(kComponentTable[static_cast<size_t>(exec->component)].letter) == std::string::npos)
                never += kComponentTable[static_cast<size_t>(exec->component)].letter;
            n = mod->occurrences;
        }
    }
    if (never.empty()) return;
    sink.report("W205", p.selective.crex_by->span,
                fmt::format("this map is at most {:g}, so `{{ }}` runs only the first {:g} of its {:g} occurrences: {} never run{}", u,
                            std::ceil(u * n), n, never, never.size() == 1 ? "s" : ""))
        .help = "raise the map's weights (importance(..., op \"+\") of weights summing to 1 reaches 1) or move those letters earlier in the braces";
}

namespace {
// The expressions guidance evaluates: every map and `by` the planner kept.
std::vector<const pipeline::ast::Expr*> used_expressions(const pipeline::ResolvedPipeline& p, const PipelinePlan& plan) {
    std::vector<const pipeline::ast::Expr*> roots;
    // A map the planner pruned (its only consumer was, e.g. `vary subsample(G)` on a scene
    // without glossy materials) is listed as pruned with its reason; a warning about what it
    // reads would only repeat that (capict.pipe warned twice on every Cornell run). A set:
    // 50,000 unused maps are 50,000 removals.
    std::unordered_set<std::string> removed;
    for (const PlanRemoval& x : plan.pruned) removed.insert(x.what);
    auto pruned = [&](const std::string& what) { return removed.count(what) > 0; };
    for (const auto& [name, e] : p.maps)
        if (!pruned("map " + name)) roots.push_back(&e);
    for (const auto& v : p.vary)
        if (!pruned("vary " + v.varied())) roots.push_back(&v.by);
    if (p.selective.crex_by) roots.push_back(&*p.selective.crex_by);
    return roots;
}
}  // namespace

void warn_scene_mismatches(const pipeline::ResolvedPipeline& p, const PipelinePlan& plan, const std::vector<std::string>* scene_tags,
                           DiagnosticSink& sink) {
    static const std::vector<std::string> none;
    const std::vector<std::string>& tags = scene_tags ? *scene_tags : none;
    for (const auto* root : used_expressions(p, plan))
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

void warn_noise_of_one_sample(const pipeline::ResolvedPipeline& p, const PipelinePlan& plan, DiagnosticSink& sink) {
    // A pixel has two samples before guidance runs if the preview or the selective floor
    // gives them (a later round sees what earlier rounds added, but with the map at 0 they
    // added nothing).
    if (plan.settings.spp >= 2 || plan.settings.selective_spp.value_or(1) >= 2) return;
    for (const auto* root : used_expressions(p, plan))
        each_call(*root, [&](const pipeline::ast::Expr& call) {
            if (call.name != "noise") return;
            sink.report("W206", call.span,
                        "noise() compares each pixel's even and odd samples, but the preview takes 1 sample a pixel: the map is 0 "
                        "everywhere")
                .help = "give the pre-selective stage 'spp 2' or more (as adaptive.pipe does)";
        });
}

void warn_media_without_medium(const pipeline::ResolvedPipeline& p, bool scene_has_medium, DiagnosticSink& sink) {
    if (scene_has_medium) return;
    for (const auto& v : p.vary)
        if (v.name == "media_samples")
            sink.report("W403", v.lo.span, "'media_samples' has no effect: the scene has no participating medium")
                .help = "give the scene a \"medium\" (docs/scene-format.md), or leave media_samples out";
}

}  // namespace crex
