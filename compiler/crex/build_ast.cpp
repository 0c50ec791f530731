// ANTLR parse tree -> ast::Crex. The grammar is permissive (see grammar/Crex.g4), so this is
// where stray repeats (E008), bad characters and unknown letters (E001) and missing, mismatched
// or unmatched brackets (E002) are reported, in crex's own words, without stopping.
#include <fmt/format.h>

#include <limits>

#include "CrexParser.h"
#include "compiler/crex/parse_internal.h"

namespace crex::detail {
namespace {

using grammar::CrexParser;

constexpr std::string_view kAllowed =
    "a crex uses the components {}, the brackets ( ) < > {{ }} [ ], '*' and integers";

class AstBuilder {
public:
    AstBuilder(const SourceFile& file, const DecodedText& text, uint32_t end, DiagnosticSink& sink)
        : file_(file), text_(text), end_(end), sink_(sink) {}

    ast::Crex build(CrexParser::CrexContext* ctx, uint32_t begin) {
        ast::Crex crex;
        crex.span = {&file_, begin, end_};
        for (auto* child : ctx->children) {
            if (auto* seq = dynamic_cast<CrexParser::SequenceContext*>(child)) {
                build_sequence(seq, crex.body);
            } else if (auto* stray = dynamic_cast<CrexParser::StrayCloseContext*>(child)) {
                report_unmatched_closer(stray->CLOSE()->getSymbol());
            }
        }
        return crex;
    }

private:
    SourceSpan span_of(antlr4::Token* t) const {
        size_t a = t->getStartIndex();
        size_t b = t->getStopIndex() + 1;
        return {&file_, text_.byte_offsets.at(a), text_.byte_offsets.at(b)};
    }
    SourceSpan span_of(antlr4::ParserRuleContext* ctx) const {
        SourceSpan a = span_of(ctx->getStart());
        antlr4::Token* stop = ctx->getStop();
        if (!stop || stop->getType() == antlr4::Token::EOF || stop->getStopIndex() < ctx->getStart()->getStartIndex())
            return a;
        return a.merge(span_of(stop));
    }
    char32_t code_point(antlr4::Token* t) const { return text_.code_points.at(t->getStartIndex()); }

    void build_sequence(CrexParser::SequenceContext* ctx, ast::Sequence& out) {
        for (auto* stray : ctx->strayRepeat()) {
            auto* r = stray->repeat();
            sink_.report("E008", span_of(r), fmt::format("repeat '{}' with nothing before it", r->getText()))
                .help = "a repeat applies to the component or group right before it, as in 'D*' or '(DG)2'";
        }
        for (auto* item : ctx->item()) {
            ast::Item built = build_atom(item->atom());
            for (auto* r : item->repeat()) built.repeats.push_back(build_repeat(r));
            out.push_back(std::move(built));
        }
    }

    ast::Repeat build_repeat(CrexParser::RepeatContext* ctx) {
        ast::Repeat r;
        r.span = span_of(ctx);
        if (ctx->STAR()) {
            r.star = true;
            return r;
        }
        // Saturating decimal parse: the checker (E003) needs to know only "too large".
        uint64_t value = 0;
        for (char c : ctx->getText()) {
            uint64_t digit = static_cast<uint64_t>(c - '0');
            if (value > (std::numeric_limits<uint64_t>::max() - digit) / 10) {
                value = std::numeric_limits<uint64_t>::max();
                break;
            }
            value = value * 10 + digit;
        }
        r.count = value;
        return r;
    }

    ast::Item build_atom(CrexParser::AtomContext* ctx) {
        ast::Item item;
        item.span = span_of(ctx);
        if (auto* letter = dynamic_cast<CrexParser::LetterContext*>(ctx)) {
            char c = static_cast<char>(code_point(letter->LETTER()->getSymbol()));
            if (auto comp = component_from_letter(c)) {
                item.kind = ast::ItemKind::kComponent;
                item.component = *comp;
            } else {
                report_bad_char(letter->LETTER()->getSymbol());
            }
            return item;
        }
        if (auto* bad = dynamic_cast<CrexParser::BadCharContext*>(ctx)) {
            report_bad_char(bad->BAD_CHAR()->getSymbol());
            return item;
        }
        auto* group = dynamic_cast<CrexParser::GroupContext*>(ctx);
        antlr4::Token* open = group->OPEN()->getSymbol();
        item.kind = ast::ItemKind::kGroup;
        item.open_span = span_of(open);
        switch (code_point(open)) {
        case '(': item.group = ast::GroupKind::kInherit; break;
        case '<': item.group = ast::GroupKind::kDefer; break;
        case '{': item.group = ast::GroupKind::kModulate; break;
        default: item.group = ast::GroupKind::kBudget; break;
        }
        build_sequence(group->sequence(), item.body);
        check_closer(item, group);
        return item;
    }

    void check_closer(ast::Item& item, CrexParser::GroupContext* group) {
        char open = ast::group_open_char(item.group);
        char want = ast::group_close_char(item.group);
        DiagnosticNote opener{item.open_span, fmt::format("the {} opens here", ast::group_kind_name(item.group))};
        if (!group->CLOSE()) {
            item.closed = false;
            // Point just past the group's last token: that is where the closer belongs.
            uint32_t at = item.span.end;
            Diagnostic& d = sink_.report("E002", {&file_, at, at},
                                         fmt::format("'{}' is never closed: expected '{}'", open, want));
            d.notes.push_back(opener);
            d.help = fmt::format("add '{}' where the group should end", want);
            return;
        }
        antlr4::Token* close = group->CLOSE()->getSymbol();
        char got = static_cast<char>(code_point(close));
        if (got != want) {
            item.closed = false;
            Diagnostic& d = sink_.report("E002", span_of(close),
                                         fmt::format("expected '{}' to close '{}', found '{}'", want, open, got));
            d.notes.push_back(opener);
        }
    }

    void report_unmatched_closer(antlr4::Token* t) {
        char c = static_cast<char>(code_point(t));
        sink_.report("E002", span_of(t), fmt::format("unmatched '{}': no group is open here", c))
            .help = "remove it, or add the matching opening bracket";
    }

    void report_bad_char(antlr4::Token* t) {
        SourceSpan span = span_of(t);
        char32_t c = code_point(t);
        std::string what;
        if (c == 0xFFFD && span.text() != "\xEF\xBF\xBD") {
            what = fmt::format("invalid UTF-8 byte 0x{:02X}",
                               static_cast<unsigned>(static_cast<unsigned char>(span.text()[0])));
        } else if (c < 0x20 || c == 0x7F) {
            what = fmt::format("unexpected character U+{:04X}", static_cast<uint32_t>(c));
        } else {
            what = fmt::format("unexpected character '{}'", span.text());
        }
        Diagnostic& d = sink_.report(
            "E001", span, fmt::format("{}; {}", what, fmt::format(kAllowed, component_letters_spaced())));
        if (c < 0x80 && c >= 'a' && c <= 'z') {
            char upper = static_cast<char>(c - 'a' + 'A');
            if (component_from_letter(upper))
                d.help = fmt::format("components are upper case: write '{}'", upper);
        }
    }

    const SourceFile& file_;
    const DecodedText& text_;
    uint32_t end_;
    DiagnosticSink& sink_;
};

}  // namespace

ast::Crex build_crex_ast(CrexParser& parser, const SourceFile& file, const DecodedText& text,
                         uint32_t begin, uint32_t end, DiagnosticSink& sink) {
    CrexParser::CrexContext* tree = parser.crex();
    return AstBuilder(file, text, end, sink).build(tree, begin);
}

}  // namespace crex::detail
