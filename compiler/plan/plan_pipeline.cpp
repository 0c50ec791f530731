#include "compiler/plan/plan_pipeline.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <numbers>
#include <set>
#include <unordered_map>

#include "compiler/crex/compile.h"
#include "compiler/pipeline/print.h"
#include "compiler/plan/dot_writer.h"
#include "compiler/plan/emit_plan.h"
#include "compiler/sched/print.h"

namespace crex {
namespace {

using pipeline::ast::Expr;
using pipeline::ast::Value;
using pipeline::expr_text;
using pipeline::value_text;

// A literal as the runtime uses it: numbers as numbers (degrees resolved to radians), strings
// without quotes. The checker has already refused other units here.
nlohmann::json value_json(const Value& v) {
    switch (v.kind) {
    case Value::Kind::kNumber: return v.unit == "deg" ? v.number * std::numbers::pi / 180 : v.number;
    case Value::Kind::kString: return v.text;
    case Value::Kind::kBool: return v.boolean;
    case Value::Kind::kCross: return "x";
    }
    return nullptr;
}

// Compiles a stage's crex literal at its position in its file; the whole lowered crex.
std::optional<sched::Node> stage_program(const Value& literal, DiagnosticSink& sink) {
    CompiledCrex c = compile_crex(*literal.text_span.file, literal.text_span.begin, literal.text_span.end, sink);
    if (!c.program) return std::nullopt;
    sched::Node all = c.program->preselective;
    for (auto& child : c.program->selective.children) all.children.push_back(child);
    return all;
}

bool has_exec(const sched::Node& n, Component c) {
    if (n.op == sched::Op::kExec) return n.component == c;
    for (const auto& k : n.children)
        if (has_exec(k, c)) return true;
    return false;
}

// The top-level and stage settings, typed; the checker has range-checked every value.
PlanSettings typed_settings(const pipeline::ResolvedPipeline& p) {
    PlanSettings s;
    auto number = [&](const char* key) -> std::optional<double> {
        auto it = p.top.find(key);
        if (it == p.top.end() || it->second.size() != 1 || it->second[0].kind != Value::Kind::kNumber) return std::nullopt;
        return it->second[0].number;
    };
    auto text = [&](const char* key) -> std::string {
        auto it = p.top.find(key);
        return it == p.top.end() || it->second.empty() ? "" : it->second[0].text;
    };
    if (auto it = p.top.find("image"); it != p.top.end() && it->second.size() == 3) {
        s.width = static_cast<int>(it->second[0].number);
        s.height = static_cast<int>(it->second[2].number);
    }
    if (auto v = number("seed")) s.seed = static_cast<uint64_t>(*v);
    s.lw = number("lw");
    s.av = number("av");
    s.aa = number("aa");
    if (auto v = number("max_depth")) s.max_depth = static_cast<uint32_t>(*v);
    if (auto v = number("ab")) s.ab = static_cast<uint32_t>(*v);
    if (auto v = number("ad")) s.ad = static_cast<uint32_t>(*v);
    for (auto [key, at] : {std::pair{"lw", &s.lw_at}, std::pair{"max_depth", &s.max_depth_at}, std::pair{"ab", &s.ab_at}})
        if (auto it = p.top.find(key); it != p.top.end() && !it->second.empty()) *at = SourceLocation::of(it->second[0].span);
    if (auto it = p.top.find("budget"); it != p.top.end() && it->second.size() == 1) {
        const Value& b = it->second[0];
        s.budget = PlanBudget{b.unit == "ms" ? b.number / 1000 : b.number, b.unit == "%", SourceLocation::of(b.span)};
    }
    if (auto name = text("policy"); !name.empty()) s.policy = pipeline::scheduling_policy_from_name(name);
    s.reference = text("reference");
    if (auto it = p.preselective.settings.find("spp"); it != p.preselective.settings.end()) s.spp = static_cast<uint32_t>(it->second.number);
    if (auto it = p.preselective.settings.find("shadow_rays"); it != p.preselective.settings.end())
        s.shadow_rays = static_cast<uint32_t>(it->second.number);
    if (auto it = p.selective.settings.find("spp"); it != p.selective.settings.end())
        s.selective_spp = static_cast<uint32_t>(it->second.number);
    if (auto it = p.selective.settings.find("rounds"); it != p.selective.settings.end()) s.rounds = static_cast<uint32_t>(it->second.number);
    return s;
}

class GraphBuilder {
public:
    explicit GraphBuilder(PipelinePlan& plan) : plan_(plan) {}

