// The pipeline parser's ANTLR boundary: text -> parse tree -> ast::File. Nothing else in the
// pipeline compiler sees ANTLR types.
#include "compiler/pipeline/parse.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <optional>

#include "PipelineLexer.h"
#include "PipelineParser.h"
#include "antlr4-runtime.h"
#include "compiler/crex/code_point_stream.h"

namespace crex::pipeline {
namespace {

using grammar::PipelineParser;

// Syntax errors in crex's words: what was found, what was expected; the first one also
// points at the bracket that was left open (found before parsing), and a lone '"' is named
// as the unterminated string it is.
class SyntaxErrors : public antlr4::BaseErrorListener {
public:
    SyntaxErrors(const SourceFile& file, const detail::DecodedText& text, DiagnosticSink& sink)
        : file_(file), text_(text), sink_(sink) {}

    std::optional<DiagnosticNote> bracket_note;

    void syntaxError(antlr4::Recognizer* recognizer, antlr4::Token* token, size_t line, size_t col, const std::string& msg,
                     std::exception_ptr) override {
        // At the end of the file there is no character to point at: an empty span there (a span
        // one past the text was what the pipeline fuzzer's first crash found).
        const uint32_t size = static_cast<uint32_t>(file_.text().size());
        uint32_t begin = std::min(file_.offset_of(static_cast<uint32_t>(line), static_cast<uint32_t>(col) + 1), size);
        uint32_t end = std::min(begin + 1, size);
        std::string found = "end of file";
        if (token && token->getType() != antlr4::Token::EOF && token->getStopIndex() + 1 < text_.byte_offsets.size()) {
            found = "'" + token->getText() + "'";
            begin = text_.byte_offsets[token->getStartIndex()];
            end = text_.byte_offsets[token->getStopIndex() + 1];
        }
        std::string what = msg;
        if (token && token->getText() == "\"") {
            what = "unterminated string: no closing '\"' before the end of the line";
        } else if (auto* p = dynamic_cast<antlr4::Parser*>(recognizer); p && token) {
            auto expected = p->getExpectedTokens().toString(p->getVocabulary());
            what = fmt::format("unexpected {}; expected {}", found, expected);
        } else if (msg.rfind("token recognition error", 0) == 0) {
            what = fmt::format("unexpected character {}", msg.substr(msg.find("at: ") + 4));
        }
        Diagnostic& d = sink_.report("E201", {&file_, begin, std::max(end, begin)}, what);
        if (bracket_note && !noted_) d.notes.push_back(*bracket_note);
        noted_ = true;
    }

private:
    const SourceFile& file_;
    const detail::DecodedText& text_;
    DiagnosticSink& sink_;
    bool noted_ = false;
};

// The bracket a missing closer belongs to, for a note at the first syntax error. Brackets are
// matched on the tokens (strings and comments are single tokens); when a '}' that starts its
// line sits left of the line that opened the '{' it closes, that '{' is the likely culprit
// (`guidance {` without its '}' makes the pipeline's last '}' close it instead).
std::optional<DiagnosticNote> unclosed_bracket(const SourceFile& file, const detail::DecodedText& text,
                                               antlr4::CommonTokenStream& tokens) {
    struct Open {
        std::string bracket;
        uint32_t at;
    };
    std::vector<Open> stack;
    std::optional<Open> suspect;
    std::map<uint32_t, uint32_t> first_col_of_line;  // line -> column of its first token
    for (antlr4::Token* t : tokens.getTokens()) {
        if (t->getType() == antlr4::Token::EOF || t->getChannel() != antlr4::Token::DEFAULT_CHANNEL) continue;
        uint32_t at = text.byte_offsets[t->getStartIndex()];
        auto pos = file.position(at);
        first_col_of_line.emplace(pos.line, pos.col);
        const std::string s = t->getText();
        if (s == "{" || s == "(" || s == "[") {
            stack.push_back({s, at});
        } else if (s == "}" || s == ")" || s == "]") {
            const std::string want = s == "}" ? "{" : s == ")" ? "(" : "[";
            if (stack.empty()) continue;
            if (stack.back().bracket != want) {
                return DiagnosticNote{{&file, stack.back().at, stack.back().at + 1},
                                      fmt::format("this '{}' is not closed before the '{}'", stack.back().bracket, s)};
            }
            auto opener = file.position(stack.back().at);
            if (s == "}" && !suspect && first_col_of_line[pos.line] == pos.col && pos.line > opener.line &&
                pos.col < first_col_of_line[opener.line])
                suspect = stack.back();
            stack.pop_back();
        }
    }
    if (stack.empty()) return std::nullopt;
    const Open& o = suspect ? *suspect : stack.back();
    return DiagnosticNote{{&file, o.at, o.at + 1}, fmt::format("this '{}' is never closed", o.bracket)};
}

class Builder {
public:
    Builder(const SourceFile& file, const detail::DecodedText& text) : file_(file), text_(text) {}

