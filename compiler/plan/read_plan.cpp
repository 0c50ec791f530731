#include "compiler/plan/read_plan.h"

#include <fmt/format.h>

#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <set>

#include "base/json_positions.h"
#include "base/number_range.h"
#include "compiler/pipeline/registry.h"
#include "compiler/pipeline/settings_table.h"

namespace crex {
namespace {

using nlohmann::json;
using sched::Node;
using sched::Op;

// "file:line:col" back to a location (the file name may itself contain colons).
SourceLocation parse_location(const std::string& text) {
    SourceLocation loc;
    size_t c2 = text.rfind(':');
    size_t c1 = c2 == std::string::npos || c2 == 0 ? std::string::npos : text.rfind(':', c2 - 1);
    if (c1 == std::string::npos) return loc;
    try {
        loc.line = static_cast<uint32_t>(std::stoul(text.substr(c1 + 1, c2 - c1 - 1)));
        loc.col = static_cast<uint32_t>(std::stoul(text.substr(c2 + 1)));
        loc.file = text.substr(0, c1);
        loc.end_line = loc.line;
        loc.end_col = loc.col + 1;
    } catch (...) {
        return SourceLocation{};
    }
    return loc;
}

class PlanReader {
public:
    PlanReader(const PositionedJson& doc, DiagnosticSink& sink) : doc_(doc), sink_(sink) {}

    bool fail(const std::string& pointer, const std::string& message) {
        sink_.report("E401", doc_.span(pointer), fmt::format("{}: {}", readable_json_path(pointer), message));
        return false;
    }

    bool node(const json& j, const std::string& ptr, Node& out) {
        if (!j.is_object()) return fail(ptr, "expected a step object");
        if (j.contains("op") && !j["op"].is_string()) return fail(ptr + "/op", "expected a step name (a string)");
        std::string op = j.value("op", "");
        static const std::pair<const char*, Op> kOps[] = {{"exec", Op::kExec},         {"seq", Op::kSeq},
                                                          {"defer", Op::kDefer},       {"modulate", Op::kModulate},
                                                          {"budgeted", Op::kBudgeted}, {"repeat", Op::kRepeat},
                                                          {"repeat_until_empty", Op::kRepeatUntilEmpty}};
        bool known = false;
        for (const auto& [name, value] : kOps)
            if (op == name) out.op = value, known = true;
        if (!known) return fail(ptr + "/op", fmt::format("unknown step '{}'", op));
        auto number = [&](const char* key, double lo, double hi, double& v, bool whole = false) {
            if (!j.contains(key) || !j[key].is_number()) return fail(ptr + "/" + key, "expected a number");
            v = j[key].get<double>();
            if (std::string e = number_range_error(v, {lo, hi, whole}); !e.empty()) return fail(ptr + "/" + key, e);
            return true;
        };
        if (j.contains("at") && !j["at"].is_string()) return fail(ptr + "/at", "expected \"file:line:col\"");
        if (j.contains("at")) out.where = parse_location(j["at"].get<std::string>());
        double v = 0;
        switch (out.op) {
        case Op::kExec: {
            if (!j.contains("component") || !j["component"].is_string())
                return fail(ptr + "/component", "expected a component letter: \"D\", \"G\", \"S\", \"T\", \"R\" or \"M\"");
            std::string c = j["component"].get<std::string>();
            auto comp = c.size() == 1 ? component_from_letter(c[0]) : std::nullopt;
            if (!comp) return fail(ptr + "/component", fmt::format("unknown component '{}'", c));
            out.component = *comp;
            if (j.contains("occurrence")) {
                if (!number("occurrence", 0, 1e300, v)) return false;
                out.first_index = v;
            }
            break;
        }
        case Op::kRepeat:
            if (!number("count", 1, 2147483647, v, true)) return false;
            out.count = static_cast<uint64_t>(v);
            if (j.contains("stride")) {
                if (!number("stride", 0, 1e300, v)) return false;
                out.stride = v;
            }
            break;
        case Op::kRepeatUntilEmpty:
            if (!number("cap", 1, 4294967295.0, v, true)) return false;
            out.cap = static_cast<uint32_t>(v);
            break;
        case Op::kModulate:
            if (!number("occurrences", 0, 1e300, v)) return false;
            out.occurrences = v;
            if (j.contains("map") && !j["map"].is_string()) return fail(ptr + "/map", "expected a map name (a string)");
            out.map = j.value("map", "importance");
            break;
        case Op::kBudgeted:
            if (j.contains("owns_deferral") && !j["owns_deferral"].is_boolean()) return fail(ptr + "/owns_deferral", "expected true or false");
            out.owns_deferral = j.value("owns_deferral", true);
            break;
        case Op::kDefer: out.owns_deferral = true; break;
        case Op::kSeq: break;
        }
        if (j.contains("children")) {
            if (!j["children"].is_array()) return fail(ptr + "/children", "expected an array of steps");
            for (size_t i = 0; i < j["children"].size(); ++i) {
                Node child;
                if (!node(j["children"][i], ptr + "/children/" + std::to_string(i), child)) return false;
                out.children.push_back(std::move(child));
            }
        }
        bool needs_one = out.op == Op::kRepeat || out.op == Op::kRepeatUntilEmpty;
        if (needs_one && out.children.size() != 1) return fail(ptr, "a repeat needs exactly one child");
        if (out.op == Op::kExec && !out.children.empty()) return fail(ptr, "an exec step has no children");
        return true;
    }

