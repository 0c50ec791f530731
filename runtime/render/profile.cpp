#include "runtime/render/profile.h"

#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include <cmath>

#include "base/json_positions.h"
#include "base/number_range.h"
#include "base/render_text.h"

namespace crex {

std::string Profile::to_json_text() const {
    nlohmann::json j;
    j["format"] = "crex-profile";
    j["version"] = 1;
    j["seconds_per_ray"] = nlohmann::json::object();
    if (camera_.cost) j["seconds_per_ray"]["camera"] = *camera_.cost;
    for (const auto& row : kComponentTable)
        if (auto c = cost(row.component)) j["seconds_per_ray"][std::string(1, row.letter)] = *c;
    return j.dump(2) + "\n";
}

std::string Profile::from_json_text(const std::string& text, Profile& out, double* full_render_seconds, const std::string& name,
                                    StageCosts* stages) {
    const SourceFile file(name, text);
    auto at = [&](const SourceSpan& span, const std::string& what) { return format_location(span) + ": " + what; };
    if (text.find_first_not_of(" \t\r\n") == std::string::npos)
        return at({&file, 0, 0}, "the file is empty: expected a crex profile, the JSON object 'crex run --save-profile' writes");
    PositionedJson doc;
    DiagnosticSink sink;
    if (!parse_json_with_positions(file, doc, sink, "E401")) {
        const Diagnostic d = sink.sorted().front();
        return at(d.span, d.message);
    }
    const nlohmann::json& j = doc.value;
    if (!j.is_object()) return at(doc.span(""), "expected a crex profile, the JSON object 'crex run --save-profile' writes");
    // Types checked before values are read: json::value() throws on a field of another type
    // (a numeric "format" ended crex run as an internal error; found by profile_fuzzer).
    auto field = [&](const char* key) { return j.contains(key) ? &j.at(key) : nullptr; };
    const auto* format = field("format");
    if (!format || !format->is_string() || format->get<std::string>() != "crex-profile")
        return at(format ? doc.span("/format") : doc.span(""), "not a crex profile (\"format\": \"crex-profile\" missing)");
    const auto* version = field("version");
    if (!version || !version->is_number_integer() || version->get<int64_t>() != 1)
        return at(version ? doc.span("/version") : doc.span(""), "unsupported profile version: this crex reads version 1");
    auto number = [&](const std::string& pointer, const nlohmann::json& value, const NumberRange& range, double& v) -> std::string {
        const std::string what = readable_json_path(pointer);
        if (!value.is_number()) return at(doc.span(pointer), fmt::format("{}: expected {}, but this is {}", what, describe(range), value.type_name()));
        v = value.get<double>();
        if (std::string e = number_range_error(v, range); !e.empty()) return at(doc.span(pointer), what + ": " + e);
        return "";
    };
    double full = 0;
    if (const auto* f = field("full_render_seconds"))
        if (std::string e = number("/full_render_seconds", *f, {0, kMaxFullRenderSeconds, false}, full); !e.empty()) return e;
    const auto* s = field("seconds_per_ray");
    if (s && !s->is_object()) return at(doc.span("/seconds_per_ray"), "seconds_per_ray: expected an object of seconds per ray by component");
    Profile p;
    if (s)
        for (const auto& [key, value] : s->items()) {
            const std::string pointer = "/seconds_per_ray/" + escape_pointer_token(key);
            double v = 0;
            if (std::string e = number(pointer, value, {0, kMaxSecondsPerRay, false}, v); !e.empty()) return e;
            if (key == "camera") {
                load(p.camera_, v);
                continue;
            }
            auto c = key.size() == 1 ? component_from_letter(key[0]) : std::nullopt;
            if (!c) return at(doc.key_span(pointer), "seconds_per_ray: unknown component '" + key + "': expected camera, D, G, S, T, R or M");
            load(p.cost_[static_cast<size_t>(*c)], v);
        }
    StageCosts st;
    if (const auto* g = field("stages")) {
        if (!g->is_object()) return at(doc.span("/stages"), "stages: expected an object of the pipeline's stage costs");
        auto stage = [&](const char* key, double& v, const NumberRange& range) -> std::string {
            if (!g->contains(key)) return "";
            return number(std::string("/stages/") + key, g->at(key), range, v);
        };
        const NumberRange seconds{0, kMaxFullRenderSeconds, false}, count{0, 1e15, true};
        double samples = 0, pixels = 0, records = 0;
        for (const std::string& e : {stage("preview_seconds", st.preview_seconds, seconds), stage("preview_samples", samples, count),
                                     stage("guidance_seconds", st.guidance_seconds, seconds), stage("pixels", pixels, count),
                                     stage("preview_fixed_seconds", st.preview_fixed_seconds, seconds),
                                     stage("preview_records", records, count),
                                     stage("preview_record_seconds", st.preview_record_seconds, seconds),
                                     stage("end_seconds", st.end_seconds, seconds),
                                     stage("strided_preview_seconds", st.strided_preview_seconds, seconds)})
            if (!e.empty()) return e;
        st.preview_samples = static_cast<uint64_t>(samples);
        st.pixels = static_cast<uint64_t>(pixels);
        st.preview_records = static_cast<uint64_t>(records);
    }
    out = p;
    if (full_render_seconds) *full_render_seconds = full;
    if (stages) *stages = st;
    return "";
}

}  // namespace crex
