#include "compiler/plan/read_plan.h"

#include <fmt/format.h>

#include "compiler/base/json_positions.h"

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
        std::string op = j.value("op", "");
        static const std::pair<const char*, Op> kOps[] = {{"exec", Op::kExec},         {"seq", Op::kSeq},
                                                          {"defer", Op::kDefer},       {"modulate", Op::kModulate},
                                                          {"budgeted", Op::kBudgeted}, {"repeat", Op::kRepeat},
                                                          {"repeat_until_empty", Op::kRepeatUntilEmpty}};
        bool known = false;
        for (const auto& [name, value] : kOps)
            if (op == name) out.op = value, known = true;
        if (!known) return fail(ptr + "/op", fmt::format("unknown step '{}'", op));
        auto number = [&](const char* key, double lo, double hi, double& v) {
            if (!j.contains(key) || !j[key].is_number()) return fail(ptr + "/" + key, "expected a number");
            v = j[key].get<double>();
            if (!(v >= lo && v <= hi)) return fail(ptr + "/" + key, fmt::format("expected a number in [{}, {}]", lo, hi));
            return true;
        };
        if (j.contains("at") && j["at"].is_string()) out.where = parse_location(j["at"].get<std::string>());
        double v = 0;
        switch (out.op) {
        case Op::kExec: {
            std::string c = j.value("component", "");
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
            if (!number("count", 1, 2147483647, v)) return false;
            out.count = static_cast<uint64_t>(v);
            if (j.contains("stride")) {
                if (!number("stride", 0, 1e300, v)) return false;
                out.stride = v;
            }
            break;
        case Op::kRepeatUntilEmpty:
            if (!number("cap", 1, 4294967295.0, v)) return false;
            out.cap = static_cast<uint32_t>(v);
            break;
        case Op::kModulate:
            if (!number("occurrences", 0, 1e300, v)) return false;
            out.occurrences = v;
            out.map = j.value("map", "importance");
            break;
        case Op::kBudgeted: out.owns_deferral = j.value("owns_deferral", true); break;
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
        if (!j.is_object() || j.value("format", "") != "crex-plan") {
            fail("", "not a crex plan (\"format\": \"crex-plan\" missing)");
            return std::nullopt;
        }
        if (j.value("version", 0) != kPlanFormatVersion) {
            fail("/version", fmt::format("this crex reads plan version {}", kPlanFormatVersion));
            return std::nullopt;
        }
        CrexPlan plan;
        if (j.contains("crex") && j["crex"].is_object()) plan.source = j["crex"].value("source", "");
        if (j.contains("scene") && j["scene"].is_object()) {
            plan.scene = j["scene"].value("spec", "");
            plan.census_hash = j["scene"].value("census_hash", "");
        }
        if (j.contains("settings") && j["settings"].is_object())
            for (const auto& [key, value] : j["settings"].items())
                if (value.is_string()) plan.settings[key] = value.get<std::string>();
        if (!j.contains("stages") || !j["stages"].is_object()) {
            fail("/stages", "missing the stages");
            return std::nullopt;
        }
        for (const char* stage : {"preselective", "selective"}) {
            std::string ptr = std::string("/stages/") + stage;
            if (!j["stages"].contains(stage)) {
                fail(ptr, "missing");
                return std::nullopt;
            }
            Node& out = std::string(stage) == "preselective" ? plan.program.preselective : plan.program.selective;
            if (!node(j["stages"][stage], ptr, out)) return std::nullopt;
            if (out.op != Op::kSeq) {
                fail(ptr + "/op", "a stage is a 'seq'");
                return std::nullopt;
            }
        }
        if (j.contains("pipeline") && !read_graph(j, plan)) return std::nullopt;
        return plan;
    }

    // A pipeline plan's graph: nodes and edges as plan_pipeline() wrote them.
    bool read_graph(const json& j, CrexPlan& plan) {
        PipelinePlan p;
        const json& pj = j["pipeline"];
        if (!pj.is_object() || !pj.contains("name") || !pj["name"].is_string()) return fail("/pipeline", "expected {\"name\": ...}");
        p.name = pj["name"].get<std::string>();
        p.scene = plan.scene;
        p.census_hash = plan.census_hash;
        p.program = plan.program;
        for (const auto& [k, v] : plan.settings) p.settings[k] = v;
        auto text = [&](const json& o, const char* key, const std::string& ptr, std::string& out, bool required) {
            if (!o.contains(key)) return !required || fail(ptr, std::string("missing \"") + key + "\"");
            if (!o[key].is_string()) return fail(ptr + "/" + key, "expected a string");
            out = o[key].get<std::string>();
            return true;
        };
        for (const char* list : {"nodes", "edges"})
            if (!j.contains(list) || !j[list].is_array()) return fail(std::string("/") + list, "expected an array");
        for (size_t i = 0; i < j["nodes"].size(); ++i) {
            const json& n = j["nodes"][i];
            std::string ptr = "/nodes/" + std::to_string(i);
            PlanNode node;
            if (!n.is_object()) return fail(ptr, "expected an object");
            if (!text(n, "id", ptr, node.id, true) || !text(n, "kind", ptr, node.kind, true) ||
                !text(n, "stage", ptr, node.stage, false) || !text(n, "label", ptr, node.label, false))
                return false;
            if (n.contains("params")) {
                if (!n["params"].is_object()) return fail(ptr + "/params", "expected an object");
                node.params = n["params"];
            }
            p.nodes.push_back(std::move(node));
        }
        for (size_t i = 0; i < j["edges"].size(); ++i) {
            const json& e = j["edges"][i];
            std::string ptr = "/edges/" + std::to_string(i);
            PlanEdge edge;
            if (!e.is_object()) return fail(ptr, "expected an object");
            if (!text(e, "from", ptr, edge.from, true) || !text(e, "to", ptr, edge.to, true) ||
                !text(e, "kind", ptr, edge.kind, true) || !text(e, "label", ptr, edge.label, false))
                return false;
            p.edges.push_back(std::move(edge));
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
    return PlanReader(doc, sink).read();
}

}  // namespace crex