    std::optional<CrexPlan> read() {
        const json& j = doc_.value;
        if (!j.is_object() || !j.contains("format") || j["format"] != "crex-plan") {
            fail("", "not a crex plan (\"format\": \"crex-plan\" missing)");
            return std::nullopt;
        }
        if (!j.contains("version") || !j["version"].is_number_integer() || j["version"].get<int64_t>() != kPlanFormatVersion) {
            fail("/version", fmt::format("expected the integer {}: this crex reads plan version {} (run 'crex plan' again to "
                                         "write one)", kPlanFormatVersion, kPlanFormatVersion));
            return std::nullopt;
        }
        CrexPlan plan;
        if (j.contains("crex")) {
            if (!j["crex"].is_object()) return none("/crex", "expected an object {\"source\": ..., \"canonical\": ...}");
            if (!text(j["crex"], "/crex", "source", plan.source, false)) return std::nullopt;
        }
        if (j.contains("scene") && !j["scene"].is_null()) {
            if (!j["scene"].is_object()) return none("/scene", "expected null or {\"spec\": ..., \"census_hash\": ...}");
            if (!text(j["scene"], "/scene", "spec", plan.scene, false) || !text(j["scene"], "/scene", "census_hash", plan.census_hash, false))
                return std::nullopt;
        }
        if (!j.contains("stages") || !j["stages"].is_object()) return none("/stages", "missing the stages");
        for (const char* stage : {"preselective", "selective"}) {
            std::string ptr = std::string("/stages/") + stage;
            if (!j["stages"].contains(stage)) return none(ptr, "missing");
            Node& out = std::string(stage) == "preselective" ? plan.program.preselective : plan.program.selective;
            if (!node(j["stages"][stage], ptr, out)) return std::nullopt;
            if (out.op != Op::kSeq) return none(ptr + "/op", "a stage is a 'seq'");
        }
        if (j.contains("pipeline") && !read_pipeline(j, plan)) return std::nullopt;
        return plan;
    }

    std::optional<CrexPlan> none(const std::string& pointer, const std::string& message) {
        fail(pointer, message);
        return std::nullopt;
    }

    bool text(const json& o, const std::string& ptr, const char* key, std::string& out, bool required) {
        if (!o.contains(key)) return !required || fail(ptr, std::string("missing \"") + key + "\"");
        if (!o[key].is_string()) return fail(ptr + "/" + key, "expected a string");
        out = o[key].get<std::string>();
        return true;
    }

    bool boolean(const json& o, const std::string& ptr, const char* key, bool& out) {
        if (!o.contains(key)) return true;
        if (!o[key].is_boolean()) return fail(ptr + "/" + key, "expected true or false");
        out = o[key].get<bool>();
        return true;
    }

    bool number(const json& o, const std::string& ptr, const char* key, double& out) {
        if (!o.contains(key)) return fail(ptr, std::string("missing \"") + key + "\"");
        if (!o[key].is_number()) return fail(ptr + "/" + key, "expected a number");
        out = o[key].get<double>();
        return true;
    }

