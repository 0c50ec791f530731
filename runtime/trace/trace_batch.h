/// \file trace_batch.h
/// The only calls of Embree's ray-stream API in crex (Embree 4 removed streams: keep them
/// here). Batches are split into blocks traced in parallel with TBB.
#pragma once

#include <embree3/rtcore.h>

#include <cstddef>

#include "runtime/trace/embree_scene.h"

namespace crex {

/// Closest hits. `coherent` for camera rays. Rays with tnear > tfar are holes (inactive).
void intersect_batch(const EmbreeScene& scene, RTCRayHit* rays, size_t count, bool coherent);
/// Any hit: on return, tfar = -inf marks an occluded ray.
void occluded_batch(const EmbreeScene& scene, RTCRay* rays, size_t count);

}  // namespace crex
