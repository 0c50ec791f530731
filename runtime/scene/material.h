/// \file material.h
/// Material types by name, and the component split of spec/crex.md §1: which bins a hit on a
/// material can spawn rays into. This is the single source of truth for the census (and so for
/// what the planner prunes) and for the renderer's lobe splitting.
#pragma once

#include <bitset>
#include <optional>
#include <string_view>

#include "base/components.h"
#include "runtime/scene/scene.h"

namespace crex {

using ComponentSet = std::bitset<kComponentCount>;

std::string_view material_type_name(MaterialType t);
std::optional<MaterialType> material_type_from_name(std::string_view name);

/// The names of camera projections ("perspective", "parallel", "angular", "hemispherical",
/// "stereographic", "cylindrical") and sky types ("clear", "overcast", "uniform",
/// "intermediate"), as the JSON format writes them.
std::string_view projection_name(Projection p);
std::optional<Projection> projection_from_name(std::string_view name);
std::string_view sky_type_name(SkyModel::Type t);
std::optional<SkyModel::Type> sky_type_from_name(std::string_view name);

/// Components a hit on `m` spawns into (empty for emitters, void and black surfaces; an
/// illum's surface spawns what its alternate material does: see shading_material()).
ComponentSet spawned_components(const Material& m);

/// The material rays other than shadow rays see on a surface of `m` in `scene`: an illum's
/// alternate (nullptr when it has none: the surface is invisible), else `m` itself.
const Material* shading_material(const Scene& scene, const Material& m);

/// True for emitters sampled by direct lighting: `light`, `illum`, a `glow` with a positive radius.
inline bool is_sampled_emitter(const Material& m) {
    return m.type == MaterialType::kLight || m.type == MaterialType::kIllum || (m.type == MaterialType::kGlow && m.glow_radius > 0);
}
/// True for a material whose `emission` is an image on a surface that also reflects (plastic,
/// metal, trans; no RADIANCE functions on it): direct lighting samples its meshes' triangles
/// (runtime/render/render_scene.h, TexturedEmission). A constant `emission` stays unsampled.
bool samples_textured_emission(const Material& m);
/// Does direct lighting sample shape `s` of material `m`? (A sampled emitter, or a textured
/// emission on anything but an analytic sphere, which has no texture coordinates.)
bool is_sampled_shape(const Material& m, const Shape& s);
/// True when a hit adds emission (sampled or not).
bool is_emissive(const Material& m);

/// The largest radiance a scene may give (emitters, `emission`, the background), as `av`'s
/// range: weighted by throughputs and pdfs it must stay within the image's floats (3.4e38).
/// A lamp of 1e100 overflowed to infinity, every such sample was dropped as non-finite, and
/// the image came out black without a word.
inline constexpr double kMaxRadiance = 1e30;

/// The emitted radiance of `m` (its colour for lights and glows, else its `emission`).
Vec3 emitted_radiance(const Material& m);

/// A material's parameters at one point of a surface: its constants, or what its textures
/// give there (runtime/texture). What the renderer's lobes are made from.
struct MaterialValues {
    Vec3 color;
    double specularity = 0, roughness = 0, metallic = 0, opacity = 1;
    std::optional<Vec3> specular_tint;  ///< a specular colour texture's value (else white, or the colour for metal)
    std::optional<Vec3> emission;
};

/// The values of an untextured material (and of a textured one where it has no texture).
MaterialValues constant_values(const Material& m);

/// "D T R" for a set.
std::string component_set_letters(const ComponentSet& set);

}  // namespace crex
