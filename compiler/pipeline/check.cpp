#include "compiler/pipeline/check.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "base/image_formats.h"
#include "base/nearest_name.h"
#include "compiler/crex/compile.h"
#include "compiler/pipeline/registry.h"
#include "compiler/pipeline/resolve.h"
#include "compiler/pipeline/stdlib_pipelines.h"
#include "compiler/pipeline/settings_table.h"

namespace crex::pipeline {
namespace {

using ast::Expr;
using ast::Statement;
using ast::Value;

using Type = ValueType;

std::string_view type_name(Type t) {
    switch (t) {
    case Type::kImage: return "an image";
    case Type::kBuffer: return "a component buffer";
    case Type::kMap: return "a map";
    case Type::kObjects: return "a set of tagged objects";
    case Type::kComponent: return "a component letter";
    }
    return "?";
}

// What a parameter takes, with its article (literal_ok's ranges).
std::string_view literal_name(LiteralKind k) {
    switch (k) {
    case LiteralKind::kNumber: return "a finite number";
    case LiteralKind::kAngle: return "an angle above 0 and below 180 deg, like 2 deg";
    case LiteralKind::kString: return "a string";
    case LiteralKind::kNone: break;
    }
    return "?";
}

const std::map<std::string, Type>& builtin_names() {
    static const std::map<std::string, Type> names = {
        {"preview", Type::kImage}, {"direct", Type::kBuffer}, {"emission", Type::kBuffer}, {"ambient", Type::kBuffer},
        {"D", Type::kComponent},   {"G", Type::kComponent},   {"S", Type::kComponent},    {"T", Type::kComponent},
        {"R", Type::kComponent},   {"M", Type::kComponent}};
    return names;
}

template <class Names>
std::string nearest(const std::string& name, const Names& names) {
    return did_you_mean(name, std::vector<std::string>(names.begin(), names.end()));
}

class Checker {
public:
    explicit Checker(DiagnosticSink& sink) : sink_(sink) {}

    void file(const ast::File& f) {
        std::set<std::string> earlier;
        // The maps each pipeline above defines or inherits: a chain of `extends` in the file is
        // then linear to check (resolving every base afresh made 4,000 pipelines take 25 s).
        std::map<std::string, std::vector<std::string>> maps_of;
        for (const auto& p : f.pipelines) {
            if (earlier.count(p.name)) sink_.report("E211", p.name_span, fmt::format("pipeline '{}' is defined twice", p.name));
            std::vector<std::string> inherited;
            if (!p.base.empty() && base(f, p, earlier)) {
                if (auto it = maps_of.find(p.base); it != maps_of.end()) {
                    inherited = it->second;
                } else if (auto r = stdlib_base(f, p)) {  // a stdlib pipeline, checked with its own bases
                    for (const auto& [name, _] : r->maps) inherited.push_back(name);
                }
            }
            pipeline(p, inherited);
            std::vector<std::string> all = inherited;
            std::set<std::string> in_all(all.begin(), all.end());  // a set beside: n maps were n^2 finds
            for (const auto& sec : p.body)
                if (sec.kind == Statement::Kind::kSection && sec.key == "guidance")
                    for (const auto& s : sec.body)
                        if (s.kind == Statement::Kind::kDefinition && in_all.insert(s.key).second) all.push_back(s.key);
            maps_of[p.name] = std::move(all);
            earlier.insert(p.name);
        }
    }

private:
    // A stdlib base (stdlib/pipelines/NAME.pipe) resolved with its chain of bases, its files
    // checked as `crex plan` would use them: a base file with errors, or a chain that comes back
    // to itself across files, is an error at the `extends` that reaches it (E210), with the
    // base's own diagnostics beside it. `crex check` passed such a pipeline that plan refused.
    std::optional<ResolvedPipeline> stdlib_base(const ast::File& f, const ast::Pipeline& p) {
        DiagnosticSink chain;
        std::optional<ResolvedPipeline> r;
        if (const ast::Pipeline* b = find_base(f, p, chain)) r = resolve_from(f, *b, chain);
        if (r)
            for (const std::string& name : r->chain) check_stdlib_file(name, chain);
        if (!chain.has_errors()) return r;
        std::vector<Diagnostic> errors;
        for (const auto& d : chain.sorted())
            if (d.severity == Severity::kError) errors.push_back(d);
        Diagnostic& d = sink_.report("E210", p.base_span, fmt::format("pipeline '{}' extends '{}', which cannot be used: {}", p.name, p.base,
                                                                      errors.front().message));
        for (const auto& e : errors) d.notes.push_back({e.span, fmt::format("error[{}]: {}", e.code, e.message)});
        d.help = "fix the base's file, or extend another pipeline";
        return std::nullopt;
    }

