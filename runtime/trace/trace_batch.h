/// \file trace_batch.h
/// The only calls of Embree's ray-stream API in crex (Embree 4 removed streams: keep them
/// here). Batches are split into blocks traced in parallel with TBB.
#pragma once

#include <embree3/rtcore.h>

#include <cmath>
#include <cstddef>

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

/// Closest hits. `coherent` for camera rays. Rays with tnear > tfar are holes (inactive).
void intersect_batch(const EmbreeScene& scene, RTCRayHit* rays, size_t count, bool coherent);
/// Any hit: on return, tfar = -inf marks an occluded ray.
void occluded_batch(const EmbreeScene& scene, RTCRay* rays, size_t count);

}  // namespace crex
