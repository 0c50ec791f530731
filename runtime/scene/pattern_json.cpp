#include "runtime/scene/pattern_json.h"

#include <fmt/format.h>

#include <cmath>

#include "runtime/scene/data_table.h"
#include "runtime/scene/text_pattern.h"

namespace crex {
namespace {

constexpr const char* kKinds[] = {"brightfunc", "colorfunc", "brightdata", "colordata", "colorpict", "brighttext", "colortext"};

bool numbers(const nlohmann::json& j, const char* key, std::vector<double>& out, std::string& error) {
    if (!j.contains(key)) return true;
    const nlohmann::json& a = j.at(key);
    if (!a.is_array()) return error = fmt::format("'{}' must be an array of numbers", key), false;
    out.clear();
    for (const auto& v : a) {
        if (!v.is_number() || !std::isfinite(v.get<double>())) return error = fmt::format("'{}' must hold finite numbers only", key), false;
        out.push_back(v.get<double>());
    }
    return true;
}

bool strings(const nlohmann::json& j, const char* key, std::vector<std::string>& out, std::string& error) {
    if (!j.contains(key)) return true;
    const nlohmann::json& a = j.at(key);
    if (!a.is_array()) return error = fmt::format("'{}' must be an array of strings", key), false;
    for (const auto& v : a) {
        if (!v.is_string()) return error = fmt::format("'{}' must hold strings only", key), false;
        out.push_back(v.get<std::string>());
    }
    return true;
}

}  // namespace

nlohmann::json pattern_to_json(const FunctionPattern& p) {
    nlohmann::json j = {{"kind", kKinds[static_cast<int>(p.kind)]}, {"name", p.name}, {"definitions", p.definitions},
                        {"functions", p.functions}, {"args", p.args}, {"to_pattern", p.to_pattern}, {"scale", p.scale}};
    if (!p.coordinates.empty()) j["coordinates"] = p.coordinates;
    if (!p.picture.empty()) j["picture"] = p.picture;
    if (!p.font.empty()) j["font"] = p.font, j["text"] = p.text;
    for (const DataTable& t : p.tables) {
        nlohmann::json tj = {{"values", t.values}};
        for (const DataTable::Axis& a : t.axes) {
            nlohmann::json aj = {{"origin", a.origin}, {"size", a.size}, {"count", a.count}};
            if (!a.points.empty()) aj["points"] = a.points;
            tj["axes"].push_back(aj);
        }
        j["tables"].push_back(tj);
    }
    return j;
}

bool pattern_from_json(const nlohmann::json& j, FunctionPattern& out, std::string& error) {
    if (!j.is_object()) return error = "a pattern must be an object", false;
    FunctionPattern p;
    const std::string kind = j.value("kind", std::string());
    bool known = false;
    for (int k = 0; k < 7; ++k)
        if (kind == kKinds[k]) p.kind = static_cast<FunctionPattern::Kind>(k), known = true;
    if (!known)
        return error = fmt::format("'kind' must be brightfunc, colorfunc, brightdata, colordata, colorpict, brighttext or colortext, got '{}'",
                                   kind), false;
    if (j.contains("name") && j.at("name").is_string()) p.name = j.at("name").get<std::string>();
    if (j.contains("definitions")) {
        if (!j.at("definitions").is_string()) return error = "'definitions' must be a string", false;
        p.definitions = j.at("definitions").get<std::string>();
    }
    if (!strings(j, "functions", p.functions, error) || !strings(j, "coordinates", p.coordinates, error) || !numbers(j, "args", p.args, error))
        return false;
    if (p.kind == FunctionPattern::Kind::kBrightText || p.kind == FunctionPattern::Kind::kColorText) {
        // Text: the font's text, the lines, and A R D, the colours inside and out, [spacing].
        const bool colour = p.kind == FunctionPattern::Kind::kColorText;
        if (!j.contains("font") || !j.at("font").is_string()) return error = "a text pattern needs a 'font' (the font file's text)", false;
        p.font = j.at("font").get<std::string>();
        if (!strings(j, "text", p.text, error)) return false;
        const size_t n = colour ? 15 : 11;
        if (p.args.size() != n && p.args.size() != n + 1) return error = fmt::format("a {} takes {} or {} 'args'", kind, n, n + 1), false;
        Font font;
        std::string problem;
        if (!parse_font(p.font, font, problem)) return error = "its font: " + problem, false;
        out = std::move(p);
        return true;
    }
    const bool one = p.kind == FunctionPattern::Kind::kBrightFunc || p.kind == FunctionPattern::Kind::kBrightData;
    if (p.functions.size() != (one ? 1u : 3u)) return error = fmt::format("a {} takes {} 'functions'", kind, one ? 1 : 3), false;
    if (j.contains("picture")) {
        if (!j.at("picture").is_string()) return error = "'picture' must be a string", false;
        p.picture = j.at("picture").get<std::string>();
    }
    std::vector<double> m;
    if (!numbers(j, "to_pattern", m, error)) return false;
    if (!m.empty()) {
        if (m.size() != 12) return error = "'to_pattern' must hold 12 numbers (a 3x4 matrix)", false;
        std::copy(m.begin(), m.end(), p.to_pattern.begin());
    }
    if (j.contains("scale") && !(j.at("scale").is_number() && j.at("scale").get<double>() > 0 && std::isfinite(j.at("scale").get<double>())))
        return error = "'scale' must be a positive number", false;
    p.scale = j.value("scale", 1.0);
    if (j.contains("tables")) {
        if (!j.at("tables").is_array()) return error = "'tables' must be an array", false;
        for (const auto& tj : j.at("tables")) {
            DataTable t;
            if (!tj.is_object() || !tj.contains("axes") || !tj.at("axes").is_array()) return error = "a table needs 'axes' (an array)", false;
            for (const auto& aj : tj.at("axes")) {
                DataTable::Axis a;
                if (!aj.is_object()) return error = "a table's axis must be an object", false;
                auto number = [&](const char* key, double fallback) {
                    const nlohmann::json* v = aj.contains(key) ? &aj.at(key) : nullptr;
                    return v && v->is_number() ? v->get<double>() : fallback;
                };
                a.origin = number("origin", 0.0);
                a.size = number("size", 1.0);
                // A count read as a double first: a huge or fractional one must not reach an int.
                const double count = number("count", 0.0);
                if (!(count >= 2 && count <= (1 << 24) && count == std::floor(count)))
                    return error = "a table's axis needs a whole 'count' from 2 to 2^24", false;
                a.count = static_cast<int>(count);
                if (!numbers(aj, "points", a.points, error)) return false;
                t.axes.push_back(std::move(a));
            }
            if (!numbers(tj, "values", t.values, error)) return false;
            if (std::string problem = data_table_problem(t); !problem.empty()) return error = "a table: " + problem, false;
            t.axes.shrink_to_fit();
            p.tables.push_back(std::move(t));
        }
    }
    const size_t tables = p.kind == FunctionPattern::Kind::kBrightData ? 1 : p.kind == FunctionPattern::Kind::kColorData ? 3 : 0;
    if (p.tables.size() != tables) return error = fmt::format("a {} takes {} 'tables'", kind, tables), false;
    const size_t coordinates = tables ? p.tables.front().axes.size() : p.kind == FunctionPattern::Kind::kColorPict ? 2 : 0;
    if (p.coordinates.size() != coordinates) return error = fmt::format("this {} takes {} 'coordinates'", kind, coordinates), false;
    for (const DataTable& t : p.tables)
        if (t.axes.size() != coordinates) return error = "its tables must have the same number of dimensions", false;
    if (p.kind == FunctionPattern::Kind::kColorPict && p.picture.empty()) return error = "a colorpict needs a 'picture'", false;
    out = std::move(p);
    return true;
}

nlohmann::json surface_functions_to_json(const SurfaceFunctions& s) {
    auto vec = [](const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
    return {{"reflection", pattern_to_json(s.reflection)}, {"transmission", pattern_to_json(s.transmission)},
            {"front_diffuse", vec(s.front_diffuse)}, {"back_diffuse", vec(s.back_diffuse)}, {"diffuse_transmit", vec(s.diffuse_transmit)}};
}

bool surface_functions_from_json(const nlohmann::json& j, SurfaceFunctions& out, std::string& error) {
    if (!j.is_object()) return error = "expected an object", false;
    SurfaceFunctions s;
    for (const char* key : {"reflection", "transmission"}) {
        FunctionPattern& f = std::string(key) == "reflection" ? s.reflection : s.transmission;
        if (!j.contains(key) || !pattern_from_json(j.at(key), f, error)) {
            error = fmt::format("'{}': {}", key, error.empty() ? "missing" : error);
            return false;
        }
        if (f.kind != FunctionPattern::Kind::kColorFunc) return error = fmt::format("'{}' must be a colorfunc", key), false;
    }
    for (const char* key : {"front_diffuse", "back_diffuse", "diffuse_transmit"}) {
        std::vector<double> v;
        if (!numbers(j, key, v, error)) return false;
        if (v.size() != 3 || !(v[0] >= 0 && v[1] >= 0 && v[2] >= 0 && v[0] <= 1 && v[1] <= 1 && v[2] <= 1))
            return error = fmt::format("'{}' must be three numbers in [0, 1]", key), false;
        (std::string(key) == "front_diffuse" ? s.front_diffuse : std::string(key) == "back_diffuse" ? s.back_diffuse : s.diffuse_transmit) =
            Vec3{v[0], v[1], v[2]};
    }
    out = std::move(s);
    return true;
}

nlohmann::json redirections_to_json(const std::vector<Redirection>& r) {
    nlohmann::json a = nlohmann::json::array();
    for (const Redirection& x : r) a.push_back({{"coefficient", pattern_to_json(x.coefficient)}, {"direction", pattern_to_json(x.direction)}});
    return a;
}

bool redirections_from_json(const nlohmann::json& j, std::vector<Redirection>& out, std::string& error) {
    if (!j.is_array() || j.empty() || j.size() > 2) return error = "expected an array of one or two redirections", false;
    std::vector<Redirection> r;
    for (const nlohmann::json& x : j) {
        Redirection d;
        for (const char* key : {"coefficient", "direction"}) {
            FunctionPattern& f = std::string(key) == "coefficient" ? d.coefficient : d.direction;
            if (!x.is_object() || !x.contains(key) || !pattern_from_json(x.at(key), f, error)) {
                error = fmt::format("'{}': {}", key, error.empty() ? "missing" : error);
                return false;
            }
        }
        if (d.coefficient.kind != FunctionPattern::Kind::kBrightFunc || d.coefficient.functions.size() != 1)
            return error = "'coefficient' must be a brightfunc of one expression", false;
        if (d.direction.kind != FunctionPattern::Kind::kColorFunc || d.direction.functions.size() != 3)
            return error = "'direction' must be a colorfunc of three expressions", false;
        r.push_back(std::move(d));
    }
    out = std::move(r);
    return true;
}

nlohmann::json directional_function_to_json(const DirectionalFunction& d) {
    auto vec = [](const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
    return {{"shape", pattern_to_json(d.shape)}, {"diffuse_reflect", vec(d.diffuse_reflect)}, {"diffuse_transmit", vec(d.diffuse_transmit)},
            {"reflect", vec(d.reflect)}, {"transmit", vec(d.transmit)}};
}

bool directional_function_from_json(const nlohmann::json& j, DirectionalFunction& out, std::string& error) {
    if (!j.is_object()) return error = "expected an object", false;
    DirectionalFunction d;
    if (!j.contains("shape") || !pattern_from_json(j.at("shape"), d.shape, error)) {
        error = fmt::format("'shape': {}", error.empty() ? "missing" : error);
        return false;
    }
    if (d.shape.kind != FunctionPattern::Kind::kBrightFunc) return error = "'shape' must be a brightfunc", false;
    const std::pair<const char*, Vec3*> parts[] = {{"diffuse_reflect", &d.diffuse_reflect}, {"diffuse_transmit", &d.diffuse_transmit},
                                                   {"reflect", &d.reflect}, {"transmit", &d.transmit}};
    for (const auto& [key, target] : parts) {
        std::vector<double> v;
        if (!numbers(j, key, v, error)) return false;
        if (v.size() != 3 || !(v[0] >= 0 && v[1] >= 0 && v[2] >= 0 && v[0] <= 1 && v[1] <= 1 && v[2] <= 1))
            return error = fmt::format("'{}' must be three numbers in [0, 1]", key), false;
        *target = Vec3{v[0], v[1], v[2]};
    }
    out = std::move(d);
    return true;
}

}  // namespace crex
