#include "base/render_json.h"

namespace crex {
namespace {

void put_span(nlohmann::json& j, const SourceSpan& span) {
    if (!span.valid()) {
        j["file"] = nullptr;
        return;
    }
    LineCol b = span.file->position(span.begin);
    LineCol e = span.file->position(span.end);
    j["file"] = span.file->name();
    j["line"] = b.line;
    j["col"] = b.col;
    j["end_line"] = e.line;
    j["end_col"] = e.col;
}

}  // namespace

nlohmann::json to_json(const Diagnostic& d) {
    nlohmann::json j;
    put_span(j, d.span);
    if (!d.span.valid() && !d.where.empty()) j["where"] = d.where;
    j["code"] = d.code;
    j["severity"] = std::string(severity_name(d.severity));
    j["message"] = d.message;
    j["notes"] = nlohmann::json::array();
    for (const auto& n : d.notes) {
        nlohmann::json jn;
        put_span(jn, n.span);
        jn["message"] = n.message;
        j["notes"].push_back(std::move(jn));
    }
    if (!d.help.empty()) j["help"] = d.help;
    return j;
}

nlohmann::json to_json(const std::vector<Diagnostic>& ds) {
    nlohmann::json arr = nlohmann::json::array();
    for (const auto& d : ds) arr.push_back(to_json(d));
    return arr;
}

}  // namespace crex
