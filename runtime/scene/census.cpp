#include "runtime/scene/census.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>

#include "base/fnv1a.h"

namespace crex {

Census take_census(const Scene& scene) {
    Census c;
    std::map<std::string, MaterialUse> used;
    std::map<std::string, size_t> tagged;
    for (const auto& shape : scene.shapes) {
        const Material* m = scene.find_material(shape.material);
        if (!m) continue;  // loaders reject unknown materials; be safe anyway
        MaterialUse& u = used[m->name];
        u.name = m->name;
        u.type = m->type;
        // An illum's surface is its alternate material to every ray that can spawn others.
        const Material* seen = shading_material(scene, *m);
        u.spawns = seen ? spawned_components(*seen) : ComponentSet{};
        ++u.shapes;
        if (is_sampled_shape(*m, shape) && is_emissive(*m)) ++c.sampled_emitters;
        else if (is_emissive(*m)) ++c.unsampled_emitters;
        // A mixture's surfaces are its background material too, where the coefficient says.
        if (const Material* b = m->mixture ? scene.find_material(m->mixture->background) : nullptr) {
            if (const Material* bs = shading_material(scene, *b)) u.spawns |= spawned_components(*bs);
            if (is_emissive(*b)) ++c.unsampled_emitters;
        }
        if (shape.tag) ++tagged[shape.tag->name];
    }
    for (const auto& l : scene.distant_lights) {
        const Material* m = scene.find_material(l.material);
        if (!m || !is_emissive(*m)) continue;
        if (m->type == MaterialType::kGlow && m->glow_radius < 0) ++c.unsampled_emitters;
        else ++c.sampled_emitters;  // the sun, a sky: direct lighting samples them
    }
    for (const auto& [name, count] : tagged) {
        c.tags.push_back(name);
        c.tag_surfaces.push_back(count);
    }
    for (auto& [name, use] : used) {
        c.spawnable |= use.spawns;
        c.materials.push_back(use);
    }
    c.has_medium = scene.medium && max_component(scene.medium->extinction) > 0;
    // The hash covers what a plan depends on: reachable bins, emitter kinds, media and tags.
    std::string key = fmt::format("spawnable={};light={};glow={};medium={};tags=", c.spawnable.to_string(),
                                  c.sampled_emitters > 0, c.unsampled_emitters > 0, c.has_medium);
    for (const auto& t : c.tags) key += t + ",";
    c.hash = fnv1a64(key);
    return c;
}

std::string census_hash_hex(uint64_t hash) { return hex16(hash); }

nlohmann::json to_json(const Census& c) {
    nlohmann::json j;
    j["hash"] = census_hash_hex(c.hash);
    nlohmann::json comps = nlohmann::json::object();
    for (const auto& row : kComponentTable) {
        nlohmann::json e;
        e["can_occur"] = c.can_occur(row.component);
        e["name"] = std::string(row.name);
        nlohmann::json from = nlohmann::json::array();
        for (const auto& m : c.materials)
            if (m.spawns.test(static_cast<size_t>(row.component))) from.push_back(m.name);
        e["spawned_by"] = from;
        comps[std::string(1, row.letter)] = e;
    }
    j["components"] = comps;
    nlohmann::json mats = nlohmann::json::array();
    for (const auto& m : c.materials)
        mats.push_back({{"name", m.name},
                        {"type", std::string(material_type_name(m.type))},
                        {"spawns", component_set_letters(m.spawns)},
                        {"shapes", m.shapes}});
    j["materials"] = mats;
    nlohmann::json graph = nlohmann::json::object();
    std::vector<std::string> sources = {"camera"};
    for (const auto& row : kComponentTable)
        if (c.can_occur(row.component)) sources.push_back(std::string(1, row.letter));
    for (const auto& s : sources) graph[s] = component_set_letters(c.spawnable);
    j["spawn_graph"] = graph;
    j["sampled_emitters"] = c.sampled_emitters;
    j["unsampled_emitters"] = c.unsampled_emitters;
    j["medium"] = c.has_medium;
    j["tags"] = c.tags;
    nlohmann::json counts = nlohmann::json::object();
    for (size_t i = 0; i < c.tags.size(); ++i) counts[c.tags[i]] = c.tag_surfaces[i];
    j["tag_surfaces"] = counts;
    return j;
}

}  // namespace crex
