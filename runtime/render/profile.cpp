#include "runtime/render/profile.h"

#include <nlohmann/json.hpp>

#include <cmath>

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

std::string Profile::from_json_text(const std::string& text, Profile& out) {
    nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return "not a JSON object";
    // Types checked before values are read: json::value() throws on a field of another type
    // (a numeric "format" ended crex run as an internal error; found by profile_fuzzer).
    auto field = [&](const char* key) { return j.contains(key) ? &j.at(key) : nullptr; };
    const auto* format = field("format");
    if (!format || !format->is_string() || format->get<std::string>() != "crex-profile")
        return "not a crex profile (\"format\": \"crex-profile\" missing)";
    const auto* version = field("version");
    if (!version || !version->is_number_integer() || version->get<int64_t>() != 1) return "unsupported profile version";
    const auto* s = field("seconds_per_ray");
    if (s && !s->is_object()) return "seconds_per_ray: expected an object of seconds per ray by component";
    Profile p;
    if (s)
        for (const auto& [key, value] : s->items()) {
            if (!value.is_number() || !(value.get<double>() >= 0) || !std::isfinite(value.get<double>()))
                return "seconds_per_ray." + key + ": expected a finite number >= 0";
            double v = value.get<double>();
            if (key == "camera") {
                load(p.camera_, v);
                continue;
            }
            auto c = key.size() == 1 ? component_from_letter(key[0]) : std::nullopt;
            if (!c) return "seconds_per_ray: unknown component '" + key + "'";
            load(p.cost_[static_cast<size_t>(*c)], v);
        }
    out = p;
    return "";
}

}  // namespace crex
