/// \file trace_batch.h
/// The only calls of Embree's ray-stream API in crex (Embree 4 removed streams: keep them
/// here). Batches are split into blocks traced in parallel with TBB.
#pragma once

#include <embree3/rtcore.h>

#include <cmath>
#include <cstddef>

#include "runtime/base/vec3.h"
#include "runtime/trace/embree_scene.h"

namespace crex {

/// A closest-hit query from (ox, oy, oz) along (dx, dy, dz), [0, inf), no hit yet.
inline void set_ray(RTCRayHit& h, float ox, float oy, float oz, float dx, float dy, float dz, unsigned id) {
    h.ray.org_x = ox, h.ray.org_y = oy, h.ray.org_z = oz;
    h.ray.dir_x = dx, h.ray.dir_y = dy, h.ray.dir_z = dz;
    h.ray.tnear = 0.0f;
    h.ray.tfar = INFINITY;
    h.ray.time = 0;
    h.ray.mask = 0xFFFFFFFFu;
    h.ray.id = id;
    h.ray.flags = 0;
    h.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    h.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

/// Aims a shadow-ray slot (its mask, id and flags already set) from `o` along `d` over [0, tfar].
inline void aim_shadow_ray(RTCRay& s, const Vec3& o, const Vec3& d, double tfar) {
    s.org_x = static_cast<float>(o.x), s.org_y = static_cast<float>(o.y), s.org_z = static_cast<float>(o.z);
    s.dir_x = static_cast<float>(d.x), s.dir_y = static_cast<float>(d.y), s.dir_z = static_cast<float>(d.z);
    s.tnear = 0.0f;
    s.tfar = static_cast<float>(tfar);
}

/// An empty shadow-ray slot: tnear > tfar, so Embree skips it.
inline void make_hole(RTCRay& s, unsigned id) {
    s.tnear = 1.0f;
    s.tfar = 0.0f;
    s.org_x = s.org_y = s.org_z = 0;
    s.dir_x = 0, s.dir_y = 0, s.dir_z = 1;
    s.mask = 0xFFFFFFFFu;
    s.flags = 0;
    s.time = 0;
    s.id = id;
}
inline bool is_hole(const RTCRay& s) { return s.tnear > s.tfar && s.tfar == 0.0f; }

/// Closest hits. `coherent` for camera rays. Rays with tnear > tfar are holes (inactive).
void intersect_batch(const EmbreeScene& scene, RTCRayHit* rays, size_t count, bool coherent);
/// intersect_batch() in the calling thread (one stream): for a task that goes on to shade them.
void intersect_serial(const EmbreeScene& scene, RTCRayHit* rays, size_t count, bool coherent);
/// Any hit: on return, tfar = -inf marks an occluded ray. With `pass` (and a scene where some
/// surface may let shadow rays through), those surfaces block a ray only where `pass` says so;
/// `through[k]` (when given) receives what the ones ray k crossed let through (1 for none, 0
/// when occluded). `weak_target[k]` (optional): ray k is aimed at a glow or an illum. The rays'
/// ids are overwritten.
void occluded_batch(const EmbreeScene& scene, RTCRay* rays, size_t count, const ShadowPass* pass = nullptr,
                    const uint8_t* weak_target = nullptr, Vec3* through = nullptr);

/// occluded_batch() in the calling thread, in blocks one after the other.
void occluded_serial(const EmbreeScene& scene, RTCRay* rays, size_t count, const ShadowPass* pass = nullptr,
                     const uint8_t* weak_target = nullptr, Vec3* through = nullptr);

/// Embree's occluded filter for surfaces that may let shadow rays through (EmbreeScene
/// installs it; it reads occluded_batch()'s context).
void shadow_pass_filter(const RTCFilterFunctionNArguments* args);

}  // namespace crex