    void node(const std::string& id, const std::string& kind, const std::string& stage, const std::string& label,
              nlohmann::json params = nlohmann::json::object()) {
        if (node_at_.try_emplace(id, plan_.nodes.size()).second) plan_.nodes.push_back({id, kind, stage, label, std::move(params)});
    }
    void add_map(PlanMap def) {
        map_at_.try_emplace(def.id, plan_.maps.size());
        plan_.maps.push_back(std::move(def));
    }
    // By id, in constant time: looking them up by scanning made a pipeline of n maps take n^2.
    PlanNode* find_node(const std::string& id) {
        auto it = node_at_.find(id);
        return it == node_at_.end() ? nullptr : &plan_.nodes[it->second];
    }
    PlanMap* find_map_by_id(const std::string& id) {
        auto it = map_at_.find(id);
        return it == map_at_.end() ? nullptr : &plan_.maps[it->second];
    }
    void edge(const std::string& from, const std::string& to, const std::string& kind, const std::string& label = "",
              std::optional<double> weight = std::nullopt) {
        plan_.edges.push_back({from, to, kind, label, weight});
    }

    // The node producing `e` (creating operator nodes as needed); "" for literals.
    std::string source(const Expr& e, const std::string& owner, int& counter, const std::set<std::string>& maps) {
        switch (e.kind) {
        case Expr::Kind::kLiteral: return "";
        case Expr::Kind::kReference:
            if (maps.count(e.name)) return "map." + e.name;
            if (e.name == "preview") return "preview";
            if (!node_at_.count("buffer." + e.name)) plan_.buffers.push_back({"buffer." + e.name, e.name});
            node("buffer." + e.name, "buffer", "preselective", e.name);
            edge("preselective", "buffer." + e.name, "buffer");
            return "buffer." + e.name;
        case Expr::Kind::kCall: {
            std::string id = fmt::format("op.{}.{}", owner, counter++);
            call_node(id, e, owner, counter, maps);
            return id;
        }
        }
        return "";
    }

    void call_node(const std::string& id, const Expr& e, const std::string& owner, int& counter, const std::set<std::string>& maps) {
        if (e.name == "component" && e.args.size() == 1 && e.args[0].name.empty()) {  // a buffer, not an operator
            std::string letter = e.args[0].expr.name;
            if (!node_at_.count(id)) plan_.buffers.push_back({id, letter});
            node(id, "buffer", "preselective", fmt::format("component({})", letter));
            edge("preselective", id, "buffer");
            return;
        }
        node(id, "operator", "guidance", expr_text(e));
        // Its typed definition; indexed, since nested calls append to plan_.maps meanwhile.
        PlanMap def;
        def.id = id;
        def.name = expr_text(e);
        def.op = pipeline::guidance_operator_from_name(e.name);  // checked
        PlanMapParams params;
        std::vector<PlanMapInput> inputs;
        for (const auto& a : e.args) {
            if (a.name.empty() && a.expr.kind == Expr::Kind::kLiteral) {  // tagged("exit_sign"), constant(0.5)
                if (a.expr.literal.kind == Value::Kind::kString) params.tag = a.expr.literal.text;
                else params.constant = a.expr.literal.number;
            } else if (a.name.empty()) {
                std::string from = source(a.expr, owner, counter, maps);
                if (!from.empty()) {
                    edge(from, id, kind_of(from));
                    inputs.push_back({from, std::nullopt});
                }
            } else if (maps.count(a.name)) {  // a weighted map (importance)
                edge("map." + a.name, id, "map", value_text(a.value), a.value.number);
                inputs.push_back({"map." + a.name, a.value.number});
            } else {
                const nlohmann::json v = value_json(a.value);
                if (a.name == "fovea") params.fovea = v.get<double>();
                if (a.name == "sigma") params.sigma = v.get<double>();
                if (a.name == "at") params.at = v.get<double>();
                if (a.name == "op") params.combine = v.get<std::string>();
            }
        }
        def.inputs = std::move(inputs);
        def.params = std::move(params);
        add_map(std::move(def));
    }