    SourceSpan span(antlr4::Token* t) const {
        return {&file_, text_.byte_offsets.at(t->getStartIndex()), text_.byte_offsets.at(t->getStopIndex() + 1)};
    }
    SourceSpan span(antlr4::ParserRuleContext* ctx) const {
        SourceSpan a = span(ctx->getStart());
        if (ctx->getStop() && ctx->getStop()->getType() != antlr4::Token::EOF && ctx->getStop()->getStopIndex() >= ctx->getStart()->getStartIndex())
            a = a.merge(span(ctx->getStop()));
        return a;
    }

    ast::File file(PipelineParser::FileContext* ctx) {
        ast::File f;
        for (auto* p : ctx->pipeline()) f.pipelines.push_back(pipeline(p));
        return f;
    }

private:
    ast::Pipeline pipeline(PipelineParser::PipelineContext* ctx) {
        ast::Pipeline p;
        p.name = ctx->name->getText();
        p.name_span = span(ctx->name);
        if (ctx->base) {
            p.base = ctx->base->getText();
            p.base_span = span(ctx->base);
        }
        p.body = block(ctx->block());
        p.span = span(ctx);
        return p;
    }

    std::vector<ast::Statement> block(PipelineParser::BlockContext* ctx) {
        std::vector<ast::Statement> out;
        for (auto* s : ctx->statement()) out.push_back(statement(s));
        return out;
    }

    ast::Statement statement(PipelineParser::StatementContext* ctx) {
        ast::Statement s;
        s.span = span(ctx);
        if (auto* sec = dynamic_cast<PipelineParser::SectionContext*>(ctx)) {
            s.kind = ast::Statement::Kind::kSection;
            s.key = sec->IDENT()->getText();
            s.key_span = span(sec->IDENT()->getSymbol());
            s.body = block(sec->block());
        } else if (auto* def = dynamic_cast<PipelineParser::DefinitionContext*>(ctx)) {
            s.kind = ast::Statement::Kind::kDefinition;
            s.key = def->IDENT()->getText();
            s.key_span = span(def->IDENT()->getSymbol());
            s.expr = expr(def->expr());
        } else if (auto* vary = dynamic_cast<PipelineParser::VaryContext*>(ctx)) {
            s.kind = ast::Statement::Kind::kVary;
            s.key = vary->name->getText();
            s.key_span = span(vary->name);
            if (vary->comp) {
                s.component = vary->comp->getText();
                s.component_span = span(vary->comp);
            }
            s.lo = value(vary->lo);
            s.hi = value(vary->hi);
            s.expr = expr(vary->expr());
            s.has_by = true;
            if (vary->USING()) {
                s.using_fn = vary->fn->getText();
                s.using_span = span(vary->fn);
            }
            if (vary->refine) {
                s.has_refine = true;
                s.refine = value(vary->refine);
            }
        } else if (auto* set = dynamic_cast<PipelineParser::SettingContext*>(ctx)) {
            s.kind = ast::Statement::Kind::kSetting;
            s.key = set->IDENT()->getText();
            s.key_span = span(set->IDENT()->getSymbol());
            for (auto* v : set->value()) s.values.push_back(value(v));
            if (set->BY()) {
                s.has_by = true;
                s.expr = expr(set->expr());
            }
        }
        return s;
    }

    ast::Expr expr(PipelineParser::ExprContext* ctx) {
        ast::Expr e;
        e.span = span(ctx);
        if (auto* call = dynamic_cast<PipelineParser::CallContext*>(ctx)) {
            e.kind = ast::Expr::Kind::kCall;
            e.name = call->IDENT()->getText();
            e.name_span = span(call->IDENT()->getSymbol());
            for (auto* a : call->arg()) e.args.push_back(arg(a));
        } else if (auto* ref = dynamic_cast<PipelineParser::ReferenceContext*>(ctx)) {
            e.kind = ast::Expr::Kind::kReference;
            e.name = ref->IDENT()->getText();
            e.name_span = span(ref->IDENT()->getSymbol());
        } else if (auto* lit = dynamic_cast<PipelineParser::LiteralContext*>(ctx)) {
            e.kind = ast::Expr::Kind::kLiteral;
            e.literal = value(lit->value());
        }
        return e;
    }

