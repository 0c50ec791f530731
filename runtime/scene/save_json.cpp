// Scene -> native JSON. Writes every field that differs from its default, so that loading the
// output gives an equal scene (tests/unit/runtime/scene_json_test.cpp checks the round trip).
#include "runtime/scene/load_scene.h"
#include "runtime/scene/material.h"
#include "runtime/scene/shapes.h"

namespace crex {
namespace {

nlohmann::json vec(const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

void write_json(std::string& out, const nlohmann::json& j, int depth) {
    auto scalar_array = [](const nlohmann::json& a) {
        for (const auto& e : a)
            if (e.is_structured()) return false;
        return true;
    };
    std::string pad(static_cast<size_t>(depth + 1) * 2, ' '), close_pad(static_cast<size_t>(depth) * 2, ' ');
    if (j.is_object()) {
        out += "{\n";
        size_t i = 0;
        for (const auto& [k, v] : j.items()) {
            out += pad + nlohmann::json(k).dump() + ": ";
            write_json(out, v, depth + 1);
            out += ++i < j.size() ? ",\n" : "\n";
        }
        out += close_pad + "}";
    } else if (j.is_array() && !scalar_array(j)) {
        out += "[\n";
        for (size_t i = 0; i < j.size(); ++i) {
            out += pad;
            write_json(out, j[i], depth + 1);
            out += i + 1 < j.size() ? ",\n" : "\n";
        }
        out += close_pad + "]";
    } else {
        out += j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);  // short arrays on one line
    }
}

}  // namespace

std::string scene_json_text(const Scene& scene) {
    std::string out;
    write_json(out, scene_to_json(scene), 0);
    return out + "\n";
}

nlohmann::json scene_to_json(const Scene& scene) {
    nlohmann::json j;
    j["format"] = "crex-scene";
    j["version"] = 1;
    const Camera& c = scene.camera;
    j["camera"] = {{"position", vec(c.position)}, {"direction", vec(c.direction)}, {"up", vec(c.up)},
                   {"vfov", c.vfov_deg},          {"view_distance", c.view_distance}};
    if (c.hfov_deg > 0) j["camera"]["hfov"] = c.hfov_deg;
    if (c.projection != Projection::kPerspective) j["camera"]["projection"] = std::string(projection_name(c.projection));
    if (c.fore_clip > 0) j["camera"]["fore_clip"] = c.fore_clip;
    j["background"] = vec(scene.background);
    if (scene.medium)
        j["medium"] = {{"extinction", vec(scene.medium->extinction)},
                       {"albedo", vec(scene.medium->albedo)},
                       {"eccentricity", scene.medium->eccentricity}};
    const Material defaults;
    j["materials"] = nlohmann::json::array();
    for (const auto& m : scene.materials) {
        nlohmann::json e = {{"name", m.name}, {"type", std::string(material_type_name(m.type))}, {"color", vec(m.color)}};
        if (m.specularity != defaults.specularity) e["specularity"] = m.specularity;
        if (m.roughness != defaults.roughness) e["roughness"] = m.roughness;
        if (m.transmissivity != defaults.transmissivity) e["transmissivity"] = m.transmissivity;
        if (m.transmitted_specular != defaults.transmitted_specular) e["transmitted_specular"] = m.transmitted_specular;
        if (m.ior != defaults.ior) e["ior"] = m.ior;
        if (m.glow_radius != defaults.glow_radius) e["glow_radius"] = m.glow_radius;
        if (m.emission) e["emission"] = vec(*m.emission);
        if (m.anisotropy) e["anisotropy"] = {{"orientation", vec(m.anisotropy->orientation)}, {"roughness_v", m.anisotropy->roughness_v}};
        if (m.spot) e["spot"] = {{"angle", m.spot->angle_deg}, {"direction", vec(m.spot->direction)}};
        if (m.outside) e["outside"] = {{"color", vec(m.outside->color)}, {"ior", m.outside->ior}};
        if (m.type == MaterialType::kIllum && !m.alternate.empty()) e["alternate"] = m.alternate;
        j["materials"].push_back(e);
    }
    j["shapes"] = nlohmann::json::array();
    for (const auto& s : scene.shapes) {
        nlohmann::json e = {{"type", std::string(shape_type_name(s.type))}, {"material", s.material}};
        if (!s.name.empty()) e["name"] = s.name;
        if (s.tag) e["tag"] = {{"name", s.tag->name}, {"task", s.tag->task}, {"distractor", s.tag->distractor}};
        if (s.inward) e["inward"] = true;
        switch (s.type) {
        case ShapeType::kSphere: e["center"] = vec(s.center), e["radius"] = s.radius; break;
        case ShapeType::kPolygon:
        case ShapeType::kMesh:
            e["vertices"] = nlohmann::json::array();
            for (const auto& v : s.vertices) e["vertices"].push_back(vec(v));
            if (s.type == ShapeType::kMesh) e["triangles"] = s.triangles;
            break;
        case ShapeType::kBox: e["min"] = vec(s.min), e["max"] = vec(s.max); break;
        case ShapeType::kRing:
            e["center"] = vec(s.center), e["normal"] = vec(s.normal);
            e["inner_radius"] = s.r0, e["outer_radius"] = s.r1;
            break;
        case ShapeType::kCone: e["p0"] = vec(s.p0), e["p1"] = vec(s.p1), e["r0"] = s.r0, e["r1"] = s.r1; break;
        case ShapeType::kCylinder: e["p0"] = vec(s.p0), e["p1"] = vec(s.p1), e["radius"] = s.radius; break;
        }
        j["shapes"].push_back(e);
    }
    if (!scene.distant_lights.empty()) {
        j["distant_lights"] = nlohmann::json::array();
        for (const auto& l : scene.distant_lights) {
            nlohmann::json e = {{"material", l.material}, {"direction", vec(l.direction)}, {"angle", l.angle_deg}};
            if (!l.name.empty()) e["name"] = l.name;
            if (l.sky)
                e["sky"] = {{"type", std::string(sky_type_name(l.sky->type))}, {"zenith", l.sky->zenith}, {"ground", l.sky->ground},
                            {"normalization", l.sky->normalization}, {"sun", vec(l.sky->sun)}};
            j["distant_lights"].push_back(e);
        }
    }
    return j;
}

}  // namespace crex