    // A setting's number, in the range of compiler/pipeline/settings_table.cpp.
    bool ranged(const json& o, const std::string& ptr, const char* key, std::string_view section, std::string_view name, double& out) {
        if (!number(o, ptr, key, out)) return false;
        const pipeline::SettingRule* rule = pipeline::find_setting_rule(section, name);
        if (auto e = rule ? pipeline::setting_range_error(*rule, out) : ""; !e.empty()) return fail(ptr + "/" + key, e);
        return true;
    }

    bool read_settings(const json& s, PlanSettings& out) {
        const std::string ptr = "/settings";
        if (!s.is_object()) return fail(ptr, "expected an object of settings");
        static const std::set<std::string> known = {"image", "spp", "shadow_rays", "selective_spp", "rounds", "seed", "lw", "av", "aa",
                                                    "max_depth", "ab", "ad", "budget", "policy", "reference"};
        for (const auto& [key, _] : s.items())
            if (!known.count(key)) return fail(ptr + "/" + escape_pointer_token(key), fmt::format("unknown setting '{}'", key));
        double v = 0;
        if (s.contains("image")) {
            const json& im = s["image"];
            double w = 0, h = 0;
            if (!im.is_object()) return fail(ptr + "/image", "expected {\"width\": W, \"height\": H}");
            if (!ranged(im, ptr + "/image", "width", "", "image", w) || !ranged(im, ptr + "/image", "height", "", "image", h)) return false;
            out.width = static_cast<int>(w);
            out.height = static_cast<int>(h);
        }
        if (s.contains("spp")) {
            if (!ranged(s, ptr, "spp", "preselective", "spp", v)) return false;
            out.spp = static_cast<uint32_t>(v);
        }
        if (s.contains("shadow_rays")) {
            if (!ranged(s, ptr, "shadow_rays", "preselective", "shadow_rays", v)) return false;
            out.shadow_rays = static_cast<uint32_t>(v);
        }
        if (s.contains("selective_spp")) {
            if (!ranged(s, ptr, "selective_spp", "selective", "spp", v)) return false;
            out.selective_spp = static_cast<uint32_t>(v);
        }
        if (s.contains("rounds")) {
            if (!ranged(s, ptr, "rounds", "selective", "rounds", v)) return false;
            out.rounds = static_cast<uint32_t>(v);
        }
        if (s.contains("seed")) {
            if (!ranged(s, ptr, "seed", "", "seed", v)) return false;
            out.seed = static_cast<uint64_t>(v);
        }
        for (auto [key, field] : {std::pair{"lw", &out.lw}, std::pair{"av", &out.av}, std::pair{"aa", &out.aa}})
            if (s.contains(key)) {
                if (!ranged(s, ptr, key, "", key, v)) return false;
                *field = v;
            }
        for (auto [key, field] : {std::pair{"max_depth", &out.max_depth}, std::pair{"ab", &out.ab}, std::pair{"ad", &out.ad}})
            if (s.contains(key)) {
                if (!ranged(s, ptr, key, "", key, v)) return false;
                *field = static_cast<uint32_t>(v);
            }
        if (s.contains("budget")) {
            const json& b = s["budget"];
            if (!b.is_object() || b.size() != 1 || !(b.contains("seconds") || b.contains("percent")))
                return fail(ptr + "/budget", "expected {\"seconds\": N} or {\"percent\": N}");
            bool percent = b.contains("percent");
            const char* key = percent ? "percent" : "seconds";
            if (!number(b, ptr + "/budget", key, v)) return false;
            if (auto e = pipeline::budget_range_error(v, percent); !e.empty()) return fail(ptr + "/budget/" + key, "expected " + e);
            out.budget = PlanBudget{v, percent, {}};
        }
        if (s.contains("policy")) {
            std::string name;
            if (!text(s, ptr, "policy", name, true)) return false;
            out.policy = pipeline::scheduling_policy_from_name(name);
            if (!out.policy) return fail(ptr + "/policy", fmt::format("unknown scheduling policy '{}': expected \"tasks\", \"queues\", \"batches\" or \"progressive\"", name));
        }
        return text(s, ptr, "reference", out.reference, false);
    }