    std::string kind_of(const std::string& id) {
        const PlanNode* n = find_node(id);
        if (!n) return "map";
        if (n->kind == "image" || n->kind == "buffer") return n->kind;
        if (const PlanMap* m = find_map_by_id(id); m && m->op == pipeline::GuidanceOperator::kTagged) return "objects";
        return "map";
    }

private:
    PipelinePlan& plan_;
    std::unordered_map<std::string, size_t> node_at_, map_at_;  // id -> index in plan_.nodes, plan_.maps
};

}  // namespace

bool lower_stages(const pipeline::ResolvedPipeline& p, PipelinePlan& plan, DiagnosticSink& sink) {
    plan.name = p.name;
    plan.chain = p.chain;
    plan.staged = true;
    plan.settings = typed_settings(p);
    const size_t errors = sink.error_count();
    plan.program.preselective.op = plan.program.selective.op = sched::Op::kSeq;
    if (p.preselective.crex)
        if (auto n = stage_program(*p.preselective.crex, sink)) plan.program.preselective = *n;
    if (p.selective.crex)
        if (auto n = stage_program(*p.selective.crex, sink)) plan.program.selective = *n;
    if (sink.error_count() != errors) return false;
    // The modulation map of the selective crex names its `{ }` groups' map.
    const std::string modulation = p.selective.crex_by ? expr_text(*p.selective.crex_by) : "importance";
    std::function<void(sched::Node&)> name_map = [&](sched::Node& n) {
        if (n.op == sched::Op::kModulate) n.map = modulation;
        for (auto& c : n.children) name_map(c);
    };
    name_map(plan.program.selective);
    return true;
}

void prune_steps_for_scene(const BinSet& spawnable, const std::string& scene, const std::string& census_hash, PipelinePlan& plan) {
    plan.scene = scene;
    plan.census_hash = census_hash;
    for (const auto& d : find_dead_steps(plan.program, spawnable))
        plan.pruned.push_back({fmt::format("step {}", component_letter(d.component)), d.where.to_string(), d.reason});
    plan.program = prune_dead_steps(plan.program, spawnable);
}

namespace {
// `vary ic_radius` and `vary ic_rays` are the irradiance cache's: a pipeline with either renders D through it.
bool varies_the_cache(const pipeline::ResolvedVariable& v) { return v.name == "ic_radius" || v.name == "ic_rays"; }
}  // namespace

std::vector<const pipeline::ResolvedVariable*> prune_variables(const pipeline::ResolvedPipeline& p, PipelinePlan& plan) {
    const bool d_left = has_exec(plan.program.preselective, Component::kD) || has_exec(plan.program.selective, Component::kD);
    // The cache exists while a D step is left; without one there is no cache to vary.
    plan.irradiance_cache = d_left && std::any_of(p.vary.begin(), p.vary.end(), varies_the_cache);
    std::vector<const pipeline::ResolvedVariable*> vary;
    for (const auto& v : p.vary) {
        if (varies_the_cache(v) && !d_left) {
            plan.pruned.push_back({"vary " + v.name, "", "no D step is left for this scene, so there is no irradiance cache"});
            continue;
        }
        if (!v.component.empty()) {  // checked: one of D G S T R M
            const Component c = *component_from_letter(v.component[0]);
            if (!has_exec(plan.program.preselective, c) && !has_exec(plan.program.selective, c)) {
                plan.pruned.push_back({"vary " + v.varied(), "", fmt::format("no {} step is left for this scene", v.component)});
                continue;
            }
        }
        vary.push_back(&v);
    }
    return vary;
}

std::set<std::string> mark_live_maps(const pipeline::ResolvedPipeline& p, const std::vector<const pipeline::ResolvedVariable*>& vary,
                                     PipelinePlan& plan) {
    std::map<std::string, const Expr*> defs;
    for (const auto& [name, e] : p.maps) defs[name] = &e;
    std::set<std::string> live;
    std::function<void(const Expr&)> use = [&](const Expr& e) {
        if (e.kind == Expr::Kind::kReference && defs.count(e.name) && live.insert(e.name).second) use(*defs[e.name]);
        for (const auto& a : e.args) {
            if (a.name.empty()) use(a.expr);
            else if (defs.count(a.name) && live.insert(a.name).second) use(*defs[a.name]);
        }
    };
    for (const auto* v : vary) use(v->by);
    if (p.selective.crex_by) use(*p.selective.crex_by);
    for (const auto& [name, e] : p.maps)
        if (!live.count(name)) plan.pruned.push_back({"map " + name, "", "no selective variable or crex consumes it"});
    return live;
}

void build_plan_graph(const pipeline::ResolvedPipeline& p, const std::vector<const pipeline::ResolvedVariable*>& vary,
                      const std::set<std::string>& maps, PipelinePlan& plan) {
    GraphBuilder g(plan);
    g.node("camera", "camera", "preselective", "camera rays");
    g.node("preselective", "crex", "preselective", "pre-selective crex", {{"crex", sched::to_crex(plan.program.preselective)}});
    g.edge("camera", "preselective", "bin");
    g.node("preview", "image", "preselective", "preview");
    g.edge("preselective", "preview", "image");
    for (const auto& [name, e] : p.maps) {
        if (!maps.count(name)) continue;
        int counter = 0;
        std::string id = "map." + name;
        if (e.kind == Expr::Kind::kCall) g.call_node(id, e, name, counter, maps);
        else {
            g.node(id, "operator", "guidance", expr_text(e));
            std::string from = g.source(e, name, counter, maps);
            if (!from.empty()) g.edge(from, id, g.kind_of(from));
            PlanMap alias;
            alias.id = id;
            if (!from.empty()) alias.inputs.push_back({from, std::nullopt});
            g.add_map(std::move(alias));
        }
        if (PlanNode* n = g.find_node(id)) n->label = name + " = " + expr_text(e);
        if (PlanMap* m = g.find_map_by_id(id)) {
            m->defines = name;
            m->name = name + " = " + expr_text(e);
        }
    }
    nlohmann::json selective_params = {{"crex", sched::to_crex(plan.program.selective)}};
    g.node("selective", "crex", "selective", "selective crex", selective_params);
    g.edge("preselective", "selective", "bin", "bins carried over");
    if (p.selective.crex_by) {
        int counter = 0;
        std::string from = g.source(*p.selective.crex_by, "modulation", counter, maps);
        if (!from.empty()) g.edge(from, "selective", "map", "{ } modulation");
        plan.modulation_map = from;
    }
    for (const auto* v : vary) {
        std::string id = "vary." + v->name + (v->component.empty() ? "" : "." + v->component);
        PlanVariable typed;
        typed.variable = *pipeline::selective_variable_from_name(v->name);  // checked
        if (!v->component.empty()) typed.component = component_from_letter(v->component[0]);
        typed.refine = v->refine;
        typed.from = v->lo.number;
        typed.to = v->hi.number;
        if (!v->using_fn.empty()) typed.modulation = *pipeline::modulation_function_from_name(v->using_fn);
        g.node(id, "svt", "selective", fmt::format("vary {} {} .. {}{}{}", v->varied(), value_text(v->lo), value_text(v->hi),
                                                   v->using_fn.empty() ? "" : " using " + v->using_fn,
                                                   v->refine ? fmt::format(" refine {:g}", *v->refine) : ""));
        int counter = 0;
        std::string from = g.source(v->by, id, counter, maps);
        if (!from.empty()) g.edge(from, id, "map");
        g.edge(id, "selective", "svt");
        typed.map = from;
        plan.variables.push_back(typed);
    }
    if (plan.irradiance_cache) {
        g.node("irradiance_cache", "cache", "selective", "irradiance cache");
        g.edge("preselective", "irradiance_cache", "cache", "records");
        g.edge("irradiance_cache", "selective", "cache", "records");
    } else if (std::any_of(p.vary.begin(), p.vary.end(), varies_the_cache)) {
        plan.pruned.push_back({"irradiance cache", "", "no D step is left for this scene"});
    }
    g.node("composite", "composite", "output", "composite");
    g.edge("selective", "composite", "image");
    for (const auto& [key, values] : p.output) {
        const auto& v = values.front();
        if (key == "components" || key == "maps") {
            (key == "maps" ? plan.outputs.maps : plan.outputs.components) = v.boolean;
            continue;
        }
        if (key == "report") plan.outputs.report = v.text;
        if (key != "image") {
            g.node("output." + key, "output", "output", fmt::format("{} {}", key, value_text(v)));
            g.edge("composite", "output." + key, "image");
            continue;
        }
        // One node per image; the first keeps the id "output.image" that plans had before.
        for (size_t i = 0; i < values.size(); ++i) {
            plan.outputs.images.push_back(values[i].text);
            const std::string id = i == 0 ? "output.image" : fmt::format("output.image{}", i + 1);
            g.node(id, "output", "output", fmt::format("image {}", value_text(values[i])));
            g.edge("composite", id, "image");
        }
    }
}

std::optional<PipelinePlan> plan_pipeline(const pipeline::ResolvedPipeline& p, const std::optional<BinSet>& spawnable,
                                          const std::string& scene, const std::string& census_hash, DiagnosticSink& sink) {
    PipelinePlan plan;
    if (!lower_stages(p, plan, sink)) return std::nullopt;
    if (spawnable) prune_steps_for_scene(*spawnable, scene, census_hash, plan);
    else plan.scene = scene, plan.census_hash = census_hash;
    const std::vector<const pipeline::ResolvedVariable*> vary = prune_variables(p, plan);
    const std::set<std::string> maps = mark_live_maps(p, vary, plan);
    build_plan_graph(p, vary, maps, plan);
    return plan;
}

nlohmann::json plan_settings_to_json(const PlanSettings& s) {
    nlohmann::json j = nlohmann::json::object();
    if (s.width && s.height) j["image"] = {{"width", *s.width}, {"height", *s.height}};
    j["spp"] = s.spp;
    if (s.shadow_rays) j["shadow_rays"] = *s.shadow_rays;
    if (s.selective_spp) j["selective_spp"] = *s.selective_spp;
    if (s.rounds) j["rounds"] = *s.rounds;
    if (s.seed) j["seed"] = *s.seed;
    if (s.lw) j["lw"] = *s.lw;
    if (s.av) j["av"] = *s.av;
    if (s.aa) j["aa"] = *s.aa;
    if (s.max_depth) j["max_depth"] = *s.max_depth;
    if (s.ab) j["ab"] = *s.ab;
    if (s.ad) j["ad"] = *s.ad;
    if (s.budget) j["budget"] = {{s.budget->percent ? "percent" : "seconds", s.budget->amount}};
    if (s.policy) j["policy"] = pipeline::name_of(*s.policy);
    if (!s.reference.empty()) j["reference"] = s.reference;
    return j;
}

nlohmann::json plan_outputs_to_json(const PlanOutputs& o) {
    nlohmann::json j = {{"images", o.images}, {"components", o.components}, {"maps", o.maps}};
    if (!o.report.empty()) j["report"] = o.report;
    return j;
}

nlohmann::json plan_map_to_json(const PlanMap& m) {
    nlohmann::json j = {{"id", m.id}, {"name", m.name}, {"inputs", nlohmann::json::array()}, {"params", nlohmann::json::object()}};
    j["operator"] = m.op ? nlohmann::json(pipeline::name_of(*m.op)) : nlohmann::json(nullptr);
    if (!m.defines.empty()) j["defines"] = m.defines;
    for (const auto& in : m.inputs) {
        nlohmann::json ji = {{"node", in.node}};
        if (in.weight) ji["weight"] = *in.weight;
        j["inputs"].push_back(ji);
    }
    nlohmann::json& p = j["params"];
    if (m.params.constant) p["constant"] = *m.params.constant;
    if (m.params.tag) p["tag"] = *m.params.tag;
    if (m.params.fovea) p["fovea"] = *m.params.fovea;
    if (m.params.sigma) p["sigma"] = *m.params.sigma;
    if (m.params.at) p["at"] = *m.params.at;
    if (m.params.combine) p["combine"] = *m.params.combine;
    return j;
}

nlohmann::json pipeline_plan_to_json(const PipelinePlan& plan) {
    nlohmann::json j;
    j["format"] = "crex-plan";
    j["version"] = kPlanFormatVersion;
    j["pipeline"] = {{"name", plan.name}, {"extends", plan.chain}};
    j["scene"] = plan.scene.empty() ? nlohmann::json(nullptr) : nlohmann::json{{"spec", plan.scene}, {"census_hash", plan.census_hash}};
    j["settings"] = plan_settings_to_json(plan.settings);
    j["outputs"] = plan_outputs_to_json(plan.outputs);
    j["variables"] = nlohmann::json::array();
    for (const auto& v : plan.variables) {
        nlohmann::json var = {{"variable", pipeline::name_of(v.variable)}, {"from", v.from}, {"to", v.to},
                              {"modulation", pipeline::name_of(v.modulation)}, {"map", v.map}};
        if (v.component) var["component"] = std::string(1, component_letter(*v.component));
        if (v.refine) var["refine"] = *v.refine;
        j["variables"].push_back(std::move(var));
    }
    j["maps"] = nlohmann::json::array();
    for (const auto& m : plan.maps) j["maps"].push_back(plan_map_to_json(m));
    j["buffers"] = nlohmann::json::array();
    for (const auto& b : plan.buffers) j["buffers"].push_back({{"id", b.id}, {"buffer", b.buffer}});
    j["irradiance_cache"] = plan.irradiance_cache;
    j["modulation_map"] = plan.modulation_map.empty() ? nlohmann::json(nullptr) : nlohmann::json(plan.modulation_map);
    j["stages"] = {{"preselective", schedule_to_json(plan.program.preselective)}, {"selective", schedule_to_json(plan.program.selective)}};
    j["nodes"] = nlohmann::json::array();
    for (const auto& n : plan.nodes)
        j["nodes"].push_back({{"id", n.id}, {"kind", n.kind}, {"stage", n.stage}, {"label", n.label}, {"params", n.params}});
    j["edges"] = nlohmann::json::array();
    for (const auto& e : plan.edges) {
        nlohmann::json je = {{"from", e.from}, {"to", e.to}, {"kind", e.kind}};
        if (!e.label.empty()) je["label"] = e.label;
        if (e.weight) je["weight"] = *e.weight;
        j["edges"].push_back(je);
    }
    j["pruned"] = nlohmann::json::array();
    for (const auto& r : plan.pruned) {
        nlohmann::json jr = {{"what", r.what}, {"reason", r.reason}};
        if (!r.at.empty()) jr["at"] = r.at;
        j["pruned"].push_back(jr);
    }
    return j;
}

std::string pipeline_plan_to_dot(const PipelinePlan& plan) {
    std::string out = "digraph crex_pipeline {\n  rankdir=LR; compound=true;\n  node [shape=box, fontname=\"Helvetica\"];\n";
    out += fmt::format("  label=\"{}\"; labelloc=t;\n",
                       escape_dot("pipeline " + plan.name + (plan.scene.empty() ? "" : " on " + plan.scene)));
    const std::map<std::string, std::string> shape = {{"camera", "ellipse"}, {"image", "note"}, {"buffer", "note"},
                                                      {"operator", "box"},   {"svt", "hexagon"}, {"cache", "cylinder"},
                                                      {"composite", "invtrapezium"}, {"output", "folder"}, {"crex", "box3d"}};
    const std::map<std::string, std::string> color = {{"bin", "#1a73e8"}, {"image", "#188038"}, {"buffer", "#188038"},
                                                      {"map", "#e37400"}, {"svt", "#9334e6"},  {"cache", "#c5221f"}};
    for (const char* stage : {"preselective", "guidance", "selective", "output"}) {
        out += fmt::format("  subgraph cluster_{} {{\n    label=\"{}\"; style=\"filled\"; fillcolor=\"#f8f9fa\";\n", stage, stage);
        for (const auto& n : plan.nodes) {
            if (n.stage != stage) continue;
            std::string label = n.label;
            if (n.kind == "crex") label += "\\n" + n.params.value("crex", std::string());
            out += fmt::format("    \"{}\" [label=\"{}\", shape={}];\n", n.id, escape_dot(label), shape.count(n.kind) ? shape.at(n.kind) : "box");
        }
        out += "  }\n";
    }
    for (const auto& e : plan.edges)
        out += fmt::format("  \"{}\" -> \"{}\" [label=\"{}\", color=\"{}\", fontcolor=\"{}\"];\n", e.from, e.to,
                           escape_dot(e.label.empty() ? e.kind : e.kind + ": " + e.label), color.count(e.kind) ? color.at(e.kind) : "black",
                           color.count(e.kind) ? color.at(e.kind) : "black");
    // The cyclic process: after each round but the last, guidance runs again on the image so far.
    if (plan.settings.rounds && *plan.settings.rounds > 1 && !plan.maps.empty())
        out += fmt::format("  \"selective\" -> \"{}\" [label=\"rounds: {} (maps again on the image so far)\", style=\"bold\", "
                           "color=\"#c5221f\", fontcolor=\"#c5221f\", constraint=false];\n",
                           plan.maps.front().id, *plan.settings.rounds);
    if (!plan.pruned.empty()) {
        out += "  subgraph cluster_pruned {\n    label=\"pruned for this scene\"; style=\"dashed\";\n";
        for (size_t i = 0; i < plan.pruned.size(); ++i)
            out += fmt::format("    pruned{} [label=\"{}\", tooltip=\"{}\", style=\"dashed\", color=\"gray50\", fontcolor=\"gray50\"];\n", i,
                               escape_dot(plan.pruned[i].what + (plan.pruned[i].at.empty() ? "" : "\\n" + plan.pruned[i].at)),
                               escape_dot(plan.pruned[i].reason));
        out += "  }\n";
    }
    out += "}\n";
    return out;
}

std::string pipeline_plan_to_text(const PipelinePlan& plan) {
    std::string chain;
    for (size_t i = 1; i < plan.chain.size(); ++i) chain += " extends " + plan.chain[i];
    std::string out = fmt::format("plan of pipeline {}{}{}\n", plan.name, chain, plan.scene.empty() ? "" : " for " + plan.scene);
    std::string pre = sched::to_crex(plan.program.preselective), sel = sched::to_crex(plan.program.selective);
    out += fmt::format("  pre-selective: {}\n", pre.empty() ? "camera rays only" : pre);
    out += fmt::format("  selective:     {}\n", sel.empty() ? "no crex steps" : sel);
    if (plan.settings.rounds && *plan.settings.rounds > 1)
        out += fmt::format("  rounds:        {} (guidance and selective rendering repeated on the image so far)\n", *plan.settings.rounds);
    for (const auto& n : plan.nodes)
        if (n.kind == "operator" && n.id.rfind("map.", 0) == 0) out += fmt::format("  map     {}\n", n.label);
    for (const auto& n : plan.nodes)
        if (n.kind == "svt") out += fmt::format("  {}\n", n.label);
    if (!plan.census_hash.empty()) out += fmt::format("  census hash:   {}\n", plan.census_hash);
    for (const auto& r : plan.pruned) out += fmt::format("  pruned {}{}: {}\n", r.what, r.at.empty() ? "" : " at " + r.at, r.reason);
    return out;
}

}  // namespace crex
