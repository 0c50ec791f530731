#include "runtime/scene/json_fields.h"

#include <fmt/format.h>

#include "base/nearest_name.h"

namespace crex {

using nlohmann::json;

std::string json_type_name(const json& v) {
    if (v.is_number()) return "a number";
    if (v.is_string()) return "a string";
    if (v.is_boolean()) return "a boolean";
    if (v.is_array()) return "an array";
    if (v.is_object()) return "an object";
    return "null";
}

std::string json_shown(const json& v) {
    std::string s = v.dump(-1, ' ', false, json::error_handler_t::replace);
    return s.size() > 40 ? s.substr(0, 37) + "..." : s;
}

std::string Range::text() const {
    if (std::isinf(lo) && std::isinf(hi)) return "";
    if (std::isinf(hi)) return fmt::format(" {} {:g}", lo_open ? ">" : ">=", lo);
    return fmt::format(" in {}{:g}, {:g}{}", lo_open ? "(" : "[", lo, hi, hi_open ? ")" : "]");
}

void ObjectReader::missing(const std::string& key, const std::string& what) {
    sink_.report("E304", doc_.span(pointer_), fmt::format("{}: missing required field '{}' ({})",
                                                           readable_json_path(pointer_), key, what));
}

void ObjectReader::wrong(const std::string& key, const std::string& expected) {
    sink_.report("E302", span(key), fmt::format("{}: expected {}, got {}", path(key), expected, json_type_name(at(key))));
}

bool ObjectReader::number(const std::string& key, double& out, const Range& r, bool required) {
    if (!has(key)) {
        if (required) missing(key, "a number");
        return false;
    }
    const json& v = at(key);
    if (!v.is_number()) {
        wrong(key, "a number" + r.text());
        return false;
    }
    double x = v.get<double>();
    if (!std::isfinite(x) || !r.contains(x)) {
        sink_.report("E303", span(key), fmt::format("{}: expected a number{}, got {}", path(key), r.text(), json_shown(v)));
        return false;
    }
    out = x;
    return true;
}

bool ObjectReader::integer(const std::string& key, int& out, int lo, int hi) {
    if (!has(key)) return false;
    const json& v = at(key);
    if (!v.is_number_integer()) {
        wrong(key, fmt::format("an integer in {} .. {}", lo, hi));
        return false;
    }
    auto x = v.get<int64_t>();
    if (x < lo || x > hi) {
        sink_.report("E303", span(key), fmt::format("{}: expected an integer in {} .. {}, got {}", path(key), lo, hi, x));
        return false;
    }
    out = static_cast<int>(x);
    return true;
}

bool ObjectReader::boolean(const std::string& key, bool& out) {
    if (!has(key)) return false;
    if (!at(key).is_boolean()) {
        wrong(key, "true or false");
        return false;
    }
    out = at(key).get<bool>();
    return true;
}

bool ObjectReader::string(const std::string& key, std::string& out, bool required) {
    if (!has(key)) {
        if (required) missing(key, "a string");
        return false;
    }
    if (!at(key).is_string()) {
        wrong(key, "a string");
        return false;
    }
    out = at(key).get<std::string>();
    return true;
}

void ObjectReader::format_and_version(std::string_view format) {
    std::string given;
    if (string("format", given) && given != format)
        sink_.report("E303", span("format"), fmt::format("format: expected \"{}\", got \"{}\"", format, given));
    int version = 1;
    if (integer("version", version, 1, 1000) && version != 1)
        sink_.report("E303", span("version"), fmt::format("version: this crex reads version 1, the file is version {}", version));
}

bool ObjectReader::vec3_of(const json& v, Vec3& out) {
    if (!v.is_array() || v.size() != 3) return false;
    for (const auto& e : v)
        if (!e.is_number()) return false;
    out = {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
    return true;
}

bool ObjectReader::vec3(const std::string& key, Vec3& out, const Range& r, bool required) {
    if (!has(key)) {
        if (required) missing(key, "an array of 3 numbers");
        return false;
    }
    Vec3 v;
    if (!vec3_of(at(key), v)) {
        sink_.report("E302", span(key), fmt::format("{}: expected an array of 3 numbers, got {}", path(key), json_shown(at(key))));
        return false;
    }
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(v[i]) || !r.contains(v[i])) {
            sink_.report("E303", doc_.span(pointer_ + "/" + key + "/" + std::to_string(i)),
                         fmt::format("{}[{}]: expected a number{}, got {}", path(key), i, r.text(), json_shown(at(key)[static_cast<size_t>(i)])));
            return false;
        }
    }
    out = v;
    return true;
}

bool ObjectReader::vec3_list(const std::string& key, std::vector<Vec3>& out, bool required) {
    if (!has(key)) {
        if (required) missing(key, "an array of points");
        return false;
    }
    if (!at(key).is_array()) {
        wrong(key, "an array of points [x, y, z]");
        return false;
    }
    out.clear();
    for (size_t i = 0; i < at(key).size(); ++i) {
        Vec3 v;
        const json& e = at(key)[i];
        std::string ptr = pointer_ + "/" + key + "/" + std::to_string(i);
        if (!vec3_of(e, v)) {
            sink_.report("E302", doc_.span(ptr), fmt::format("{}: expected [x, y, z], got {}", readable_json_path(ptr), json_shown(e)));
            return false;
        }
        if (!is_finite(v)) {
            sink_.report("E303", doc_.span(ptr), fmt::format("{}: non-finite coordinate", readable_json_path(ptr)));
            return false;
        }
        out.push_back(v);
    }
    return true;
}

void ObjectReader::warn_unknown(std::initializer_list<std::string_view> known) {
    for (const auto& [key, value] : obj_.items()) {
        bool found = false;
        for (auto k : known) found = found || k == key;
        if (found) continue;
        std::string help = did_you_mean(key, std::vector<std::string>(known.begin(), known.end()));
        Diagnostic& d = sink_.report("W301", doc_.key_span(pointer_ + "/" + escape_pointer_token(key)),
                                     fmt::format("{}: unknown field '{}' is ignored", readable_json_path(pointer_), key));
        d.help = help;
    }
}

}  // namespace crex
