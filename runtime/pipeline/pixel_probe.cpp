#include "runtime/pipeline/pixel_probe.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "runtime/trace/trace_batch.h"

namespace crex {
namespace {

RTCRayHit make_ray(const Vec3& o, const Vec3& d, unsigned id) {
    RTCRayHit h{};
    set_ray(h, static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z), static_cast<float>(d.x),
            static_cast<float>(d.y), static_cast<float>(d.z), id);
    return h;
}

}  // namespace

PixelProbe probe_pixels(const RenderScene& scene, int width, int height, int mirror_bounces) {
    std::vector<int> xs(static_cast<size_t>(std::max(width, 0))), ys(static_cast<size_t>(std::max(height, 0)));
    for (size_t x = 0; x < xs.size(); ++x) xs[x] = static_cast<int>(x);
    for (size_t y = 0; y < ys.size(); ++y) ys[y] = static_cast<int>(y);
    return probe_pixels(scene, width, height, xs, ys, mirror_bounces);
}

PixelProbe probe_pixels(const RenderScene& scene, int width, int height, const std::vector<int>& xs, const std::vector<int>& ys,
                        int mirror_bounces) {
    PixelProbe probe;
    probe.width = static_cast<int>(xs.size()), probe.height = static_cast<int>(ys.size());
    const size_t n = xs.size() * ys.size();
    probe.shape.assign(n, -1);
    probe.detected.assign(n, -1);
    probe.distance.assign(n, std::numeric_limits<float>::infinity());
    probe.normal.assign(n, Vec3{});
    const CameraRays camera(scene.scene.camera, width, height, scene.embree->origin_offset());
    // Blocks of neighbouring pixels, each traced to the end on one thread: their rays stay
    // coherent and in cache, and nothing is shared between blocks (this ran single-threaded
    // over the whole frame and was most of a short pipeline's guidance).
    constexpr size_t kBlock = 1024;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kBlock), [&](const tbb::blocked_range<size_t>& range) {
        std::vector<size_t> active, next;
        std::vector<Vec3> origin(range.size()), dir(range.size());
        std::vector<RTCRayHit> batch;
        for (size_t p = range.begin(); p < range.end(); ++p) {
            // A pixel outside a fisheye's circle sees nothing.
            const size_t i = p - range.begin();
            if (camera.generate(static_cast<double>(xs[p % xs.size()]) + 0.5, static_cast<double>(ys[p / xs.size()]) + 0.5, origin[i],
                                dir[i]))
                active.push_back(i);
        }
        for (int bounce = 0; bounce <= mirror_bounces && !active.empty(); ++bounce) {
            batch.resize(active.size());
            for (size_t k = 0; k < active.size(); ++k) batch[k] = make_ray(origin[active[k]], dir[active[k]], static_cast<unsigned>(k));
            intersect_batch(*scene.embree, batch.data(), batch.size(), bounce == 0);  // one chunk: kBlock is trace_batch's
            next.clear();
            for (size_t k = 0; k < active.size(); ++k) {
                const size_t i = active[k], p = range.begin() + i;
                const RTCRayHit& h = batch[k];
                if (h.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
                const GeometryInfo& g = scene.embree->geometries()[h.hit.geomID];
                const int32_t shape = static_cast<int32_t>(g.shape);
                const Vec3 ng = normalize_or_zero(Vec3{h.hit.Ng_x, h.hit.Ng_y, h.hit.Ng_z});
                if (bounce == 0) {
                    probe.shape[p] = shape, probe.distance[p] = h.ray.tfar;
                    probe.normal[p] = dot(ng, dir[i]) > 0 ? -ng : ng;
                }
                probe.detected[p] = shape;
                if (scene.material_of(h.hit.geomID).type != MaterialType::kMirror || ng == Vec3{}) continue;
                // Continue as the mirror's reflection.
                const Vec3 d = dir[i];
                const Vec3 hit = origin[i] + d * static_cast<double>(h.ray.tfar);
                const Vec3 r = d - ng * (2 * dot(d, ng));
                origin[i] = hit + ng * (dot(r, ng) > 0 ? 1.0 : -1.0) * scene.embree->epsilon_at(hit, h.ray.tfar);
                dir[i] = normalize_or_zero(r);
                next.push_back(i);
            }
            std::swap(active, next);
        }
    });
    return probe;
}

}  // namespace crex