    ast::Arg arg(PipelineParser::ArgContext* ctx) {
        ast::Arg a;
        a.span = span(ctx);
        if (auto* named = dynamic_cast<PipelineParser::NamedArgContext*>(ctx)) {
            a.name = named->IDENT()->getText();
            a.name_span = span(named->IDENT()->getSymbol());
            a.value = value(named->value());
        } else if (auto* pos = dynamic_cast<PipelineParser::PositionalArgContext*>(ctx)) {
            a.expr = expr(pos->expr());
        }
        return a;
    }

    ast::Value value(PipelineParser::ValueContext* ctx) {
        ast::Value v;
        if (!ctx) return v;
        v.span = span(ctx);
        if (ctx->NUMBER()) {
            v.kind = ast::Value::Kind::kNumber;
            v.number = std::strtod(ctx->NUMBER()->getText().c_str(), nullptr);
            if (ctx->unit()) v.unit = ctx->unit()->getText();
        } else if (ctx->STRING()) {
            v.kind = ast::Value::Kind::kString;
            std::string t = ctx->STRING()->getText();
            v.text = t.size() >= 2 ? t.substr(1, t.size() - 2) : "";
            v.text_span = {&file_, v.span.begin + 1, v.span.end - 1};
        } else if (ctx->TRUE() || ctx->FALSE()) {
            v.kind = ast::Value::Kind::kBool;
            v.boolean = ctx->TRUE() != nullptr;
        } else {
            v.kind = ast::Value::Kind::kCross;
        }
        return v;
    }

    const SourceFile& file_;
    const detail::DecodedText& text_;
};

// Deeper than any pipeline needs (a real one nests about six: pipeline, section, calls), and
// shallow enough that ANTLR's recursive descent and every pass after it keep to the stack.
constexpr int kMaxPipelineNesting = 64;

// E213 before parsing: ~8,000 nested `preselective {` or ~10,000 nested `blur(` overflowed the
// stack. Strings and comments are single tokens, so their brackets do not count.
bool nesting_within_limit(const SourceFile& file, const detail::DecodedText& text, antlr4::CommonTokenStream& tokens,
                          DiagnosticSink& sink) {
    tokens.fill();
    int depth = 0;
    for (antlr4::Token* t : tokens.getTokens()) {
        const std::string s = t->getText();
        if (s == "{" || s == "(" || s == "[") {
            if (++depth > kMaxPipelineNesting) {
                uint32_t begin = text.byte_offsets[t->getStartIndex()];
                sink.report("E213", {&file, begin, begin + 1}, fmt::format("blocks and calls nested more than {} deep", kMaxPipelineNesting))
                    .help = "a pipeline needs only a few levels: define maps by name and use them";
                return false;
            }
        } else if ((s == "}" || s == ")" || s == "]") && depth > 0) {
            --depth;
        }
    }
    return true;
}

}  // namespace

std::optional<ast::File> parse_pipeline_file(const SourceFile& file, DiagnosticSink& sink) {
    size_t errors = sink.error_count();
    try {
        detail::DecodedText text = detail::decode_utf8(file.text(), 0);
        detail::CodePointStream input(text.code_points);
        grammar::PipelineLexer lexer(&input);
        antlr4::CommonTokenStream tokens(&lexer);
        SyntaxErrors listener(file, text, sink);
        lexer.removeErrorListeners();
        lexer.addErrorListener(&listener);
        if (!nesting_within_limit(file, text, tokens, sink)) return std::nullopt;
        listener.bracket_note = unclosed_bracket(file, text, tokens);
        grammar::PipelineParser parser(&tokens);
        parser.removeErrorListeners();
        parser.addErrorListener(&listener);
        auto* tree = parser.file();
        if (sink.error_count() != errors) return std::nullopt;
        return Builder(file, text).file(tree);
    } catch (const std::exception& e) {
        sink.report("E201", {&file, 0, 0}, fmt::format("internal parser failure: {}", e.what()));
    } catch (...) {
        sink.report("E201", {&file, 0, 0}, "internal parser failure");
    }
    return std::nullopt;
}

}  // namespace crex::pipeline
