#include "runtime/scene/radiance/rif.h"

#include <fmt/format.h>

#include <cctype>
#include <cstring>

namespace crex::radiance {
namespace {

// rad's variables crex reads, matched (like rad) by at least their first three letters.
enum class Var { kMaterials, kScene, kIllum, kView, kRender, kOther };

Var variable(const std::string& name) {
    std::string n;
    for (char c : name) n += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    auto is = [&](const char* full) { return n.size() >= 3 && std::string(full).compare(0, n.size(), n) == 0; };
    if (is("materials")) return Var::kMaterials;
    if (is("scene")) return Var::kScene;
    if (is("illum")) return Var::kIllum;
    if (is("render")) return Var::kRender;
    if (n.size() >= 2 && std::string("view").compare(0, n.size(), n) == 0) return Var::kView;
    return Var::kOther;
}

}  // namespace

RifProject read_rif(const SourceFile& rif, DiagnosticSink& sink) {
    const std::string& t = rif.text();
    struct Assignment {
        Var var;
        std::vector<Word> words;
        std::vector<std::vector<uint32_t>> offsets;  // per word, each byte's offset (quoted commands)
    };
    std::vector<Assignment> assignments;
    size_t i = 0;
    while (i < t.size()) {
        // One logical line: continued while it ends in a backslash.
        size_t begin = i;
        std::string line;
        std::vector<uint32_t> at;
        while (i < t.size() && t[i] != '\n') {
            if (t[i] == '\\' && i + 1 < t.size() && t[i + 1] == '\n') {
                line += ' ', at.push_back(static_cast<uint32_t>(i));
                i += 2;
                continue;
            }
            if (t[i] != '\r') line += t[i], at.push_back(static_cast<uint32_t>(i));
            ++i;
        }
        at.push_back(static_cast<uint32_t>(i));
        ++i;
        size_t k = 0;
        while (k < line.size() && std::isspace(static_cast<unsigned char>(line[k]))) ++k;
        if (k >= line.size() || line[k] == '#') continue;
        size_t eq = line.find('=');
        if (eq == std::string::npos) {
            sink.report("W301", {&rif, static_cast<uint32_t>(begin), at[line.size()]}, "a .rif line without 'variable = value' is ignored");
            continue;
        }
        std::string name = line.substr(k, eq - k);
        while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
        Assignment a{variable(name), {}, {}};
        // Words of the value: blanks separate them; "..." holds a word with blanks (a command).
        for (size_t j = eq + 1; j < line.size();) {
            if (std::isspace(static_cast<unsigned char>(line[j]))) {
                ++j;
                continue;
            }
            Word w;
            std::vector<uint32_t> offs;
            size_t b = j;
            if (line[j] == '"' || line[j] == '\'') {
                const char q = line[j];
                size_t close = line.find(q, j + 1);
                if (close == std::string::npos) {
                    sink.report("E301", {&rif, at[j], at[j] + 1}, "this quote is never closed");
                    break;
                }
                w.text = line.substr(j + 1, close - j - 1);
                for (size_t c = j + 1; c < close; ++c) offs.push_back(at[c]);
                offs.push_back(at[close]);
                j = close + 1;
            } else {
                while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
                w.text = line.substr(b, j - b);
                for (size_t c = b; c < j; ++c) offs.push_back(at[c]);
                offs.push_back(at[j]);
            }
            w.span = {&rif, at[b], at[j]};
            a.words.push_back(std::move(w));
            a.offsets.push_back(std::move(offs));
        }
        assignments.push_back(std::move(a));
    }
    RifProject project;
    for (Var v : {Var::kMaterials, Var::kScene, Var::kIllum})
        for (const Assignment& a : assignments) {
            if (a.var != v) continue;
            for (size_t w = 0; w < a.words.size(); ++w) {
                RifInput in;
                if (!a.words[w].text.empty() && a.words[w].text[0] == '!') {
                    in.is_command = true;
                    in.command.text = a.words[w].text.substr(1);
                    in.command.offsets.assign(a.offsets[w].begin() + 1, a.offsets[w].end());
                    in.command.span = a.words[w].span;
                } else {
                    in.file = a.words[w];
                }
                project.inputs.push_back(std::move(in));
            }
        }
    // -bv as RADIANCE's check_bool reads it: bare toggles; + y t 1 on; - n f 0 off. Every
    // render line, in order (rad joins them).
    for (const Assignment& a : assignments) {
        if (a.var != Var::kRender) continue;
        for (const Word& w : a.words) {
            if (w.text.compare(0, 3, "-bv") != 0 || w.text.size() > 4) continue;
            const char c = w.text.size() == 3 ? '\0' : w.text[3];
            if (c == '\0') project.back_faces_visible = !project.back_faces_visible;
            else if (std::strchr("+yYtT1", c)) project.back_faces_visible = true;
            else if (std::strchr("-nNfF0", c)) project.back_faces_visible = false;
        }
    }
    for (const Assignment& a : assignments) {
        if (a.var != Var::kView || a.words.empty()) continue;
        size_t first = 0;
        if (a.words[0].text[0] != '-') project.view_name = a.words[0].text, first = 1;
        for (size_t w = first; w < a.words.size(); ++w) project.view.push_back({a.words[w].text, a.words[w].span.begin, a.words[w].span.end});
        if (project.view.empty()) project.view_name.clear();
        break;  // rad's default view is the first
    }
    return project;
}

}  // namespace crex::radiance
