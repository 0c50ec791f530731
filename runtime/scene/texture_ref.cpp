#include "runtime/scene/texture_ref.h"

#include <cmath>
#include <utility>

#include "runtime/base/name_table.h"

namespace crex {
namespace {

constexpr std::array<std::pair<TextureWrap, std::string_view>, 4> kWraps = {{
    {TextureWrap::kRepeat, "repeat"},
    {TextureWrap::kClamp, "clamp"},
    {TextureWrap::kMirror, "mirror"},
    {TextureWrap::kBlack, "black"},
}};

constexpr std::array<std::pair<TextureFilter, std::string_view>, 2> kFilters = {{
    {TextureFilter::kSmooth, "smooth"},
    {TextureFilter::kNearest, "nearest"},
}};

constexpr std::array<std::pair<TextureColorSpace, std::string_view>, 3> kColorSpaces = {{
    {TextureColorSpace::kAuto, "auto"},
    {TextureColorSpace::kSrgb, "srgb"},
    {TextureColorSpace::kLinear, "linear"},
}};

constexpr std::array<std::pair<TextureMapping, std::string_view>, 2> kMappings = {{
    {TextureMapping::kUv, "uv"},
    {TextureMapping::kPlanar, "planar"},
}};

}  // namespace

std::string_view texture_wrap_name(TextureWrap w) { return name_in(kWraps, w); }
std::optional<TextureWrap> texture_wrap_from_name(std::string_view name) { return value_in(kWraps, name); }
std::string_view texture_filter_name(TextureFilter f) { return name_in(kFilters, f); }
std::optional<TextureFilter> texture_filter_from_name(std::string_view name) { return value_in(kFilters, name); }
std::string_view texture_color_space_name(TextureColorSpace c) { return name_in(kColorSpaces, c); }
std::optional<TextureColorSpace> texture_color_space_from_name(std::string_view name) { return value_in(kColorSpaces, name); }
std::string_view texture_mapping_name(TextureMapping m) { return name_in(kMappings, m); }
std::optional<TextureMapping> texture_mapping_from_name(std::string_view name) { return value_in(kMappings, name); }

UvTransform uv_transform_of(double offset_u, double offset_v, double rotation, double scale_u, double scale_v) {
    // Translation * rotation * scale, the rotation turning (u, v) to (c u + s v, c v - s u): as
    // the extension's own test model (TextureTransformTest's arrow points to its green marker),
    // three.js and Cesium turn it. Its README's GLSL, read as written, turns the other way (the
    // model's red marker: "the rotation was applied in the opposite direction"), which crex
    // followed until 2026-12-05.
    const double c = std::cos(rotation), s = std::sin(rotation);
    return {c * scale_u, s * scale_v, offset_u, -s * scale_u, c * scale_v, offset_v};
}

}  // namespace crex
