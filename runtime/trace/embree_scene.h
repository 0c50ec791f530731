/// \file embree_scene.h
/// The scene in Embree 3: one geometry per shape (triangles, or a sphere point for spheres),
/// with what shading needs per geometry. The scene is translated so that its bounds are
/// centred at the origin before it is converted to float: a scene placed 1e6 units away keeps
/// the precision of one at the origin. All positions handed to and returned by the tracer are
/// in these *local* coordinates (world = local + origin_offset).
#pragma once

#include <embree3/rtcore.h>

#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "runtime/scene/scene.h"

namespace crex {

/// Decides, during traversal, whether a hit on a cut-out surface counts (alpha textures): a
/// hole is not a hit for any ray (camera, shadow, cache and photon rays alike). The renderer
/// implements it (runtime/render/surface.h); trace only calls it.
class CutoutTest {
public:
    virtual ~CutoutTest() = default;
    /// Does material `material` (an index into Scene::materials) ever cut holes?
    virtual bool cuts_out(uint32_t material) const = 0;
    /// False: the ray from `origin` along `dir` goes through geometry `geometry`'s primitive
    /// `prim` at barycentrics (u, v), distance t.
    virtual bool solid(uint32_t geometry, uint32_t prim, float u, float v, const Vec3& origin, const Vec3& dir, float t) const = 0;
};

/// Decides, during a shadow ray's traversal, what a surface that may let shadow rays through
/// (RADIANCE's thin glass, a trans surface's specular transmission: undeviated, so the ray
/// stays aimed at its emitter) lets through. The renderer implements it
/// (runtime/render/shadow_pass.h); trace only calls it, from occluded_batch().
class ShadowPass {
public:
    virtual ~ShadowPass() = default;
    /// What the surface at `hit` (its geomID, primID, u, v and Ng set) lets through for a shadow
    /// ray from `origin` along unit `dir` meeting it at distance t; zero: it blocks the ray.
    /// `weak_target`: the ray is aimed at a glow or an illum (which an illum in the way blocks).
    virtual Vec3 transmittance(const RTCHit& hit, const Vec3& origin, const Vec3& dir, double t, bool weak_target) const = 0;
};

/// What Embree's intersection filters need of one geometry (its user pointer): the cut-out test
/// of a material that cuts holes, and whether a ray meeting its back goes through (Scene::
/// back_faces_visible false).
struct GeometryFilter {
    const CutoutTest* cutouts = nullptr;
    bool hide_back = false;
    bool inward = false;  ///< a sphere whose front faces its centre
};

struct GeometryInfo {
    uint32_t shape = 0;     ///< index into Scene::shapes
    uint32_t material = 0;  ///< index into Scene::materials: what rays see (an illum's alternate)
    uint32_t emitter = 0;   ///< index into Scene::materials: what direct lighting samples (the shape's own)
    bool sphere = false;
    bool inward = false;    ///< sphere: the front faces the centre (RADIANCE bubble)
    bool may_pass_shadows = false;  ///< thin glass or trans (or an illum seen as one): asks a ShadowPass
    Vec3 center;            ///< sphere centre, local coordinates
    double radius = 0;
    std::vector<Vec3> positions;                   ///< triangles: local vertex positions
    std::vector<std::array<uint32_t, 3>> indices;  ///< triangles
    std::vector<Vec3> normals;  ///< triangles: unit geometric normal, zero when degenerate
    std::vector<std::array<float, 2>> uvs;  ///< meshes that have them: per vertex texture coordinates
    std::vector<Vec3> vertex_normals;        ///< meshes that have them: per vertex shading normals (unit)
    std::vector<std::array<float, 3>> colors;  ///< meshes that have them: per vertex colour (Shape::colors)
};

class EmbreeScene {
public:
    /// Builds and commits the BVH. Throws std::runtime_error with Embree's message on failure.
    /// With `cutouts`, geometries whose material cuts holes ask it about every hit.
    explicit EmbreeScene(const Scene& scene, const CutoutTest* cutouts = nullptr);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    RTCScene handle() const { return scene_; }
    const std::vector<GeometryInfo>& geometries() const { return geometries_; }
    /// Emitters no ray but a shadow ray sees (an illum without an alternate material): not in
    /// the BVH, sampled by direct lighting all the same.
    const std::vector<GeometryInfo>& hidden_emitters() const { return hidden_emitters_; }
    Vec3 origin_offset() const { return offset_; }
    /// Diagonal of the scene's bounds.
    double extent() const { return extent_; }
    /// How far a ray leaving local point p, reached along a ray of length t, is pushed off its
    /// surface (and how far short of a point it aims at a shadow ray stops): 17 to 34 float
    /// ulps of p's largest coordinate, about five times pbrt's bound on the error of a float
    /// triangle hit (7 gamma of its size), and 8 to 16 ulps of t for a point found along a ray,
    /// whatever the rest of the scene's size. An offset of 1e-5 of the whole scene's extent
    /// was 28 units in a 2-unit box beside a ground 2e6 across: no shadow ray in the box reached
    /// its lamp; 1e-5 of the box's own coordinates (about 5000 there, the scene's centre being
    /// far below) still left it 4 % dark.
    double epsilon_at(const Vec3& p, double t = 0) const {
        return 2e-6 * std::fmax(std::fabs(p.x), std::fmax(std::fabs(p.y), std::fabs(p.z))) + 1e-6 * std::fabs(t) + epsilon_floor_;
    }
    Vec3 bounds_min() const { return lo_; }
    Vec3 bounds_max() const { return hi_; }
    /// Some geometry may let shadow rays through (occluded_batch() then wants a ShadowPass).
    bool any_shadow_passes() const { return any_shadow_passes_; }

private:
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    std::vector<GeometryInfo> geometries_;
    std::vector<GeometryInfo> hidden_emitters_;
    std::vector<std::unique_ptr<GeometryFilter>> filters_;  ///< Embree holds pointers to them
    Vec3 offset_, lo_, hi_;
    double extent_ = 1, epsilon_floor_ = 1e-14;  // the floor: for a point at the local origin
    bool any_shadow_passes_ = false;
};

}  // namespace crex