    // The errors of the stdlib file defining `name`, checked once per process (it may be read
    // as the base of many pipelines); a file being checked is not checked again within itself,
    // so files extending each other end (their cycle is resolve_from's E210).
    static void check_stdlib_file(const std::string& name, DiagnosticSink& out) {
        static thread_local std::map<std::string, std::vector<Diagnostic>> checked;
        static thread_local std::set<std::string> checking;
        auto it = checked.find(name);
        if (it == checked.end()) {
            // Each file checks the files of its own bases: a chain of thousands of files in
            // $CREX_STDLIB would recurse as deep. Past 64 the deeper files are resolved (E210
            // for a cycle or an unknown base) but not checked.
            if (checking.size() >= 64 || !checking.insert(name).second) return;
            DiagnosticSink sink;
            if (const ast::File* file = stdlib_file(name, sink)) Checker(sink).file(*file);
            std::vector<Diagnostic> errors;
            for (const auto& d : sink.diagnostics())
                if (d.severity == Severity::kError) errors.push_back(d);
            checking.erase(name);
            it = checked.emplace(name, std::move(errors)).first;
        }
        for (const auto& d : it->second) out.add(d);
    }

    // True if the base exists (above in the file, or as a stdlib file).
    bool base(const ast::File& f, const ast::Pipeline& p, const std::set<std::string>& earlier) {
        if (earlier.count(p.base)) return true;
        DiagnosticSink stdlib_sink;
        if (find_base(f, p, stdlib_sink)) return true;
        for (const auto& d : stdlib_sink.diagnostics()) sink_.add(d);
        const auto& lib = stdlib_pipeline_names();
        std::vector<std::string> all(lib.begin(), lib.end());
        all.insert(all.end(), earlier.begin(), earlier.end());
        sink_.report("E210", p.base_span, fmt::format("pipeline '{}' extends '{}', which is neither a stdlib pipeline nor "
                                                      "defined above it", p.name, p.base)).help = nearest(p.base, all);
        return false;
    }

    void pipeline(const ast::Pipeline& p, const std::vector<std::string>& inherited) {
        maps_.clear();
        used_.clear();
        inherited_.clear();
        for (const auto& name : inherited) inherited_.insert(name);
        section("", p.body);
        for (const auto& [name, span] : maps_)
            if (!used_.count(name) && !overrides_.count(name))
                sink_.report("W201", span, fmt::format("map '{}' is defined but no selective variable or crex uses it", name));
    }

    void section(const std::string& where, const std::vector<Statement>& body) {
        std::map<std::string, SourceSpan> seen;
        for (const auto& s : body) {
            if (s.kind != Statement::Kind::kDefinition) {
                std::string key = (s.kind == Statement::Kind::kVary ? "vary " : "") + s.key +
                                  (s.component.empty() ? "" : "(" + s.component + ")");
                if (auto it = seen.find(key); it != seen.end()) {
                    Diagnostic& d = sink_.report("E211", s.key_span, fmt::format("'{}' is given twice here", s.key));
                    d.notes.push_back({it->second, "first given here"});
                    continue;
                }
                seen[key] = s.key_span;
            }
            switch (s.kind) {
            case Statement::Kind::kSection: {
                const auto sections = setting_sections();
                if (!where.empty() || s.key.empty() || std::find(sections.begin(), sections.end(), s.key) == sections.end()) {
                    std::vector<std::string> names;
                    for (auto n : sections)
                        if (!n.empty()) names.emplace_back(n);
                    sink_.report("E202", s.key_span,
                                 where.empty() ? fmt::format("unknown section '{}'; sections are preselective, guidance, "
                                                             "selective and output", s.key)
                                               : fmt::format("sections do not nest: '{}' inside '{}'", s.key, where))
                        .help = nearest(s.key, names);
                    continue;
                }
                section(s.key, s.body);
                break;
            }
            case Statement::Kind::kDefinition: definition(where, s); break;
            case Statement::Kind::kVary: vary(where, s); break;
            case Statement::Kind::kSetting: setting(where, s); break;
            }
        }
    }

