// Scene -> native JSON. Writes every field that differs from its default, so that loading the
// output gives an equal scene (tests/unit/runtime/scene_json_test.cpp checks the round trip).
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include <fmt/format.h>

#include "base/base64.h"
#include "base/fnv1a.h"
#include "runtime/scene/pattern_json.h"
#include "runtime/scene/load_scene.h"
#include "runtime/scene/material.h"
#include "runtime/scene/shapes.h"

namespace crex {
namespace {

nlohmann::json vec(const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

nlohmann::json camera_json(const Camera& c) {
    nlohmann::json j = {{"position", vec(c.position)}, {"direction", vec(c.direction)}, {"up", vec(c.up)},
                        {"vfov", c.vfov_deg},          {"view_distance", c.view_distance}};
    if (c.hfov_deg > 0) j["hfov"] = c.hfov_deg;
    if (c.projection != Projection::kPerspective) j["projection"] = std::string(projection_name(c.projection));
    if (c.fore_clip > 0) j["fore_clip"] = c.fore_clip;
    return j;
}

// A texture reference with every field that differs from its default.
nlohmann::json texture_json(const TextureRef& t) {
    const TextureRef d;
    nlohmann::json j;
    if (!t.file.empty()) j["file"] = t.file;
    else j["image"] = t.image;
    if (t.color_space != d.color_space) j["color_space"] = std::string(texture_color_space_name(t.color_space));
    if (t.wrap_s != d.wrap_s || t.wrap_t != d.wrap_t)
        j["wrap"] = {std::string(texture_wrap_name(t.wrap_s)), std::string(texture_wrap_name(t.wrap_t))};
    if (t.filter != d.filter) j["filter"] = std::string(texture_filter_name(t.filter));
    if (t.scale != d.scale) j["scale"] = vec(t.scale);
    if (t.power != d.power) j["power"] = t.power;
    if (t.channel != d.channel) j["channel"] = t.channel;
    if (t.prefer_alpha != d.prefer_alpha) j["prefer_alpha"] = t.prefer_alpha;
    if (t.uv_transform != d.uv_transform) j["uv_transform"] = {{"matrix", t.uv_transform}};
    if (t.mapping != d.mapping) j["mapping"] = std::string(texture_mapping_name(t.mapping));
    if (t.planar != d.planar) j["planar"] = t.planar;
    return j;
}

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

std::string scene_identity_text(const Scene& scene) {
    nlohmann::json j = scene_to_json(scene);
    std::function<void(nlohmann::json&)> by_content = [&](nlohmann::json& v) {
        if (v.is_array()) {
            for (auto& e : v) by_content(e);
        } else if (v.is_object()) {
            for (auto& [key, value] : v.items()) {
                if (key != "file" || !value.is_string()) {
                    by_content(value);
                    continue;
                }
                const std::filesystem::path path(value.get<std::string>());
                std::ifstream in(path, std::ios::binary);
                std::ostringstream bytes;
                if (in && (bytes << in.rdbuf())) value = fmt::format("{} fnv1a {:016x}", path.filename().string(), fnv1a64(bytes.str()));
            }
        }
    };
    if (j.contains("materials")) by_content(j["materials"]);  // texture references live in materials
    std::string out;
    write_json(out, j, 0);
    return out + "\n";
}

nlohmann::json scene_to_json(const Scene& scene) {
    nlohmann::json j;
    j["format"] = "crex-scene";
    j["version"] = 1;
    j["camera"] = camera_json(scene.camera);
    for (const auto& named : scene.cameras) {
        nlohmann::json c = camera_json(named.camera);
        if (!named.name.empty()) c["name"] = named.name;
        j["cameras"].push_back(c);
    }
    if (scene.units.metres_per_unit > 0 || scene.units.up != Vec3{}) {
        if (scene.units.metres_per_unit > 0) j["units"]["metres_per_unit"] = scene.units.metres_per_unit;
        if (scene.units.up != Vec3{}) j["units"]["up"] = vec(scene.units.up);
    }
    j["background"] = vec(scene.background);
    if (!scene.back_faces_visible) j["back_faces_visible"] = false;
    for (const auto& image : scene.images)
        j["images"].push_back({{"name", image.name}, {"mime_type", image.mime_type}, {"data", base64(image.bytes)}});
    if (scene.medium)
        j["medium"] = {{"extinction", vec(scene.medium->extinction)},
                       {"albedo", vec(scene.medium->albedo)},
                       {"eccentricity", scene.medium->eccentricity}};
    if (scene.medium && scene.medium->bounded) j["medium"]["box"] = {vec(scene.medium->box_min), vec(scene.medium->box_max)};
    const Material defaults;
    j["materials"] = nlohmann::json::array();
    for (const auto& m : scene.materials) {
        nlohmann::json e = {{"name", m.name}, {"type", std::string(material_type_name(m.type))}, {"color", vec(m.color)}};
        if (m.specularity != defaults.specularity) e["specularity"] = m.specularity;
        if (m.roughness != defaults.roughness) e["roughness"] = m.roughness;
        if (m.transmissivity != defaults.transmissivity) e["transmissivity"] = m.transmissivity;
        if (m.transmitted_specular != defaults.transmitted_specular) e["transmitted_specular"] = m.transmitted_specular;
        if (m.ior != defaults.ior) e["ior"] = m.ior;
        if (m.thin_glass) e["thin"] = true;
        if (m.glow_radius != defaults.glow_radius) e["glow_radius"] = m.glow_radius;
        if (m.emission) e["emission"] = vec(*m.emission);
        if (!m.emission_sampled) e["emission_sampled"] = false;
        if (m.anisotropy) e["anisotropy"] = {{"orientation", vec(m.anisotropy->orientation)}, {"roughness_v", m.anisotropy->roughness_v}};
        if (m.spot) e["spot"] = {{"angle", m.spot->angle_deg}, {"direction", vec(m.spot->direction)}};
        if (m.outside) e["outside"] = {{"color", vec(m.outside->color)}, {"ior", m.outside->ior}};
        if (m.type == MaterialType::kIllum && !m.alternate.empty()) e["alternate"] = m.alternate;
        if (m.metallic != defaults.metallic) e["metallic"] = m.metallic;
        if (m.opacity != defaults.opacity) e["opacity"] = m.opacity;
        if (m.alpha_mode != defaults.alpha_mode) e["alpha_mode"] = m.alpha_mode == AlphaMode::kBlend ? "blend" : "mask";
        if (m.alpha_cutoff != defaults.alpha_cutoff) e["alpha_cutoff"] = m.alpha_cutoff;
        // A textured parameter is written as its reference, in place of the constant.
        m.textures.for_each([&](const char* slot, const TextureRef& t) { e[slot] = texture_json(t); });
        for (const FunctionPattern& f : m.patterns) e["patterns"].push_back(pattern_to_json(f));
        if (m.surface_functions) e["surface_functions"] = surface_functions_to_json(*m.surface_functions);
        if (m.directional) e["directional_function"] = directional_function_to_json(*m.directional);
        if (!m.redirections.empty()) e["redirections"] = redirections_to_json(m.redirections);
        if (!m.clips.empty()) e["clips"] = m.clips;
        if (m.mixture) e["mixture"] = {{"background", m.mixture->background}, {"coefficient", pattern_to_json(m.mixture->coefficient)}};
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
            if (!s.uvs.empty()) e["uvs"] = s.uvs;
            if (!s.normals.empty())
                for (const auto& n : s.normals) e["normals"].push_back(vec(n));
            if (!s.colors.empty())
                for (const auto& c : s.colors) e["colors"].push_back(vec(c));
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
