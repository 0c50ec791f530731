#include "runtime/scene/radiance/command_line.h"

#include <fmt/format.h>

#include <cctype>

namespace crex::radiance {

std::vector<std::string> texts(const CommandWords& words, size_t first) {
    std::vector<std::string> out;
    for (size_t i = first; i < words.size(); ++i) out.push_back(words[i].text);
    return out;
}

bool split_command_line(const Command& c, std::vector<CommandWords>& stages, DiagnosticSink& sink) {
    const std::string& t = c.text;
    const SourceFile* file = c.span.file;
    auto span = [&](size_t b, size_t e) {
        return SourceSpan{file, c.offsets[std::min(b, c.offsets.size() - 1)], c.offsets[std::min(e, c.offsets.size() - 1)]};
    };
    auto refuse = [&](size_t at, const std::string& what) {
        sink.report("E307", span(at, at + 1), fmt::format("{} in a '!' command needs a shell, and crex runs none", what))
            .help = "crex carries out xform, genbox, genprism, genrev and gensky itself, alone or piped into "
                    "xform; write the other commands' output into a file and read that";
        return false;
    };
    stages.assign(1, {});
    size_t i = 0;
    while (i < t.size()) {
        const char ch = t[i];
        if (std::isspace(static_cast<unsigned char>(ch))) {
            ++i;
            continue;
        }
        if (ch == '|') {
            if (i + 1 < t.size() && t[i + 1] == '|') return refuse(i, "'||'");
            if (stages.back().empty()) {
                sink.report("E301", span(i, i + 1), "'|' with no command before it");
                return false;
            }
            stages.emplace_back();
            ++i;
            continue;
        }
        if (ch == ';' || ch == '&' || ch == '<' || ch == '>' || ch == '`' || ch == '(' || ch == ')')
            return refuse(i, fmt::format("'{}'", ch));
        Word w;
        const size_t begin = i;
        while (i < t.size() && !std::isspace(static_cast<unsigned char>(t[i])) && t[i] != '|') {
            const char d = t[i];
            if (d == ';' || d == '&' || d == '<' || d == '>' || d == '`') return refuse(i, fmt::format("'{}'", d));
            if (d == '$') return refuse(i, "a '$' expansion");
            if (d == '(' || d == ')') return refuse(i, fmt::format("an unquoted '{}' (quote the expression)", d));
            // An unquoted * ? [ stays itself when it matches no file, as a shell leaves it.
            if (d == '\'') {
                size_t close = t.find('\'', i + 1);
                if (close == std::string::npos) {
                    sink.report("E301", span(i, i + 1), "this quote (') is never closed");
                    return false;
                }
                w.text += t.substr(i + 1, close - i - 1);
                i = close + 1;
            } else if (d == '"') {
                size_t k = i + 1;
                for (; k < t.size() && t[k] != '"'; ++k) {
                    if (t[k] == '$' || t[k] == '`') return refuse(k, t[k] == '$' ? "a '$' expansion" : "'`'");
                    if (t[k] == '\\' && k + 1 < t.size() && (t[k + 1] == '"' || t[k + 1] == '\\')) ++k;
                    w.text += t[k];
                }
                if (k >= t.size()) {
                    sink.report("E301", span(i, i + 1), "this quote (\") is never closed");
                    return false;
                }
                i = k + 1;
            } else if (d == '\\' && i + 1 < t.size()) {
                w.text += t[i + 1];
                i += 2;
            } else {
                w.text += d;
                ++i;
            }
        }
        w.span = span(begin, i);
        stages.back().push_back(std::move(w));
    }
    if (stages.back().empty()) {
        sink.report("E301", c.span, stages.size() == 1 ? "an empty '!' command" : "'|' with no command after it");
        return false;
    }
    return true;
}

}  // namespace crex::radiance
