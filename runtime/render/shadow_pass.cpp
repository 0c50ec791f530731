#include "runtime/render/shadow_pass.h"

#include "runtime/render/shade.h"
#include "runtime/render/surface.h"

namespace crex {

Vec3 SurfaceShadowPass::transmittance(const RTCHit& hit, const Vec3& origin, const Vec3& dir, double t, bool weak_target) const {
    const GeometryInfo& g = scene_.embree->geometries()[hit.geomID];
    // RADIANCE's illumblock: an illum passing a glow's light on would count it twice.
    if (weak_target && scene_.scene.materials[g.emitter].type == MaterialType::kIllum) return {};
    HitFrame f = hit_frame(*scene_.embree, hit, origin + dir * t, dir, t);
    Bsdf scratch;
    // The full filter: what a pane passes shows as the pattern of its shadow on what is seen.
    return shadow_transmittance(surface_at(scene_, hit, f, scratch, SurfaceDetail::kSeen), f);
}

void trace_shadow_rays(const RenderScene& scene, RTCRay* rays, const uint8_t* weak_target, Vec3* through, size_t count) {
    const SurfaceShadowPass pass(scene);
    occluded_batch(*scene.embree, rays, count, &pass, weak_target, through);
}

void trace_shadow_rays_in_this_task(const RenderScene& scene, RTCRay* rays, const uint8_t* weak_target, Vec3* through, size_t count) {
    const SurfaceShadowPass pass(scene);
    occluded_serial(*scene.embree, rays, count, &pass, weak_target, through);
}

}  // namespace crex