    bool read_outputs(const json& o, PlanOutputs& out) {
        const std::string ptr = "/outputs";
        if (!o.is_object()) return fail(ptr, "expected {\"images\": [...], \"components\": ..., \"maps\": ...}");
        if (o.contains("images")) {
            if (!o["images"].is_array()) return fail(ptr + "/images", "expected an array of paths");
            for (size_t i = 0; i < o["images"].size(); ++i) {
                if (!o["images"][i].is_string()) return fail(ptr + "/images/" + std::to_string(i), "expected a path (a string)");
                out.images.push_back(o["images"][i].get<std::string>());
            }
        }
        return boolean(o, ptr, "components", out.components) && boolean(o, ptr, "maps", out.maps) && text(o, ptr, "report", out.report, false);
    }

    // A graph node's parameters: only a stage's crex, for the picture; the typed data is elsewhere.
    bool node_params(const json& params, const std::string& ptr) {
        for (const auto& [key, value] : params.items()) {
            if (key != "crex") return fail(ptr + "/" + escape_pointer_token(key), fmt::format("unknown node parameter '{}'", key));
            if (!value.is_string()) return fail(ptr + "/crex", "expected the stage's crex (a string)");
        }
        return true;
    }

    // The typed map definitions and buffers guidance evaluates; every id names a graph node,
    // every input a buffer, a map or the preview, and no map depends on itself.
    bool read_guidance(const json& j, const std::map<std::string, size_t>& index, PipelinePlan& p) {
        for (const char* list : {"maps", "buffers"})
            if (!j.contains(list) || !j[list].is_array()) return fail(std::string("/") + list, "expected an array");
        static const std::set<std::string> buffers = {"direct", "emission", "ambient", "D", "G", "S", "T", "R", "M"};
        std::set<std::string> ids = {"preview"};
        for (size_t i = 0; i < j["buffers"].size(); ++i) {
            const json& b = j["buffers"][i];
            std::string ptr = "/buffers/" + std::to_string(i);
            PlanBuffer buffer;
            if (!b.is_object()) return fail(ptr, "expected {\"id\", \"buffer\"}");
            if (!text(b, ptr, "id", buffer.id, true) || !text(b, ptr, "buffer", buffer.buffer, true)) return false;
            if (!index.count(buffer.id)) return fail(ptr + "/id", fmt::format("no node '{}' in the plan", buffer.id));
            if (!buffers.count(buffer.buffer))
                return fail(ptr + "/buffer", fmt::format("unknown buffer '{}': expected direct, emission, ambient or a component letter", buffer.buffer));
            if (!ids.insert(buffer.id).second) return fail(ptr + "/id", fmt::format("'{}' is defined twice", buffer.id));
            p.buffers.push_back(std::move(buffer));
        }
        for (const auto& m : j["maps"])
            if (m.is_object() && m.contains("id") && m["id"].is_string()) ids.insert(m["id"].get<std::string>());
        std::map<std::string, std::vector<std::pair<std::string, std::string>>> uses;  // map -> (input, pointer)
        std::set<std::string> map_ids;
        for (size_t i = 0; i < j["maps"].size(); ++i) {
            const json& m = j["maps"][i];
            std::string ptr = "/maps/" + std::to_string(i);
            PlanMap def;
            if (!m.is_object()) return fail(ptr, "expected {\"id\", \"name\", \"operator\", \"inputs\", \"params\"}");
            if (!text(m, ptr, "id", def.id, true) || !text(m, ptr, "name", def.name, false) || !text(m, ptr, "defines", def.defines, false))
                return false;
            if (!index.count(def.id)) return fail(ptr + "/id", fmt::format("no node '{}' in the plan", def.id));
            if (!map_ids.insert(def.id).second) return fail(ptr + "/id", fmt::format("map '{}' is defined twice", def.id));
            if (m.contains("operator") && !m["operator"].is_null()) {
                if (!m["operator"].is_string()) return fail(ptr + "/operator", "expected a guidance operator's name or null");
                def.op = pipeline::guidance_operator_from_name(m["operator"].get<std::string>());
                if (!def.op) return fail(ptr + "/operator", fmt::format("unknown guidance operator '{}'", m["operator"].get<std::string>()));
            }
            if (!m.contains("inputs") || !m["inputs"].is_array()) return fail(ptr + "/inputs", "expected an array");
            for (size_t k = 0; k < m["inputs"].size(); ++k) {
                const json& in = m["inputs"][k];
                std::string iptr = ptr + "/inputs/" + std::to_string(k);
                PlanMapInput input;
                if (!in.is_object()) return fail(iptr, "expected {\"node\": ...}");
                if (!text(in, iptr, "node", input.node, true)) return false;
                if (!ids.count(input.node)) return fail(iptr + "/node", fmt::format("'{}' is not a map, a buffer or the preview", input.node));
                if (in.contains("weight")) {
                    double w = 0;
                    if (!number(in, iptr, "weight", w)) return false;
                    if (!(std::isfinite(w) && w >= 0)) return fail(iptr + "/weight", "expected a weight >= 0");
                    input.weight = w;
                }
                uses[def.id].push_back({input.node, iptr + "/node"});
                def.inputs.push_back(std::move(input));
            }
            if (!def.op && def.inputs.size() != 1) return fail(ptr + "/inputs", "an alias (no operator) has exactly one input");
            if (m.contains("params") && !map_params(m["params"], ptr + "/params", def.params)) return false;
            p.maps.push_back(std::move(def));
        }
        std::map<std::string, int> state;  // 1 on the path, 2 done
        std::function<bool(const std::string&)> visit = [&](const std::string& id) {
            state[id] = 1;
            for (const auto& [to, ptr] : uses[id]) {
                if (state[to] == 1) return fail(ptr, fmt::format("map '{}' depends on itself through '{}'", to, id));
                if (state[to] == 0 && !visit(to)) return false;
            }
            state[id] = 2;
            return true;
        };
        for (const auto& m : p.maps)
            if (state[m.id] == 0 && !visit(m.id)) return false;
        return true;
    }

