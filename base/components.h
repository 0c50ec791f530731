/// \file components.h
/// The light-transport components a crex names (spec/crex.md §1). This table is the only
/// place that knows the letters: the lexer accepts any ASCII letter and the AST builder looks
/// it up here, so adding a component is one row.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace crex {

enum class Component : uint8_t { kD, kG, kS, kT, kR, kM };

struct ComponentInfo {
    Component component;
    char letter;
    std::string_view name;        ///< "indirect diffuse"
    std::string_view spawned_by;  ///< which material lobes spawn rays into this bin
};

inline constexpr std::array<ComponentInfo, 6> kComponentTable = {{
    {Component::kD, 'D', "indirect diffuse",
     "diffuse reflection (and diffuse transmission of trans)"},
    {Component::kG, 'G', "indirect glossy", "rough specular of plastic, metal, trans"},
    {Component::kS, 'S', "indirect specular", "ideal specular of plastic, metal, trans"},
    {Component::kT, 'T', "transmitted", "glass, dielectric; specular transmission of trans"},
    {Component::kR, 'R', "reflected off glass/dielectric", "Fresnel reflection of glass, dielectric"},
    {Component::kM, 'M', "mirror reflection", "mirror"},
}};

inline constexpr size_t kComponentCount = kComponentTable.size();

inline const ComponentInfo& component_info(Component c) {
    return kComponentTable[static_cast<size_t>(c)];
}
inline char component_letter(Component c) { return component_info(c).letter; }

inline std::optional<Component> component_from_letter(char letter) {
    for (const auto& row : kComponentTable)
        if (row.letter == letter) return row.component;
    return std::nullopt;
}

/// "D G S T R M", for messages that list what is allowed.
std::string_view component_letters_spaced();

}  // namespace crex