    void definition(const std::string& where, const Statement& s) {
        if (where != "guidance") {
            sink_.report("E202", s.key_span, fmt::format("maps are defined in the 'guidance' section, not {}",
                                                         where.empty() ? "at the top of the pipeline" : "in '" + where + "'"));
            return;
        }
        if (maps_.count(s.key) || builtin_names().count(s.key)) {
            sink_.report("E211", s.key_span, fmt::format("'{}' is already defined", s.key));
            return;
        }
        if (inherited_.count(s.key)) overrides_.insert(s.key);  // replaces the base's map: used there
        deepest_reference_ = 0;
        auto t = expr(s.expr);
        // Maps built on maps: planning and evaluating them recurse once per level (a chain of
        // 29,000 blur()s crashed `crex plan`), so the chain is bounded like the nesting.
        map_depth_[s.key] = deepest_reference_ + 1;
        if (map_depth_[s.key] > kMaxMapChain) {
            sink_.report("E214", s.key_span, fmt::format("'{}' is built on a chain of more than {} maps", s.key, kMaxMapChain)).help =
                "combine maps with importance(...) instead of chaining them";
            map_depth_[s.key] = 0;
        }
        if (t && *t != Type::kMap)
            sink_.report("E206", s.expr.span, fmt::format("'{}' must be a map, but this is {}", s.key, type_name(*t)));
        maps_[s.key] = s.key_span;
    }

    void vary(const std::string& where, const Statement& s) {
        if (where != "selective") {
            sink_.report("E202", s.key_span, "selective variables are varied in the 'selective' section");
            return;
        }
        auto known = selective_variable_from_name(s.key);
        const VariableSignature* var = known ? &signature(*known) : nullptr;
        if (!var) {
            std::vector<std::string> names;
            for (const auto& v : kSelectiveVariables) names.emplace_back(v.name);
            sink_.report("E207", s.key_span, fmt::format("unknown selective variable '{}'", s.key)).help = nearest(s.key, names);
        } else {
            if (!s.component.empty() && !var->per_component) {
                sink_.report("E207", s.component_span,
                             fmt::format("'{}' applies to every component; only subsample takes one (`vary subsample(D) ...`)", s.key));
            } else if (!s.component.empty() && (s.component.size() != 1 || !component_from_letter(s.component[0]))) {
                sink_.report("E207", s.component_span,
                             fmt::format("'{}' is not a component: expected one of D, G, S, T, R, M", s.component));
            }
            for (const Value* v : {&s.lo, &s.hi}) {
                if (v->kind != Value::Kind::kNumber || !v->unit.empty()) {
                    sink_.report("E208", v->span, fmt::format("{}: expected a plain number", s.key));
                    continue;
                }
                bool whole = v->number == static_cast<double>(static_cast<long long>(v->number));
                if (v->number < var->lo || v->number > var->hi || (var->integer && !whole))
                    sink_.report("E208", v->span, fmt::format("{}: {:g} is out of range: expected {} in [{}, {}]", s.key, v->number,
                                                              var->integer ? "an integer" : "a number", fmt::format("{:.10g}", var->lo),
                                                              fmt::format("{:.10g}", var->hi)));
            }
        }
        if (s.has_refine) {
            if (s.component.empty() || !var || !var->per_component)
                sink_.report("E207", s.refine.span, "refine applies to one component's sub-sampling only (`vary subsample(D) 8 .. 1 by m refine 0.5`)");
            else if (s.refine.kind != Value::Kind::kNumber || !s.refine.unit.empty() || !(s.refine.number > 0 && s.refine.number <= 100))
                sink_.report("E208", s.refine.span, "refine: expected a plain number in (0, 100] (a share of the corners' mean light)");
        }
        if (!s.using_fn.empty()) {
            const std::vector<std::string> functions(kModulationFunctionNames.begin(), kModulationFunctionNames.end());
            if (!modulation_function_from_name(s.using_fn))
                sink_.report("E206", s.using_span,
                             fmt::format("unknown modulation function '{}': expected linear, quadratic, sqrt or step", s.using_fn))
                    .help = nearest(s.using_fn, functions);
        }
        map_use(s.expr);
    }

