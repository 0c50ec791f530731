/// \file shadow_pass.h
/// Shadow rays in crex: the sample direct lighting makes (ShadowSample), what thin glass and
/// trans surfaces let through to it (RADIANCE's glass and trans pass shadow rays: the light
/// goes straight on, so the ray stays aimed at its emitter), and the one call every direct
/// lighting estimate traces its shadow rays with.
#pragma once

#include <cstddef>
#include <cstdint>

#include "runtime/render/render_scene.h"
#include "runtime/trace/trace_batch.h"

namespace crex {

/// A shadow ray to trace and the light it brings (beta included) if nothing blocks it.
struct ShadowSample {
    Vec3 value, origin, direction;
    double tfar = 0;
    bool weak_target = false;  ///< aimed at a glow or an illum (LightSample::weak)
};

inline void aim_shadow_ray(RTCRay& s, const ShadowSample& sample) { aim_shadow_ray(s, sample.origin, sample.direction, sample.tfar); }

/// trace's ShadowPass over the scene's surfaces: thin glass and trans let through their
/// straight T lobe's weight at the hit (textures included); an illum blocks rays aimed at glows
/// and illums (it stands for what lies behind it) and lets those to a `light` through as its
/// alternate material does.
class SurfaceShadowPass final : public ShadowPass {
public:
    explicit SurfaceShadowPass(const RenderScene& scene) : scene_(scene) {}
    Vec3 transmittance(const RTCHit& hit, const Vec3& origin, const Vec3& dir, double t, bool weak_target) const override;

private:
    const RenderScene& scene_;
};

/// Traces `count` shadow rays; through[k] becomes what reaches the end of ray k: 0 where it is
/// blocked, else the product of what the surfaces it crossed let through (1 for none, and for
/// holes, tnear > tfar). `weak_target` may be null (no ray aimed at a glow or an illum).
void trace_shadow_rays(const RenderScene& scene, RTCRay* rays, const uint8_t* weak_target, Vec3* through, size_t count);
/// The same in the calling task alone (no nested parallel loop): for callers that are one of
/// many tasks already, each tracing its own few rays.
void trace_shadow_rays_in_this_task(const RenderScene& scene, RTCRay* rays, const uint8_t* weak_target, Vec3* through, size_t count);

}  // namespace crex
