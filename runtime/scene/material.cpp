#include "runtime/scene/material.h"

#include <array>
#include <utility>

#include "runtime/base/name_table.h"

namespace crex {
namespace {

constexpr std::array<std::pair<MaterialType, std::string_view>, 10> kMaterialNames = {{
    {MaterialType::kVoid, "void"},
    {MaterialType::kPlastic, "plastic"},
    {MaterialType::kMetal, "metal"},
    {MaterialType::kTrans, "trans"},
    {MaterialType::kGlass, "glass"},
    {MaterialType::kDielectric, "dielectric"},
    {MaterialType::kMirror, "mirror"},
    {MaterialType::kLight, "light"},
    {MaterialType::kGlow, "glow"},
    {MaterialType::kIllum, "illum"},
}};

constexpr std::array<std::pair<Projection, std::string_view>, 6> kProjections = {{
    {Projection::kPerspective, "perspective"},
    {Projection::kParallel, "parallel"},
    {Projection::kAngular, "angular"},
    {Projection::kHemispherical, "hemispherical"},
    {Projection::kStereographic, "stereographic"},
    {Projection::kCylindrical, "cylindrical"},
}};

constexpr std::array<std::pair<SkyModel::Type, std::string_view>, 4> kSkyTypes = {{
    {SkyModel::Type::kClear, "clear"},
    {SkyModel::Type::kOvercast, "overcast"},
    {SkyModel::Type::kUniform, "uniform"},
    {SkyModel::Type::kIntermediate, "intermediate"},
}};

void set(ComponentSet& s, Component c) { s.set(static_cast<size_t>(c)); }

}  // namespace

std::string_view material_type_name(MaterialType t) { return name_in(kMaterialNames, t); }

std::optional<MaterialType> material_type_from_name(std::string_view name) { return value_in(kMaterialNames, name); }

std::string_view projection_name(Projection p) { return name_in(kProjections, p); }
std::optional<Projection> projection_from_name(std::string_view name) { return value_in(kProjections, name); }
std::string_view sky_type_name(SkyModel::Type t) { return name_in(kSkyTypes, t); }
std::optional<SkyModel::Type> sky_type_from_name(std::string_view name) { return value_in(kSkyTypes, name); }

ComponentSet spawned_components(const Material& m) {
    ComponentSet s;
    // A texture can make any texel anything in its range: a textured parameter counts as
    // possibly non-zero (a material whose texture happens to be black is still a material),
    // and a textured roughness as glossy (it is kept above 0: textures never make S).
    const MaterialTextures& tex = m.textures;
    bool coloured = max_component(m.color) > 0 || tex.color.has_value();
    switch (m.type) {
    case MaterialType::kPlastic:
    case MaterialType::kMetal:
    case MaterialType::kTrans: {
        const bool metal_part = m.metallic > 0 || tex.metallic.has_value();
        const bool dielectric_part = m.metallic < 1 || tex.metallic.has_value();
        const bool some_specular = m.specularity > 0 || tex.specularity.has_value();
        const bool all_specular = m.specularity >= 1 && !tex.specularity;
        const bool rough = m.roughness > 0 || tex.roughness.has_value();
        const bool all_transmitted = m.type == MaterialType::kTrans && m.transmissivity >= 1;
        if (coloured && dielectric_part && !all_specular && !all_transmitted) set(s, Component::kD);  // diffuse reflection
        if ((some_specular && dielectric_part) || (metal_part && coloured)) set(s, rough ? Component::kG : Component::kS);
        if (m.type == MaterialType::kTrans && coloured && dielectric_part && !all_specular && m.transmissivity > 0) {
            if (m.transmitted_specular < 1) set(s, Component::kD);  // diffuse transmission
            if (m.transmitted_specular > 0) set(s, Component::kT);  // specular transmission
        }
        break;
    }
    case MaterialType::kGlass:
    case MaterialType::kDielectric:
        // Fresnel reflection happens whatever the colour; transmission needs a non-black colour.
        set(s, Component::kR);
        if (coloured) set(s, Component::kT);
        break;
    case MaterialType::kMirror:
        if (coloured) set(s, Component::kM);
        break;
    case MaterialType::kVoid:
    case MaterialType::kLight:
    case MaterialType::kGlow:
    case MaterialType::kIllum: break;  // an illum's surface spawns what its alternate does
    }
    return s;
}

const Material* shading_material(const Scene& scene, const Material& m) {
    if (m.type != MaterialType::kIllum) return &m;
    return m.alternate.empty() ? nullptr : scene.find_material(m.alternate);
}

MaterialValues constant_values(const Material& m) {
    MaterialValues v;
    v.color = m.color;
    v.specularity = m.specularity;
    v.roughness = m.roughness;
    v.metallic = m.metallic;
    v.opacity = m.opacity;
    v.emission = m.emission;
    return v;
}

Vec3 emitted_radiance(const Material& m) {
    if (m.type == MaterialType::kLight || m.type == MaterialType::kGlow || m.type == MaterialType::kIllum) return m.color;
    return m.emission ? *m.emission : Vec3{};
}

bool samples_textured_emission(const Material& m) {
    const bool reflects = m.type == MaterialType::kPlastic || m.type == MaterialType::kMetal || m.type == MaterialType::kTrans;
    return reflects && m.emission_sampled && m.textures.emission.has_value() && m.patterns.empty() && !m.surface_functions &&
           !m.directional && m.redirections.empty() && !m.mixture;
}

bool is_sampled_shape(const Material& m, const Shape& s) {
    return is_sampled_emitter(m) || (samples_textured_emission(m) && s.type != ShapeType::kSphere);
}

bool is_emissive(const Material& m) { return max_component(emitted_radiance(m)) > 0 || m.textures.emission.has_value(); }

std::string component_set_letters(const ComponentSet& set) {
    std::string out;
    for (const auto& row : kComponentTable) {
        if (!set.test(static_cast<size_t>(row.component))) continue;
        if (!out.empty()) out += ' ';
        out += row.letter;
    }
    return out;
}

}  // namespace crex
