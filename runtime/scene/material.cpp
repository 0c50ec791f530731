#include "runtime/scene/material.h"

#include <array>
#include <utility>

#include "runtime/base/name_table.h"

namespace crex {
namespace {

constexpr std::array<std::pair<MaterialType, std::string_view>, 10> kNames = {{
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

std::string_view material_type_name(MaterialType t) { return name_in(kNames, t); }

std::optional<MaterialType> material_type_from_name(std::string_view name) { return value_in(kNames, name); }

std::string_view projection_name(Projection p) { return name_in(kProjections, p); }
std::optional<Projection> projection_from_name(std::string_view name) { return value_in(kProjections, name); }
std::string_view sky_type_name(SkyModel::Type t) { return name_in(kSkyTypes, t); }
std::optional<SkyModel::Type> sky_type_from_name(std::string_view name) { return value_in(kSkyTypes, name); }

ComponentSet spawned_components(const Material& m) {
    ComponentSet s;
    bool coloured = max_component(m.color) > 0;
    switch (m.type) {
    case MaterialType::kPlastic:
    case MaterialType::kMetal:
    case MaterialType::kTrans: {
        double spec = m.specularity;
        if (coloured && spec < 1) set(s, Component::kD);  // diffuse reflection
        if (spec > 0) set(s, m.roughness > 0 ? Component::kG : Component::kS);
        if (m.type == MaterialType::kTrans && coloured && m.transmissivity > 0) {
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

Vec3 emitted_radiance(const Material& m) {
    if (m.type == MaterialType::kLight || m.type == MaterialType::kGlow || m.type == MaterialType::kIllum) return m.color;
    return m.emission ? *m.emission : Vec3{};
}

bool is_emissive(const Material& m) { return max_component(emitted_radiance(m)) > 0; }

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
