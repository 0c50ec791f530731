#include "compiler/pipeline/print.h"

#include <fmt/format.h>

namespace crex::pipeline {
namespace {

using ast::Expr;
using ast::Statement;
using ast::Value;

std::string values_text(const std::vector<Value>& values) {
    std::string out;
    for (const auto& v : values) out += (out.empty() ? "" : " ") + value_text(v);
    return out;
}

void print_statement(const Statement& s, const std::string& indent, std::string& out) {
    switch (s.kind) {
    case Statement::Kind::kSection:
        out += fmt::format("{}{} {{\n", indent, s.key);
        for (const auto& inner : s.body) print_statement(inner, indent + "  ", out);
        out += indent + "}\n";
        break;
    case Statement::Kind::kDefinition: out += fmt::format("{}{} = {}\n", indent, s.key, expr_text(s.expr)); break;
    case Statement::Kind::kVary:
        out += fmt::format("{}vary {} {} .. {} by {}{}{}\n", indent, s.key + (s.component.empty() ? "" : "(" + s.component + ")"),
                           value_text(s.lo), value_text(s.hi), expr_text(s.expr), s.using_fn.empty() ? "" : " using " + s.using_fn,
                           s.has_refine ? " refine " + value_text(s.refine) : "");
        break;
    case Statement::Kind::kSetting:
        out += fmt::format("{}{} {}{}\n", indent, s.key, values_text(s.values), s.has_by ? " by " + expr_text(s.expr) : "");
        break;
    }
}

void print_stage(const char* name, const ResolvedStage& stage, const std::vector<ResolvedVariable>* vary, std::string& out) {
    if (!stage.crex && stage.settings.empty() && (!vary || vary->empty())) return;
    out += fmt::format("  {} {{\n", name);
    if (stage.crex) out += fmt::format("    crex {}{}\n", value_text(*stage.crex), stage.crex_by ? " by " + expr_text(*stage.crex_by) : "");
    for (const auto& [key, v] : stage.settings) out += fmt::format("    {} {}\n", key, value_text(v));
    if (vary)
        for (const auto& v : *vary)
            out += fmt::format("    vary {} {} .. {} by {}{}{}\n", v.varied(), value_text(v.lo), value_text(v.hi), expr_text(v.by),
                               v.using_fn.empty() ? "" : " using " + v.using_fn, v.refine ? fmt::format(" refine {:g}", *v.refine) : "");
    out += "  }\n";
}

}  // namespace

std::string value_text(const Value& v) {
    switch (v.kind) {
    case Value::Kind::kNumber: return fmt::format("{:g}{}{}", v.number, v.unit.empty() ? "" : " ", v.unit);
    case Value::Kind::kString: return "\"" + v.text + "\"";
    case Value::Kind::kBool: return v.boolean ? "true" : "false";
    case Value::Kind::kCross: return "x";
    }
    return "";
}

std::string expr_text(const Expr& e) {
    switch (e.kind) {
    case Expr::Kind::kReference: return e.name;
    case Expr::Kind::kLiteral: return value_text(e.literal);
    case Expr::Kind::kCall: {
        std::string args;
        for (const auto& a : e.args) {
            if (!args.empty()) args += ", ";
            args += a.name.empty() ? expr_text(a.expr) : a.name + " " + value_text(a.value);
        }
        return fmt::format("{}({})", e.name, args);
    }
    }
    return "";
}

std::string print_file(const ast::File& file) {
    std::string out;
    for (const auto& p : file.pipelines) {
        out += fmt::format("pipeline {}{} {{\n", p.name, p.base.empty() ? "" : " extends " + p.base);
        for (const auto& s : p.body) print_statement(s, "  ", out);
        out += "}\n";
    }
    return out;
}

std::string print_resolved(const ResolvedPipeline& p) {
    std::string chain;
    for (size_t i = 1; i < p.chain.size(); ++i) chain += (chain.empty() ? "" : ", ") + p.chain[i];
    std::string out = chain.empty() ? "" : fmt::format("// {} with its bases applied: {}\n", p.name, chain);
    out += fmt::format("pipeline {} {{\n", p.name);
    for (const auto& [key, values] : p.top) out += fmt::format("  {} {}\n", key, values_text(values));
    print_stage("preselective", p.preselective, nullptr, out);
    if (!p.maps.empty()) {
        out += "  guidance {\n";
        for (const auto& [name, e] : p.maps) out += fmt::format("    {} = {}\n", name, expr_text(e));
        out += "  }\n";
    }
    print_stage("selective", p.selective, &p.vary, out);
    if (!p.output.empty()) {
        out += "  output {\n";
        for (const auto& [key, values] : p.output) {
            out += "    " + key;
            for (const auto& v : values) out += " " + value_text(v);
            out += "\n";
        }
        out += "  }\n";
    }
    out += "}\n";
    return out;
}

}  // namespace crex::pipeline
