/// \file surface.h
/// What a hit's surface is, beyond its material's constants: the mesh's interpolated shading
/// normal and texture coordinates, the pixel's footprint there (so texture lookups filter
/// over what one pixel sees: a 1-spp preview does not alias), its textures' values and
/// normal or bump map, and cut-outs (alpha textures) for Embree. Every place that shades a
/// hit (bins, oracle, irradiance cache, photons) asks surface_at() for its Bsdf.
#pragma once

#include <embree3/rtcore.h>

#include "runtime/render/bsdf.h"
#include "runtime/scene/scene.h"
#include "runtime/texture/surface_textures.h"
#include "runtime/trace/embree_scene.h"

namespace crex {

struct RenderScene;

/// The pixel footprint of a pinhole camera at any point, as pbrt-v4 approximates it for
/// every hit (camera rays and deeper ones alike): where the rays through the neighbouring
/// pixels, one pixel right and one down, meet the tangent plane of the point. The footprint
/// does not shrink with more samples per pixel, so a textured pixel reads the same filtered
/// value at 1 spp as at 64 (selective rendering gives pixels very different counts).
class PixelFootprint {
public:
    PixelFootprint() = default;
    /// `eye` in local coordinates (the camera's position minus the scene's origin offset).
    PixelFootprint(const Camera& camera, int width, int height, const Vec3& eye, double pixels = 1);
    bool valid() const { return valid_; }
    /// dp/dx and dp/dy at `p` (local) on the plane with unit normal `n`; zero when unknown.
    void at(const Vec3& p, const Vec3& n, Vec3& dpdx, Vec3& dpdy) const;

private:
    Vec3 eye_, forward_, right_step_, down_step_;
    bool valid_ = false;
};

/// Cut-outs for Embree: a hit on a material with an opacity texture (or a constant opacity
/// below 1) is a hole where the opacity is below the material's cutoff (alpha mode mask), or
/// with probability 1 - opacity (blend, decided by a hash of the ray and the hit, so the same
/// ray always meets the same holes). A hit on a material an antimatter clips (Material::clips)
/// is a hole inside the antimatter's solid.
class SceneCutouts final : public CutoutTest {
public:
    /// `textures` may be null (a scene with antimatter and no textures).
    SceneCutouts(const Scene& scene, const SurfaceTextures* textures);
    /// Whether any material cuts holes (else the scene needs no filter).
    bool any() const;
    void attach(const EmbreeScene& embree) { embree_ = &embree; }
    bool cuts_out(uint32_t material) const override {
        return (textures_ && textures_->cuts_out(material)) || (material < clipped_by_.size() && !clipped_by_[material].empty());
    }
    bool solid(uint32_t geometry, uint32_t prim, float u, float v, const Vec3& origin, const Vec3& dir, float t) const override;

private:
    /// An antimatter's solid: its shapes' triangles (world coordinates) and their bounds.
    struct Solid {
        std::vector<std::array<Vec3, 3>> triangles;
        Vec3 lo, hi;
        /// Inside by the parity of crossings along a fixed direction.
        bool inside(const Vec3& p) const;
    };
    const Scene& scene_;
    const SurfaceTextures* textures_;
    const EmbreeScene* embree_ = nullptr;
    std::vector<Solid> solids_;
    std::vector<std::vector<uint32_t>> clipped_by_;  ///< per material: the solids that remove it
};

/// The surface at Embree's `hit`, whose frame `f` hit_frame() made: sets f.shading (the
/// mesh's vertex normal, then its normal or bump map) and returns the Bsdf to shade with:
/// the material's prepared one, or one made in `scratch` from its textures' values there.
/// A hit the camera sees (directly or through mirrors and glass) reads its textures through
/// the full filter; any other through a cheaper one (TextureLookup::indirect); a hit whose
/// light is averaged with hundreds of others' (an irradiance record's hemisphere ray, a
/// photon) from each image's coarse copy (SurfacePoint::coarse).
enum class SurfaceDetail { kSeen, kIndirect, kAveraged };
const Bsdf& surface_at(const RenderScene& scene, const RTCHit& hit, HitFrame& f, Bsdf& scratch, SurfaceDetail detail);

/// The mesh's texture coordinates (u, v) at barycentrics (b1, b2) of its triangle t.
void interpolate_uv(const GeometryInfo& g, const std::array<uint32_t, 3>& t, double b1, double b2, double& u, double& v);

/// True when `hit` is on the front of an illum (seen as its alternate material). Direct
/// lighting already brings its light, so rays other than camera rays and rays from ideal
/// specular lobes (diffuse and glossy bounces, the cache's hemisphere rays) must take
/// nothing from there and end, as RADIANCE discards them (source.c's badcomponent) and as
/// crex treats a `light`; only the others see the alternate. Without this the window of a
/// mkillum scene lit the room twice: as an illum, and as the sky through its glass.
bool illum_front(const RenderScene& scene, const RTCHit& hit, const HitFrame& f);

}  // namespace crex
