#include "runtime/trace/trace_batch.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <vector>

namespace crex {
namespace {

constexpr size_t kBlock = 1024;

// A shadow ray crossing more surfaces that let it through than this is taken as blocked.
constexpr size_t kMaxCrossings = 8;

// What one shadow ray has crossed: Embree may report the same triangle twice (a triangle in
// two leaves of a BVH built with spatial splits), so each is counted once.
struct Crossings {
    Vec3 through{1, 1, 1};
    size_t count = 0;
    std::array<uint64_t, kMaxCrossings> seen{};
};

// Embree's context with occluded_batch()'s own data after it (Embree passes the pointer it was
// given to the filter, which casts it back). A ray's id is its index in the batch.
struct ShadowContext {
    RTCIntersectContext embree;
    const ShadowPass* pass = nullptr;
    const uint8_t* weak_target = nullptr;
    Crossings* crossings = nullptr;  // of the block
    size_t first = 0;                // the block's first ray
};

}  // namespace

void shadow_pass_filter(const RTCFilterFunctionNArguments* args) {
    const auto* context = reinterpret_cast<const ShadowContext*>(args->context);
    if (!context->pass) return;  // not asked: every surface blocks
    const unsigned n = args->N;
    for (unsigned i = 0; i < n; ++i) {
        if (args->valid[i] != -1) continue;
        const unsigned id = RTCRayN_id(args->ray, n, i);
        Crossings& c = context->crossings[id - context->first];
        RTCHit hit{};
        hit.geomID = RTCHitN_geomID(args->hit, n, i);
        hit.primID = RTCHitN_primID(args->hit, n, i);
        hit.u = RTCHitN_u(args->hit, n, i);
        hit.v = RTCHitN_v(args->hit, n, i);
        hit.Ng_x = RTCHitN_Ng_x(args->hit, n, i);
        hit.Ng_y = RTCHitN_Ng_y(args->hit, n, i);
        hit.Ng_z = RTCHitN_Ng_z(args->hit, n, i);
        hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        const uint64_t key = (uint64_t{hit.geomID} << 32) | hit.primID;
        if (std::find(c.seen.begin(), c.seen.begin() + static_cast<std::ptrdiff_t>(c.count), key) != c.seen.begin() + static_cast<std::ptrdiff_t>(c.count)) {
            args->valid[i] = 0;  // crossed already
            continue;
        }
        if (c.count == kMaxCrossings) continue;
        const Vec3 origin{RTCRayN_org_x(args->ray, n, i), RTCRayN_org_y(args->ray, n, i), RTCRayN_org_z(args->ray, n, i)};
        const Vec3 dir{RTCRayN_dir_x(args->ray, n, i), RTCRayN_dir_y(args->ray, n, i), RTCRayN_dir_z(args->ray, n, i)};
        const bool weak = context->weak_target && context->weak_target[id];
        const Vec3 t = context->pass->transmittance(hit, origin, dir, RTCRayN_tfar(args->ray, n, i), weak);
        if (!(max_component(t) > 0) || !is_finite(t)) continue;  // it blocks the ray
        c.through = c.through * t;
        c.seen[c.count++] = key;
        if (max_component(c.through) > 1e-12) args->valid[i] = 0;  // on through it
    }
}

void intersect_serial(const EmbreeScene& scene, RTCRayHit* rays, size_t count, bool coherent) {
    if (count == 0) return;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    rtcIntersect1M(scene.handle(), &context, rays, static_cast<unsigned>(count), sizeof(RTCRayHit));
}

void intersect_batch(const EmbreeScene& scene, RTCRayHit* rays, size_t count, bool coherent) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kBlock), [&](const tbb::blocked_range<size_t>& r) {
        intersect_serial(scene, rays + r.begin(), r.size(), coherent);
    });
}

namespace {

// Rays [begin, end) of a batch (ids are indices into it, for the filter's context).
void occluded_block(const EmbreeScene& scene, RTCRay* rays, size_t begin, size_t end, const ShadowPass* pass, const uint8_t* weak_target,
                    Vec3* through) {
    const bool passing = pass && scene.any_shadow_passes();
    ShadowContext context;
    rtcInitIntersectContext(&context.embree);
    // Each thread's crossings, kept from block to block. Not a thread_local: the first touch of
    // one with a destructor takes the dynamic loader's lock, so a render's first shadow rays
    // would wait out the image plugin's load (preload_image_plugin) on another thread.
    static tbb::enumerable_thread_specific<std::vector<Crossings>> per_thread;
    Crossings* crossings = nullptr;
    if (passing) {
        std::vector<Crossings>& mine = per_thread.local();
        mine.assign(end - begin, Crossings{});
        crossings = mine.data();
        for (size_t k = begin; k < end; ++k) rays[k].id = static_cast<unsigned>(k);
        context.pass = pass;
        context.weak_target = weak_target;
        context.crossings = crossings;
        context.first = begin;
    }
    rtcOccluded1M(scene.handle(), &context.embree, rays + begin, static_cast<unsigned>(end - begin), sizeof(RTCRay));
    if (through)
        for (size_t k = begin; k < end; ++k)
            through[k] = rays[k].tfar == -INFINITY ? Vec3{} : crossings ? crossings[k - begin].through : Vec3{1, 1, 1};
}

}  // namespace

void occluded_batch(const EmbreeScene& scene, RTCRay* rays, size_t count, const ShadowPass* pass, const uint8_t* weak_target,
                    Vec3* through) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kBlock), [&](const tbb::blocked_range<size_t>& r) {
        occluded_block(scene, rays, r.begin(), r.end(), pass, weak_target, through);
    });
}

void occluded_serial(const EmbreeScene& scene, RTCRay* rays, size_t count, const ShadowPass* pass, const uint8_t* weak_target,
                     Vec3* through) {
    for (size_t begin = 0; begin < count; begin += kBlock) occluded_block(scene, rays, begin, std::min(count, begin + kBlock), pass, weak_target, through);
}

}  // namespace crex