    void setting(const std::string& where, const Statement& s) {
        const SettingRule* rule = find_setting_rule(where, s.key);
        if (!rule) {
            std::vector<std::string> names;
            for (const auto& r : setting_rules())
                if (r.section == where) names.emplace_back(r.name);
            sink_.report("E202", s.key_span, where == "guidance" ? fmt::format("'{}' is not a map definition (write NAME = operator(...))", s.key)
                                                                : fmt::format("unknown setting '{}'{}", s.key, where.empty() ? "" : " in '" + where + "'"))
                .help = nearest(s.key, names);
            return;
        }
        const SettingShape shape = rule->shape;
        auto bad_at = [&](const SourceSpan& span, const std::string& expected) {
            sink_.report("E203", span, fmt::format("{}: expected {}", s.key, expected));
        };
        auto bad = [&](const std::string& expected) {
            bad_at(s.values.empty() ? s.key_span : s.values.front().span.merge(s.values.back().span), expected);
        };
        auto is = [&](size_t i, Value::Kind k) { return i < s.values.size() && s.values[i].kind == k; };
        auto plain_number = [&](size_t i) { return is(i, Value::Kind::kNumber) && s.values[i].unit.empty(); };
        if (s.has_by && shape != SettingShape::kCrex) bad("no 'by' here");
        switch (shape) {
        case SettingShape::kString:
            if (!(s.values.size() == 1 && is(0, Value::Kind::kString))) bad("a string in double quotes");
            break;
        case SettingShape::kImages:
            if (s.values.empty() || !std::all_of(s.values.begin(), s.values.end(), [](const Value& v) { return v.kind == Value::Kind::kString; }))
                bad("one or more image paths in double quotes, e.g. image \"out/x.exr\" \"out/x.png\"");
            else
                for (const Value& v : s.values)
                    if (!is_image_file_name(v.text)) {
                        const std::string ext = image_extension(v.text);
                        sink_.report("E203", v.span, fmt::format("{}: unknown image format '{}': crex writes {}", s.key,
                                                                 ext.empty() ? "(no extension)" : ext, image_formats_text()));
                    }
            break;
        case SettingShape::kBool:
            if (!(s.values.size() == 1 && is(0, Value::Kind::kBool))) bad("true or false");
            break;
        case SettingShape::kInteger:
        case SettingShape::kNumber:
            if (!(s.values.size() == 1 && plain_number(0))) bad(shape == SettingShape::kInteger ? "a whole number" : "a number");
            else if (auto e = setting_literal_error(*rule, s.values[0].number, s.values[0].span.text()); !e.empty())
                sink_.report("E203", s.values[0].span, fmt::format("{}: {}", s.key, e));
            break;
        case SettingShape::kSize:
            if (!(s.values.size() == 3 && plain_number(0) && is(1, Value::Kind::kCross) && plain_number(2))) {
                bad(fmt::format("WIDTH x HEIGHT, e.g. 512 x 512 ({:g} .. {:g} each)", rule->lo, rule->hi));
                break;
            }
            for (size_t i : {size_t{0}, size_t{2}})
                if (auto e = setting_literal_error(*rule, s.values[i].number, s.values[i].span.text()); !e.empty())
                    sink_.report("E203", s.values[i].span, fmt::format("{}: {}: {}", s.key, i == 0 ? "width" : "height", e));
            break;
        case SettingShape::kBudget: {
            const Value* v = s.values.size() == 1 ? &s.values[0] : nullptr;
            if (!v || v->kind != Value::Kind::kNumber) {
                sink_.report("E209", s.values.empty() ? s.key_span : s.values.front().span, "budget: expected a time like 10 s, 500 ms or 25 %");
            } else if (v->unit != "s" && v->unit != "ms" && v->unit != "%") {
                sink_.report("E209", v->span, fmt::format("budget: '{}' needs a unit: s, ms or % (of a profiled full render)", v->number));
            } else {
                double amount = v->unit == "ms" ? v->number / 1000 : v->number;
                if (auto e = budget_range_error(amount, v->unit == "%"); !e.empty())
                    sink_.report("E209", v->span, fmt::format("budget: expected {}", e));
            }
            break;
        }
        case SettingShape::kPolicy: {
            std::vector<std::string> names(scheduling_policy_names().begin(), scheduling_policy_names().end());
            if (!(s.values.size() == 1 && is(0, Value::Kind::kString)))
                bad("a policy in double quotes: \"tasks\", \"batches\", \"queues\" or \"progressive\"");
            else if (!scheduling_policy_from_name(s.values[0].text))
                sink_.report("E203", s.values[0].span, fmt::format("policy: unknown scheduling policy '{}': expected \"tasks\" "
                                                                   "(whole tasks, thesis 5.4), \"batches\" (rays by pixel importance, "
                                                                   "5.5), \"queues\" (per-variable queues, 8.3) or \"progressive\"",
                                                                   s.values[0].text))
                    .help = nearest(s.values[0].text, names);
            break;
        }
        case SettingShape::kCrex: break;
        }
        if (shape == SettingShape::kCrex) {
            if (!(s.values.size() == 1 && is(0, Value::Kind::kString))) {
                bad("a crex in double quotes, e.g. crex \"TT\"");
                return;
            }
            const Value& lit = s.values[0];
            DiagnosticSink crex_sink;
            CompiledCrex c = compile_crex(*lit.text_span.file, lit.text_span.begin, lit.text_span.end, crex_sink);
            for (const auto& d : crex_sink.diagnostics()) sink_.add(d);
            if (where == "preselective" && c.ast) {
                bool braces = lit.text.find('{') != std::string::npos;
                if (braces)
                    sink_.report("E212", lit.text_span, "the pre-selective crex may not contain '{ }': importance exists only "
                                                        "after guidance").help = "move the '{ }' part to the selective section";
            }
            if (s.has_by) {
                if (where != "selective") sink_.report("E203", s.expr.span, "only the selective crex is modulated 'by' a map");
                map_use(s.expr);
            }
        }
    }

