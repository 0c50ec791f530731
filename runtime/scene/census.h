/// \file census.h
/// The material census (spec/crex.md §5): which components the scene's materials can ever
/// spawn, and so which crex steps can ever have work. Only materials some shape uses count.
/// The spawn graph is conservative (no visibility): an edge X -> Y for every source X (the
/// camera, or a component that can itself occur) iff some used material spawns into Y.
/// The census hash identifies what a plan depends on; running a plan on a scene with another
/// hash is an error, never a silently wrong image.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "runtime/scene/material.h"
#include "runtime/scene/scene.h"

namespace crex {

struct MaterialUse {
    std::string name;
    MaterialType type = MaterialType::kVoid;
    ComponentSet spawns;
    size_t shapes = 0;  ///< how many shapes use it
};

struct Census {
    std::vector<MaterialUse> materials;  ///< used materials, in name order
    ComponentSet spawnable;              ///< union of what used materials spawn
    size_t sampled_emitters = 0;         ///< shapes and distant sources direct lighting samples
    size_t unsampled_emitters = 0;       ///< shapes (or sources) that glow but are not sampled
    bool has_medium = false;
    std::vector<std::string> tags;  ///< names of tagged objects, sorted
    std::vector<size_t> tag_surfaces;  ///< how many shapes each of `tags` tags
    uint64_t hash = 0;

    bool can_occur(Component c) const { return spawnable.test(static_cast<size_t>(c)); }
    /// Edge of the spawn graph; `from` = nullopt is the camera.
    bool can_spawn(std::optional<Component> from, Component to) const {
        return (!from || can_occur(*from)) && can_occur(to);
    }
};

Census take_census(const Scene& scene);
nlohmann::json to_json(const Census& census);
/// The hash as it is printed and stored in plans: 16 hex digits.
std::string census_hash_hex(uint64_t hash);

}  // namespace crex