    bool map_params(const json& params, const std::string& ptr, PlanMapParams& out) {
        if (!params.is_object()) return fail(ptr, "expected an object");
        static const std::set<std::string> known = {"constant", "tag", "fovea", "sigma", "at", "combine"};
        for (const auto& [key, _] : params.items())
            if (!known.count(key)) return fail(ptr + "/" + escape_pointer_token(key), fmt::format("unknown parameter '{}'", key));
        double v = 0;
        for (auto [key, field] : {std::pair{"constant", &out.constant}, std::pair{"fovea", &out.fovea}, std::pair{"sigma", &out.sigma},
                                  std::pair{"at", &out.at}})
            if (params.contains(key)) {
                if (!number(params, ptr, key, v)) return false;
                if (!std::isfinite(v)) return fail(ptr + "/" + key, "expected a finite number");
                *field = v;
            }
        if (out.fovea && !(*out.fovea > 0 && *out.fovea < std::numbers::pi)) return fail(ptr + "/fovea", "expected an angle in radians in (0, pi)");
        std::string t;
        if (params.contains("tag")) {
            if (!text(params, ptr, "tag", t, true)) return false;
            out.tag = t;
        }
        if (params.contains("combine")) {
            if (!text(params, ptr, "combine", t, true)) return false;
            if (t != "+" && t != "max" && t != "*") return fail(ptr + "/combine", fmt::format("expected \"+\", \"max\" or \"*\", not \"{}\"", t));
            out.combine = t;
        }
        return true;
    }

