/// \file primitive_types.h
/// RADIANCE's primitive types by name: what kind each is (surface, material, pattern, ...) and
/// whether its string arguments end in a function file and transform (which xform extends).
/// Knowing every type RADIANCE knows lets an unsupported one be named as such, and an unknown
/// one be called a typo.
#pragma once

#include <string_view>

namespace crex::radiance {

enum class PrimitiveKind { kSurface, kMaterial, kPattern, kTexture, kMixture, kAlias };

struct PrimitiveTypeInfo {
    std::string_view name;
    PrimitiveKind kind;
    bool function_transform = false;  ///< strings end in "funcfile [transform]" (xform appends)
    bool light = false;               ///< light, illum, glow, spotlight
};

/// The type named `name`, or nullptr when RADIANCE has no such type.
const PrimitiveTypeInfo* find_primitive_type(std::string_view name);

/// The type a surface becomes when its normal is inverted (xform -I): sphere <-> bubble,
/// cone <-> cup, cylinder <-> tube; others are themselves.
std::string_view inverted_surface_type(std::string_view type);

}  // namespace crex::radiance
