#include "runtime/scene/radiance/primitive_types.h"

#include <array>

namespace crex::radiance {
namespace {

using K = PrimitiveKind;

// RADIANCE's type table (its src/common/otypes.h lists the same names): kind, whether the
// strings carry a function file and its transform, whether it is a light source material.
constexpr std::array<PrimitiveTypeInfo, 53> kTypes = {{
    {"polygon", K::kSurface},     {"cone", K::kSurface},          {"sphere", K::kSurface},
    {"ring", K::kSurface},        {"cylinder", K::kSurface},      {"cup", K::kSurface},
    {"bubble", K::kSurface},      {"tube", K::kSurface},          {"source", K::kSurface},
    {"instance", K::kSurface, true}, {"mesh", K::kSurface, true},
    {"plastic", K::kMaterial},    {"metal", K::kMaterial},        {"glass", K::kMaterial},
    {"trans", K::kMaterial},      {"dielectric", K::kMaterial},   {"interface", K::kMaterial},
    {"plastic2", K::kMaterial, true}, {"metal2", K::kMaterial, true}, {"trans2", K::kMaterial, true},
    {"plasfunc", K::kMaterial, true}, {"metfunc", K::kMaterial, true}, {"transfunc", K::kMaterial, true},
    {"BRTDfunc", K::kMaterial, true}, {"WGMDfunc", K::kMaterial, true}, {"ashik2", K::kMaterial, true},
    {"plasdata", K::kMaterial, true}, {"metdata", K::kMaterial, true}, {"transdata", K::kMaterial, true},
    {"BSDF", K::kMaterial, true}, {"aBSDF", K::kMaterial, true},
    {"prism1", K::kMaterial, true}, {"prism2", K::kMaterial, true},
    {"glow", K::kMaterial, false, true}, {"light", K::kMaterial, false, true},
    {"illum", K::kMaterial, false, true}, {"spotlight", K::kMaterial, false, true},
    {"mirror", K::kMaterial},     {"mist", K::kMaterial},         {"antimatter", K::kMaterial},
    {"texfunc", K::kTexture, true}, {"texdata", K::kTexture, true},
    {"brightfunc", K::kPattern, true}, {"colorfunc", K::kPattern, true},
    {"brightdata", K::kPattern, true}, {"colordata", K::kPattern, true},
    {"colorpict", K::kPattern, true}, {"brighttext", K::kPattern}, {"colortext", K::kPattern},
    {"mixfunc", K::kMixture, true}, {"mixdata", K::kMixture, true}, {"mixpict", K::kMixture, true},
    {"mixtext", K::kMixture},
}};

constexpr PrimitiveTypeInfo kAlias{"alias", K::kAlias};

}  // namespace

const PrimitiveTypeInfo* find_primitive_type(std::string_view name) {
    if (name == "alias") return &kAlias;
    for (const auto& t : kTypes)
        if (t.name == name) return &t;
    return nullptr;
}

std::string_view inverted_surface_type(std::string_view type) {
    if (type == "sphere") return "bubble";
    if (type == "bubble") return "sphere";
    if (type == "cone") return "cup";
    if (type == "cup") return "cone";
    if (type == "cylinder") return "tube";
    if (type == "tube") return "cylinder";
    return type;
}

}  // namespace crex::radiance