    // A pipeline plan: settings, outputs, variables and the graph, every reference resolved.
    bool read_pipeline(const json& j, CrexPlan& plan) {
        PipelinePlan p;
        const json& pj = j["pipeline"];
        if (!pj.is_object() || !pj.contains("name") || !pj["name"].is_string()) return fail("/pipeline", "expected {\"name\": ...}");
        p.name = pj["name"].get<std::string>();
        if (pj.contains("extends")) {
            if (!pj["extends"].is_array()) return fail("/pipeline/extends", "expected an array of pipeline names");
            for (size_t i = 0; i < pj["extends"].size(); ++i) {
                if (!pj["extends"][i].is_string()) return fail("/pipeline/extends/" + std::to_string(i), "expected a pipeline name");
                p.chain.push_back(pj["extends"][i].get<std::string>());
            }
        }
        p.scene = plan.scene;
        p.census_hash = plan.census_hash;
        p.program = plan.program;
        if (j.contains("settings") && !read_settings(j["settings"], p.settings)) return false;
        if (j.contains("outputs") && !read_outputs(j["outputs"], p.outputs)) return false;
        for (const char* list : {"nodes", "edges", "variables"})
            if (!j.contains(list) || !j[list].is_array()) return fail(std::string("/") + list, "expected an array");
        static const std::set<std::string> kinds = {"camera", "crex", "image", "buffer", "operator", "svt", "cache", "composite", "output"};
        static const std::set<std::string> stages = {"preselective", "guidance", "selective", "output"};
        std::map<std::string, size_t> index;
        for (size_t i = 0; i < j["nodes"].size(); ++i) {
            const json& n = j["nodes"][i];
            std::string ptr = "/nodes/" + std::to_string(i);
            PlanNode node;
            if (!n.is_object()) return fail(ptr, "expected an object");
            if (!text(n, ptr, "id", node.id, true) || !text(n, ptr, "kind", node.kind, true) || !text(n, ptr, "stage", node.stage, false) ||
                !text(n, ptr, "label", node.label, false))
                return false;
            if (!kinds.count(node.kind)) return fail(ptr + "/kind", fmt::format("unknown node kind '{}'", node.kind));
            if (!node.stage.empty() && !stages.count(node.stage)) return fail(ptr + "/stage", fmt::format("unknown stage '{}'", node.stage));
            if (!index.emplace(node.id, i).second) return fail(ptr + "/id", fmt::format("node '{}' is defined twice", node.id));
            if (n.contains("params")) {
                if (!n["params"].is_object()) return fail(ptr + "/params", "expected an object");
                if (!node_params(n["params"], ptr + "/params")) return false;
                node.params = n["params"];
            }
            p.nodes.push_back(std::move(node));
        }
        // The nodes every pipeline has: without them a stage would silently not run.
        for (const char* id : {"camera", "preselective", "preview", "selective", "composite"})
            if (!index.count(id)) return fail("/nodes", fmt::format("the plan has no '{}' node (every pipeline plan has camera, "
                                                                    "preselective, preview, selective and composite)", id));
        static const std::set<std::string> edge_kinds = {"bin", "image", "buffer", "map", "objects", "svt", "cache", "profile"};
        std::map<std::string, std::vector<std::pair<std::string, size_t>>> out_edges;
        for (size_t i = 0; i < j["edges"].size(); ++i) {
            const json& e = j["edges"][i];
            std::string ptr = "/edges/" + std::to_string(i);
            PlanEdge edge;
            if (!e.is_object()) return fail(ptr, "expected an object");
            if (!text(e, ptr, "from", edge.from, true) || !text(e, ptr, "to", edge.to, true) || !text(e, ptr, "kind", edge.kind, true) ||
                !text(e, ptr, "label", edge.label, false))
                return false;
            for (const auto& [key, id] : {std::pair{"from", edge.from}, std::pair{"to", edge.to}})
                if (!index.count(id)) return fail(ptr + "/" + key, fmt::format("no node '{}' in the plan", id));
            if (!edge_kinds.count(edge.kind)) return fail(ptr + "/kind", fmt::format("unknown edge kind '{}'", edge.kind));
            if (e.contains("weight")) {
                double w = 0;
                if (!number(e, ptr, "weight", w)) return false;
                if (!(std::isfinite(w) && w >= 0)) return fail(ptr + "/weight", "expected a weight >= 0");
                edge.weight = w;
            }
            out_edges[edge.from].push_back({edge.to, i});
            p.edges.push_back(std::move(edge));
        }
        // Acyclic: a map may not (through others) depend on itself.
        std::map<std::string, int> state;  // 1 on the path, 2 done
        std::function<bool(const std::string&)> visit = [&](const std::string& id) {
            state[id] = 1;
            for (const auto& [to, i] : out_edges[id]) {
                if (state[to] == 1)
                    return fail("/edges/" + std::to_string(i), fmt::format("this edge closes a cycle through '{}'", to));
                if (state[to] == 0 && !visit(to)) return false;
            }
            state[id] = 2;
            return true;
        };
        for (const auto& n : p.nodes)
            if (state[n.id] == 0 && !visit(n.id)) return false;
        for (size_t i = 0; i < j["variables"].size(); ++i) {
            const json& v = j["variables"][i];
            std::string ptr = "/variables/" + std::to_string(i);
            if (!v.is_object()) return fail(ptr, "expected {\"variable\", \"from\", \"to\", \"modulation\", \"map\"}");
            PlanVariable var;
            std::string name, modulation = "linear";
            if (!text(v, ptr, "variable", name, true) || !text(v, ptr, "modulation", modulation, false) || !text(v, ptr, "map", var.map, true) ||
                !number(v, ptr, "from", var.from) || !number(v, ptr, "to", var.to))
                return false;
            auto known = pipeline::selective_variable_from_name(name);
            if (!known) return fail(ptr + "/variable", fmt::format("unknown selective variable '{}'", name));
            var.variable = *known;
            const auto& sig = pipeline::signature(var.variable);
            for (const auto& [key, value] : {std::pair{"from", var.from}, std::pair{"to", var.to}})
                if (!(value >= sig.lo && value <= sig.hi) || (sig.integer && value != std::floor(value)))
                    return fail(ptr + "/" + key, fmt::format("expected {} in [{:.10g}, {:.10g}] for {}", sig.integer ? "a whole number" : "a number",
                                                             sig.lo, sig.hi, name));
            auto f = pipeline::modulation_function_from_name(modulation);
            if (!f) return fail(ptr + "/modulation", fmt::format("unknown modulation function '{}'", modulation));
            var.modulation = *f;
            if (v.contains("component")) {
                std::string letter;
                if (!text(v, ptr, "component", letter, true)) return false;
                auto c = letter.size() == 1 ? component_from_letter(letter[0]) : std::nullopt;
                if (!c) return fail(ptr + "/component", fmt::format("'{}' is not a component: expected one of D, G, S, T, R, M", letter));
                if (!sig.per_component) return fail(ptr + "/component", fmt::format("{} applies to every component; only subsample takes one", name));
                var.component = c;
            }
            if (v.contains("refine")) {
                double t = 0;
                if (!number(v, ptr, "refine", t)) return false;
                if (!var.component) return fail(ptr + "/refine", "refine applies to one component's sub-sampling only");
                if (!(t > 0 && t <= 100)) return fail(ptr + "/refine", "expected a number in (0, 100]");
                var.refine = t;
            }
            if (!index.count(var.map)) return fail(ptr + "/map", fmt::format("no node '{}' in the plan", var.map));
            p.variables.push_back(var);
        }
        if (!read_guidance(j, index, p)) return false;
        p.staged = true;
        if (j.contains("irradiance_cache")) {
            if (!j["irradiance_cache"].is_boolean()) return fail("/irradiance_cache", "expected true or false");
            p.irradiance_cache = j["irradiance_cache"].get<bool>();
        } else {  // plans of format 2 written before the field: the graph has the cache node
            p.irradiance_cache = index.count("irradiance_cache") > 0;
        }
        if (j.contains("modulation_map") && !j["modulation_map"].is_null()) {
            if (!text(j, "", "modulation_map", p.modulation_map, true)) return false;
            if (!index.count(p.modulation_map)) return fail("/modulation_map", fmt::format("no node '{}' in the plan", p.modulation_map));
        }
        if (j.contains("pruned")) {
            if (!j["pruned"].is_array()) return fail("/pruned", "expected an array");
            for (size_t i = 0; i < j["pruned"].size(); ++i) {
                std::string ptr = "/pruned/" + std::to_string(i);
                PlanRemoval r;
                if (!j["pruned"][i].is_object()) return fail(ptr, "expected {\"what\", \"reason\"}");
                if (!text(j["pruned"][i], ptr, "what", r.what, true) || !text(j["pruned"][i], ptr, "at", r.at, false) ||
                    !text(j["pruned"][i], ptr, "reason", r.reason, true))
                    return false;
                p.pruned.push_back(std::move(r));
            }
        }
        plan.pipeline = std::move(p);
        return true;
    }

private:
    const PositionedJson& doc_;
    DiagnosticSink& sink_;
};

}  // namespace

std::optional<CrexPlan> read_plan(const SourceFile& file, DiagnosticSink& sink) {
    PositionedJson doc;
    if (!parse_json_with_positions(file, doc, sink, "E401")) return std::nullopt;
    try {
        return PlanReader(doc, sink).read();
    } catch (const nlohmann::json::exception& e) {  // a check above is missing: still located, never a crash
        sink.report("E401", doc.span(""), fmt::format("malformed plan: {}", e.what()));
        return std::nullopt;
    }
}

}  // namespace crex
