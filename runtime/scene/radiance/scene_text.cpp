#include "runtime/scene/radiance/scene_text.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <cstdlib>

namespace crex::radiance {
namespace {

bool is_space(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

// A counted list longer than this is not a scene a person wrote: a corrupt count (or a fuzzer)
// must not make us reserve gigabytes before the file runs out.
constexpr long kMaxArguments = 100000000;

class TextReader {
public:
    TextReader(const SourceFile& file, DiagnosticSink& sink) : file_(file), text_(file.text()), sink_(sink) {}

    std::vector<Item> read() {
        std::vector<Item> items;
        while (true) {
            skip_space();
            if (pos_ >= text_.size()) break;
            char c = text_[pos_];
            if (c == '#') {
                size_t end = line_end(pos_);
                if (text_.compare(pos_, 6, "#@crex") == 0)
                    items.emplace_back(Directive{text_.substr(pos_, end - pos_), span(pos_, end)});
                pos_ = end;
            } else if (c == '!') {
                items.emplace_back(read_command());
            } else {
                Primitive p;
                Outcome o = read_primitive(p);
                if (o == Outcome::kOk) items.emplace_back(std::move(p));
                if (o == Outcome::kLost) break;
            }
        }
        return items;
    }

private:
    enum class Outcome { kOk, kDropped, kLost };

    SourceSpan span(size_t b, size_t e) const { return {&file_, static_cast<uint32_t>(b), static_cast<uint32_t>(e)}; }
    SourceSpan at_end() const { return span(text_.size(), text_.size()); }

    void skip_space() {
        while (pos_ < text_.size() && is_space(text_[pos_])) ++pos_;
    }
    size_t line_end(size_t from) const {
        size_t e = text_.find('\n', from);
        return e == std::string::npos ? text_.size() : e;
    }

    // `!command`, continued while a line ends in a backslash (the shell removes both the
    // backslash and the newline; so do we).
    Command read_command() {
        Command c;
        size_t begin = pos_++;
        while (pos_ < text_.size()) {
            char ch = text_[pos_];
            if (ch == '\\' && pos_ + 1 < text_.size() && (text_[pos_ + 1] == '\n' || text_[pos_ + 1] == '\r')) {
                pos_ += text_[pos_ + 1] == '\r' && pos_ + 2 < text_.size() && text_[pos_ + 2] == '\n' ? 3 : 2;
                continue;
            }
            if (ch == '\n') break;
            if (ch != '\r') {
                c.text.push_back(ch);
                c.offsets.push_back(static_cast<uint32_t>(pos_));
            }
            ++pos_;
        }
        c.offsets.push_back(static_cast<uint32_t>(pos_));  // one past the end
        c.span = span(begin, pos_);
        return c;
    }

    // One word, quoted or not (RADIANCE's fgetword): false at the end of the file.
    bool word(Word& w) {
        skip_space();
        if (pos_ >= text_.size()) return false;
        size_t begin = pos_;
        char q = text_[pos_];
        if (q == '"' || q == '\'') {
            size_t close = text_.find(q, pos_ + 1);
            if (close == std::string::npos) {
                sink_.report("E301", span(begin, begin + 1), fmt::format("this quote ({}) is never closed", q))
                    .help = "a quoted word ends at the next matching quote, on any line";
                pos_ = text_.size();
                unclosed_quote_ = true;
                return false;
            }
            w.text = text_.substr(pos_ + 1, close - pos_ - 1);
            pos_ = close + 1;
            w.span = span(begin, pos_);
            return true;
        }
        while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
        w.text = text_.substr(begin, pos_ - begin);
        w.span = span(begin, pos_);
        return true;
    }

    bool need_word(Word& w, const Primitive& p, const char* what) {
        if (word(w)) return true;
        if (!unclosed_quote_)
            sink_.report("E301", at_end(), fmt::format("the file ends inside primitive '{}': {} is missing", p.id.text.empty() ? p.modifier.text : p.id.text, what))
                .help = "a primitive is 'modifier type identifier', then its string, integer and real arguments, each list "
                        "starting with its count";
        return false;
    }

    bool count(const Primitive& p, const char* what, long& n) {
        Word w;
        if (!need_word(w, p, fmt::format("the number of {} arguments", what).c_str())) return false;
        char* end = nullptr;
        n = std::strtol(w.text.c_str(), &end, 10);
        if (w.text.empty() || end != w.text.c_str() + w.text.size() || n < 0 || n > kMaxArguments) {
            sink_.report("E302", w.span, fmt::format("{} '{}': expected the number of {} arguments, got '{}'", p.type.text,
                                                     p.id.text, what, w.text))
                .help = "each argument list starts with how many arguments follow (0 if none)";
            return false;
        }
        return true;
    }

    Outcome read_primitive(Primitive& p) {
        size_t begin = pos_;
        if (!word(p.modifier)) return Outcome::kLost;
        if (!need_word(p.type, p, "its type") || !need_word(p.id, p, "its identifier")) return Outcome::kLost;
        if (p.is_alias()) {
            if (!need_word(p.alias_of, p, "the primitive it is an alias of")) return Outcome::kLost;
            p.span = span(begin, pos_);
            return Outcome::kOk;
        }
        long n = 0;
        if (!count(p, "string", n)) return Outcome::kLost;
        for (long k = 0; k < n; ++k) {
            Word w;
            if (!need_word(w, p, fmt::format("string argument {} of {}", k + 1, n).c_str())) return Outcome::kLost;
            p.strings.push_back(std::move(w));
        }
        if (!count(p, "integer", n)) return Outcome::kLost;
        for (long k = 0; k < n; ++k) {  // no RADIANCE primitive takes any: read and ignore
            Word w;
            if (!need_word(w, p, "an integer argument")) return Outcome::kLost;
        }
        if (!count(p, "real", n)) return Outcome::kLost;
        bool ok = true;
        for (long k = 0; k < n; ++k) {
            Word w;
            if (!need_word(w, p, fmt::format("real argument {} of {}", k + 1, n).c_str())) return Outcome::kLost;
            double x = 0;
            if (!parse_real(w.text, x)) {
                char* end = nullptr;
                const bool number = !w.text.empty() && (std::strtod(w.text.c_str(), &end), end == w.text.c_str() + w.text.size());
                if (ok)
                    sink_.report(number ? "E303" : "E302", w.span,
                                 fmt::format("{} '{}': expected a {} number, got '{}'", p.type.text, p.id.text, number ? "finite" : "real", w.text));
                ok = false;
            }
            p.reals.push_back(x);
            p.real_spans.push_back(w.span);
        }
        p.span = span(begin, pos_);
        return ok ? Outcome::kOk : Outcome::kDropped;
    }

    const SourceFile& file_;
    const std::string& text_;
    DiagnosticSink& sink_;
    size_t pos_ = 0;
    bool unclosed_quote_ = false;
};

}  // namespace

SourceSpan Primitive::reals_span(size_t first, size_t last) const {
    if (real_spans.empty() || first >= real_spans.size()) return span;
    last = std::min(last, real_spans.size() - 1);
    return real_spans[first].merge(real_spans[last]);
}

bool parse_real(const std::string& text, double& out) {
    if (text.empty()) return false;
    char* end = nullptr;
    out = std::strtod(text.c_str(), &end);
    return end == text.c_str() + text.size() && std::isfinite(out);
}

std::vector<Item> read_scene_text(const SourceFile& file, DiagnosticSink& sink) { return TextReader(file, sink).read(); }

}  // namespace crex::radiance
