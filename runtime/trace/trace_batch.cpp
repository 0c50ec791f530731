#include "runtime/trace/trace_batch.h"

#include <tbb/parallel_for.h>

namespace crex {
namespace {

constexpr size_t kBlock = 1024;

}  // namespace

void intersect_batch(const EmbreeScene& scene, RTCRayHit* rays, size_t count, bool coherent) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kBlock), [&](const tbb::blocked_range<size_t>& r) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
        rtcIntersect1M(scene.handle(), &context, rays + r.begin(), static_cast<unsigned>(r.size()), sizeof(RTCRayHit));
    });
}

void occluded_batch(const EmbreeScene& scene, RTCRay* rays, size_t count) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kBlock), [&](const tbb::blocked_range<size_t>& r) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        rtcOccluded1M(scene.handle(), &context, rays + r.begin(), static_cast<unsigned>(r.size()), sizeof(RTCRay));
    });
}

}  // namespace crex
