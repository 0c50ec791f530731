#include "runtime/render/profile.h"

#include <nlohmann/json.hpp>

namespace crex {

std::string Profile::to_json_text() const {
    nlohmann::json j;
    j["format"] = "crex-profile";
    j["version"] = 1;
    j["seconds_per_ray"] = nlohmann::json::object();
    if (camera_) j["seconds_per_ray"]["camera"] = *camera_;
    for (const auto& row : kComponentTable)
        if (auto c = cost(row.component)) j["seconds_per_ray"][std::string(1, row.letter)] = *c;
    return j.dump(2) + "\n";
}

std::string Profile::from_json_text(const std::string& text, Profile& out) {
    nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return "not a JSON object";
    if (j.value("format", "") != "crex-profile") return "not a crex profile (\"format\": \"crex-profile\" missing)";
    if (j.value("version", 0) != 1) return "unsupported profile version";
    const auto& s = j.value("seconds_per_ray", nlohmann::json::object());
    Profile p;
    for (const auto& [key, value] : s.items()) {
        if (!value.is_number() || !(value.get<double>() >= 0)) return "seconds_per_ray." + key + ": expected a number >= 0";
        double v = value.get<double>();
        if (key == "camera") {
            p.camera_ = v;
            continue;
        }
        auto c = key.size() == 1 ? component_from_letter(key[0]) : std::nullopt;
        if (!c) return "seconds_per_ray: unknown component '" + key + "'";
        p.cost_[static_cast<size_t>(*c)] = v;
    }
    out = p;
    return "";
}

}  // namespace crex
