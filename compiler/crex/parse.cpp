#include "compiler/crex/parse.h"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

#include "CrexLexer.h"
#include "CrexParser.h"
#include "antlr4-runtime.h"
#include "compiler/crex/code_point_stream.h"

namespace crex {
namespace detail {

DecodedText decode_utf8(std::string_view text, uint32_t base_offset) {
    DecodedText out;
    out.code_points.reserve(text.size());
    out.byte_offsets.reserve(text.size() + 1);
    size_t i = 0;
    while (i < text.size()) {
        unsigned char c = static_cast<unsigned char>(text[i]);
        size_t len = c < 0x80 ? 1 : (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3
                   : (c & 0xF8) == 0xF0 ? 4 : 0;
        char32_t cp = 0xFFFD;
        if (len == 1) {
            cp = c;
        } else if (len > 1 && i + len <= text.size()) {
            cp = c & (0x7F >> len);
            for (size_t k = 1; k < len && len; ++k) {
                unsigned char cc = static_cast<unsigned char>(text[i + k]);
                if ((cc & 0xC0) != 0x80) {
                    len = 0;
                    break;
                }
                cp = (cp << 6) | (cc & 0x3F);
            }
            // Overlong forms, surrogates and values past U+10FFFF are malformed too.
            static constexpr char32_t kMin[5] = {0, 0, 0x80, 0x800, 0x10000};
            if (len && (cp < kMin[len] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF))) len = 0;
        } else {
            len = 0;
        }
        if (len == 0) {  // one U+FFFD per malformed byte, as render_text displays it
            cp = 0xFFFD;
            len = 1;
        }
        out.code_points.push_back(cp);
        out.byte_offsets.push_back(base_offset + static_cast<uint32_t>(i));
        i += len;
    }
    out.byte_offsets.push_back(base_offset + static_cast<uint32_t>(text.size()));
    return out;
}

namespace {

// The grammar accepts every token sequence, so these fire only on an internal inconsistency;
// they still become located diagnostics rather than text on stdout.
class ErrorListener : public antlr4::BaseErrorListener {
public:
    ErrorListener(const SourceFile& file, const DecodedText& text, DiagnosticSink& sink,
                  const char* code)
        : file_(file), text_(text), sink_(sink), code_(code) {}

    void syntaxError(antlr4::Recognizer*, antlr4::Token* token, size_t, size_t, const std::string& msg,
                     std::exception_ptr) override {
        uint32_t at = text_.byte_offsets.back();
        if (token && token->getStartIndex() < text_.code_points.size())
            at = text_.byte_offsets[token->getStartIndex()];
        sink_.report(code_, {&file_, at, at}, fmt::format("cannot parse the crex here ({})", msg));
    }

private:
    const SourceFile& file_;
    const DecodedText& text_;
    DiagnosticSink& sink_;
    const char* code_;
};

bool is_opener(char32_t c) { return c == '(' || c == '<' || c == '{' || c == '['; }
bool is_closer(char32_t c) { return c == ')' || c == '>' || c == '}' || c == ']'; }

// E010 before parsing: the parser and every pass after it recurse once per nesting level,
// and lowering wraps an item once per repeat after it: `D` and 70,000 stacked '*' lowered to
// a tree 70,000 deep and overflowed the stack (exit 139) in check, plan and run. So the depth
// counted is that of the lowered tree: a group adds a level to the deepest item inside it,
// each repeat a level to the item it follows.
bool nesting_within_limit(const SourceFile& file, const DecodedText& text, DiagnosticSink& sink) {
    struct Level {
        uint32_t deepest = 0;  // of the items closed in this group so far
        uint32_t last = 0;     // of the item repeats now apply to (0: none yet)
    };
    std::vector<Level> open(1);
    auto too_deep = [&](size_t i, std::string what) {
        sink.report("E010", {&file, text.byte_offsets[i], text.byte_offsets[i + 1]},
                    fmt::format("{} nested more than {} deep", what, kMaxCrexNesting))
            .help = "flatten the expression; deeper nesting is never needed, and a '*' after a '*' adds nothing";
        return false;
    };
    for (size_t i = 0; i < text.code_points.size(); ++i) {
        const char32_t c = text.code_points[i];
        Level& here = open.back();
        if (is_opener(c)) {
            if (open.size() > kMaxCrexNesting) return too_deep(i, "groups");
            open.push_back({});
        } else if (is_closer(c)) {
            if (open.size() == 1) continue;  // unmatched: E002 later
            const uint32_t group = open.back().deepest + 1;
            open.pop_back();
            open.back().last = group;
            open.back().deepest = std::max(open.back().deepest, group);
        } else if (c == '*' || (c >= '0' && c <= '9')) {
            if (c != '*' && i > 0 && text.code_points[i - 1] >= '0' && text.code_points[i - 1] <= '9') continue;  // one integer
            if (here.last == 0) continue;  // a stray repeat: E008 later
            here.deepest = std::max(here.deepest, ++here.last);
            if (here.last + open.size() - 1 > kMaxCrexNesting) return too_deep(i, "groups and repeats");
        } else if (c != ' ' && c != '\t' && c != '\r' && c != '\n' && c != '\f' && c != '\v') {
            here.last = 1;  // a letter (or a bad character, E001 later): a leaf
            here.deepest = std::max(here.deepest, uint32_t{1});
        }
    }
    return true;
}

}  // namespace
}  // namespace detail

std::optional<ast::Crex> parse_crex(const SourceFile& file, uint32_t begin, uint32_t end,
                                    DiagnosticSink& sink) {
    if (end - begin > kMaxCrexBytes) {
        sink.report("E011", {&file, begin, begin + 1},
                    fmt::format("crex is {} bytes long; the limit is {}", end - begin, kMaxCrexBytes));
        return std::nullopt;
    }
    std::string_view text = std::string_view(file.text()).substr(begin, end - begin);
    detail::DecodedText decoded = detail::decode_utf8(text, begin);
    if (!detail::nesting_within_limit(file, decoded, sink)) return std::nullopt;

    try {
        detail::CodePointStream input(decoded.code_points);
        grammar::CrexLexer lexer(&input);
        antlr4::CommonTokenStream tokens(&lexer);
        grammar::CrexParser parser(&tokens);
        // SLL prediction resolves the optional closer greedily after one token; full LL would
        // look ahead to the end of the input at every group (quadratic or worse on nesting).
        parser.getInterpreter<antlr4::atn::ParserATNSimulator>()->setPredictionMode(
            antlr4::atn::PredictionMode::SLL);
        detail::ErrorListener lexer_errors(file, decoded, sink, "E001");
        detail::ErrorListener parser_errors(file, decoded, sink, "E002");
        lexer.removeErrorListeners();
        lexer.addErrorListener(&lexer_errors);
        parser.removeErrorListeners();
        parser.addErrorListener(&parser_errors);
        return detail::build_crex_ast(parser, file, decoded, begin, end, sink);
    } catch (const std::exception& e) {
        sink.report("E001", {&file, begin, begin}, fmt::format("internal parser failure: {}", e.what()));
    } catch (...) {  // the ANTLR runtime has historically thrown C strings
        sink.report("E001", {&file, begin, begin}, "internal parser failure");
    }
    return std::nullopt;
}

std::optional<ast::Crex> parse_crex(const SourceFile& file, DiagnosticSink& sink) {
    return parse_crex(file, 0, static_cast<uint32_t>(file.text().size()), sink);
}

}  // namespace crex