    // A map argument of `by`: a defined map, or an expression producing one.
    void map_use(const Expr& e) {
        auto t = expr(e);
        if (t && *t != Type::kMap) sink_.report("E206", e.span, fmt::format("expected a map here, but this is {}", type_name(*t)));
    }

    std::optional<Type> reference(const std::string& name, const SourceSpan& span) {
        if (auto it = builtin_names().find(name); it != builtin_names().end()) return it->second;
        if (maps_.count(name)) {
            used_.insert(name);
            deepest_reference_ = std::max(deepest_reference_, map_depth_[name]);
            return Type::kMap;
        }
        if (inherited_.count(name)) return Type::kMap;
        Diagnostic& d = sink_.report("E205", span, fmt::format("'{}' is not defined (maps must be defined above their use)", name));
        // A suggestion looks at every map: for the first few unknown names only, or n of them
        // among n maps would take n^2.
        if (suggestions_left_ > 0) {
            --suggestions_left_;
            std::vector<std::string> names;
            for (const auto& [n, _] : maps_) names.push_back(n);
            for (const auto& [n, _] : builtin_names()) names.push_back(n);
            d.help = nearest(name, names);
        }
        return std::nullopt;
    }

    std::optional<Type> expr(const Expr& e) {
        switch (e.kind) {
        case Expr::Kind::kReference: return reference(e.name, e.name_span);
        case Expr::Kind::kLiteral:
            sink_.report("E206", e.span, "expected a map, a buffer or an operator call, not a literal value");
            return std::nullopt;
        case Expr::Kind::kCall: return call(e);
        }
        return std::nullopt;
    }

    bool literal_ok(const Value& v, LiteralKind kind) {
        switch (kind) {
        case LiteralKind::kString: return v.kind == Value::Kind::kString;
        case LiteralKind::kNumber: return v.kind == Value::Kind::kNumber && v.unit.empty() && std::isfinite(v.number);
        case LiteralKind::kAngle: return v.kind == Value::Kind::kNumber && v.unit == "deg" && v.number > 0 && v.number < 180;
        case LiteralKind::kNone: break;
        }
        return false;
    }

