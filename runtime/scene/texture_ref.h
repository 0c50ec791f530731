/// \file texture_ref.h
/// Texture references in the scene model: where a material parameter takes its value from an
/// image instead of a constant. Plain data, like the rest of the scene, so that any loader
/// (native JSON, OBJ/MTL, glTF, RADIANCE's picture patterns) can produce one and a scene with
/// textures can still be serialised and shipped. How a reference is sampled (filtering,
/// caching) is the renderer's business (runtime/texture/); here is only what it means:
///
///   value = (scale x texel(channels [channel, channel + n)))^power
///
/// at texture coordinates (s, t) = uv_transform applied to the point's (u, v), where (u, v)
/// come from the mesh's per-vertex coordinates (mapping kUv) or from the point's position
/// (mapping kPlanar: u = a . P + a0, v = b . P + b0, RADIANCE's planar picture mappings).
/// t = 0 is the image's top row, as glTF and OpenImageIO have it (OBJ's v runs upwards:
/// its loader flips it).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>

#include "runtime/base/vec3.h"

namespace crex {

/// What lies outside [0, 1) in s or t.
enum class TextureWrap { kRepeat, kClamp, kMirror, kBlack };

/// How texel values are decoded. kAuto: the sRGB curve is undone for colour parameters
/// (colour, specular colour, emission) read from 8-bit images, and nothing else.
enum class TextureColorSpace { kAuto, kSrgb, kLinear };

/// How a point between texels reads them: smoothly (interpolated, and filtered over the
/// pixel's footprint), or the nearest texel's value (glTF's magFilter NEAREST: pixel art and
/// lookup tables stay crisp when magnified).
enum class TextureFilter { kSmooth, kNearest };

/// Where the texture coordinates come from.
enum class TextureMapping {
    kUv,      ///< the mesh's per-vertex (u, v); shapes without them get (0, 0)
    kPlanar,  ///< an affine function of the hit position (scene coordinates)
};

std::string_view texture_wrap_name(TextureWrap w);
std::optional<TextureWrap> texture_wrap_from_name(std::string_view name);
std::string_view texture_filter_name(TextureFilter f);
std::optional<TextureFilter> texture_filter_from_name(std::string_view name);
std::string_view texture_color_space_name(TextureColorSpace c);
std::optional<TextureColorSpace> texture_color_space_from_name(std::string_view name);
std::string_view texture_mapping_name(TextureMapping m);
std::optional<TextureMapping> texture_mapping_from_name(std::string_view name);

/// A 2x3 affine map of texture coordinates: s = m[0] u + m[1] v + m[2], t = m[3] u + m[4] v + m[5].
using UvTransform = std::array<double, 6>;
inline constexpr UvTransform kIdentityUv{1, 0, 0, 0, 1, 0};

/// glTF's KHR_texture_transform: scale, then rotate by `rotation` radians, then offset, as
/// one matrix (T * R * S in the extension's words): s = c su u + s sv v + offset_u,
/// t = c sv v - s su u + offset_v, with c and s the rotation's cosine and sine.
UvTransform uv_transform_of(double offset_u, double offset_v, double rotation, double scale_u, double scale_v);

struct TextureRef {
    std::string file;   ///< image path (loaders resolve a relative one against the scene file's folder)
    std::string image;  ///< or: the name of an image embedded in the scene (Scene::images); then `file` is empty
    TextureColorSpace color_space = TextureColorSpace::kAuto;
    TextureWrap wrap_s = TextureWrap::kRepeat, wrap_t = TextureWrap::kRepeat;
    TextureFilter filter = TextureFilter::kSmooth;
    Vec3 scale{1, 1, 1};  ///< multiplies the texel (a scalar parameter uses scale.x)
    double power = 1;     ///< after scale (glTF roughness: 2, its perceptual roughness squared)
    int channel = 0;      ///< first channel read: a colour reads 3 from it, a scalar 1
    /// Read the image's alpha channel where it has one (RGBA, grey and alpha, an EXR's A),
    /// `channel` where it has none: glTF's opacity (channel 3: none, so opaque), MTL's
    /// `-imfchan m`, its default for scalar maps (channel 0: a grey or RGB mask's first).
    bool prefer_alpha = false;
    UvTransform uv_transform = kIdentityUv;
    TextureMapping mapping = TextureMapping::kUv;
    /// kPlanar: u = planar[0..2] . P + planar[3], v = planar[4..6] . P + planar[7].
    std::array<double, 8> planar{1, 0, 0, 0, 0, 1, 0, 0};

    /// What identifies the image (file or embedded name), for messages and the census.
    const std::string& source() const { return file.empty() ? image : file; }
    bool operator==(const TextureRef&) const = default;
};

/// How a material's opacity texture cuts it out.
enum class AlphaMode {
    kMask,   ///< opacity below the cutoff is a hole (glTF MASK, OBJ map_d)
    kBlend,  ///< a hit is kept with probability = opacity (glTF BLEND: stochastic transparency)
};

/// A material's textured parameters; an empty slot keeps the constant.
struct MaterialTextures {
    std::optional<TextureRef> color;           ///< replaces Material::color (RGB)
    std::optional<TextureRef> specular_color;  ///< tints the specular lobe (RGB; white for plastic)
    std::optional<TextureRef> specularity;     ///< replaces Material::specularity
    std::optional<TextureRef> roughness;       ///< replaces Material::roughness (kept above 0: always G)
    std::optional<TextureRef> metallic;        ///< replaces Material::metallic
    std::optional<TextureRef> normal;          ///< tangent-space normal map (RGB in [0, 1] -> [-1, 1])
    std::optional<TextureRef> bump;            ///< height map; scale.x is the height of a texel of 1, in scene units
    std::optional<TextureRef> opacity;         ///< replaces Material::opacity (cut-outs)
    std::optional<TextureRef> emission;        ///< replaces Material::emission (RGB radiance)

    bool any() const {
        return color || specular_color || specularity || roughness || metallic || normal || bump || opacity || emission;
    }
    /// Calls f(slot name, reference) for every filled slot, in a fixed order.
    template <class F>
    void for_each(F&& f) const {
        if (color) f("color", *color);
        if (specular_color) f("specular_color", *specular_color);
        if (specularity) f("specularity", *specularity);
        if (roughness) f("roughness", *roughness);
        if (metallic) f("metallic", *metallic);
        if (normal) f("normal_map", *normal);
        if (bump) f("bump_map", *bump);
        if (opacity) f("opacity", *opacity);
        if (emission) f("emission", *emission);
    }
    bool operator==(const MaterialTextures&) const = default;
};

/// An image carried inside the scene (glTF data URIs and GLB buffer views): its encoded bytes
/// (PNG, JPEG, ...), read by the renderer as if they were a file.
struct EmbeddedImage {
    std::string name;      ///< what texture references use; "scene.glb#image3"
    std::string mime_type;
    std::string bytes;
};

}  // namespace crex