    std::optional<Type> call(const Expr& e) {
        auto known = guidance_operator_from_name(e.name);
        const OperatorSignature* op = known ? &signature(*known) : nullptr;
        if (!op) {
            sink_.report("E204", e.name_span, fmt::format("unknown guidance operator '{}'", e.name)).help =
                nearest(e.name, guidance_operator_names());
            return std::nullopt;
        }
        size_t positional = 0;
        std::set<std::string> given;
        for (const auto& a : e.args) {
            if (a.name.empty()) {
                // Positional: the n-th positional parameter.
                const ParamSignature* p = nullptr;
                size_t k = 0;
                for (const auto& q : op->parameters())
                    if (q.name.empty() && k++ == positional) p = &q;
                ++positional;
                if (!p) {
                    sink_.report("E206", a.span, fmt::format("{}() takes no more positional arguments", op->name));
                    continue;
                }
                if (p->literal != LiteralKind::kNone) {
                    if (a.expr.kind != Expr::Kind::kLiteral || !literal_ok(a.expr.literal, p->literal))
                        sink_.report("E206", a.span, fmt::format("{}(): expected {} here", op->name, literal_name(p->literal)));
                    continue;
                }
                auto t = expr(a.expr);
                if (t && !accepts(p->accepts, *t)) {
                    std::string want;
                    for (Type ty : {Type::kImage, Type::kBuffer, Type::kMap, Type::kObjects, Type::kComponent})
                        if (accepts(p->accepts, ty)) want += (want.empty() ? "" : " or ") + std::string(type_name(ty));
                    sink_.report("E206", a.span, fmt::format("{}(): expected {}, but this is {}", op->name, want, type_name(*t)));
                }
                continue;
            }
            if (!given.insert(a.name).second) {
                sink_.report("E211", a.name_span, fmt::format("{}(): '{}' is given twice", op->name, a.name));
                continue;
            }
            const ParamSignature* p = nullptr;
            for (const auto& q : op->parameters())
                if (q.name == a.name) p = &q;
            if (p) {
                if (!literal_ok(a.value, p->literal))
                    sink_.report("E206", a.value.span, fmt::format("{}(): '{}' expects {}", op->name, a.name, literal_name(p->literal)));
                if (op->op == GuidanceOperator::kImportance && a.name == "op" && a.value.kind == Value::Kind::kString &&
                    a.value.text != "+" && a.value.text != "max" && a.value.text != "*")
                    sink_.report("E206", a.value.span, "importance(): op is \"+\", \"max\" or \"*\"");
                continue;
            }
            if (op->weighted_maps) {  // `task 0.5`: the map `task` with weight 0.5
                reference(a.name, a.name_span);
                if (!(a.value.kind == Value::Kind::kNumber && a.value.unit.empty() && a.value.number >= 0 && std::isfinite(a.value.number)))
                    sink_.report("E206", a.value.span, fmt::format("importance(): the weight of '{}' must be a finite number >= 0", a.name));
                continue;
            }
            std::vector<std::string> names;
            for (const auto& q : op->parameters())
                if (!q.name.empty()) names.emplace_back(q.name);
            sink_.report("E206", a.name_span, fmt::format("{}() has no parameter '{}'", op->name, a.name)).help = nearest(a.name, names);
        }
        size_t required = 0;
        for (const auto& q : op->parameters()) required += q.name.empty() && q.required;
        if (positional < required)
            sink_.report("E206", e.span, fmt::format("{}() needs {} argument{}, got {}", op->name, required, required == 1 ? "" : "s", positional));
        return op->result;
    }

    DiagnosticSink& sink_;
    std::map<std::string, SourceSpan> maps_;
    static constexpr int kMaxMapChain = 256;
    std::map<std::string, int> map_depth_;  // 1 + the deepest map a definition reads
    int deepest_reference_ = 0;
    int suggestions_left_ = 20;  // "did you mean" for unknown map names
    std::set<std::string> used_;
    std::set<std::string> inherited_;   // maps defined by the bases
    std::set<std::string> overrides_;   // maps redefined here that the bases use
};

}  // namespace

std::vector<std::string> guidance_operator_names() {
    std::vector<std::string> out;
    for (const auto& o : kGuidanceOperators) out.emplace_back(o.name);
    return out;
}

void check_pipeline_file(const ast::File& file, DiagnosticSink& sink) { Checker(sink).file(file); }

}  // namespace crex::pipeline
