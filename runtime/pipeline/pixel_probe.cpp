#include "runtime/pipeline/pixel_probe.h"

#include <cmath>
#include <limits>

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
    PixelProbe probe;
    probe.width = width, probe.height = height;
    size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
    probe.shape.assign(n, -1);
    probe.detected.assign(n, -1);
    probe.distance.assign(n, std::numeric_limits<float>::infinity());
    probe.normal.assign(n, Vec3{});
    CameraRays camera(scene.scene.camera, width, height, scene.embree->origin_offset());
    std::vector<Vec3> origin(n), dir(n);
    std::vector<size_t> active;
    active.reserve(n);
    for (size_t p = 0; p < n; ++p) {
        // A pixel outside a fisheye's circle sees nothing.
        if (camera.generate(static_cast<double>(p % static_cast<size_t>(width)) + 0.5,
                            static_cast<double>(p / static_cast<size_t>(width)) + 0.5, origin[p], dir[p]))
            active.push_back(p);
    }
    for (int bounce = 0; bounce <= mirror_bounces && !active.empty(); ++bounce) {
        std::vector<RTCRayHit> batch(active.size());
        for (size_t i = 0; i < active.size(); ++i) batch[i] = make_ray(origin[active[i]], dir[active[i]], static_cast<unsigned>(i));
        intersect_batch(*scene.embree, batch.data(), batch.size(), bounce == 0);
        std::vector<size_t> next;
        for (size_t i = 0; i < active.size(); ++i) {
            size_t p = active[i];
            const RTCRayHit& h = batch[i];
            if (h.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
            const GeometryInfo& g = scene.embree->geometries()[h.hit.geomID];
            int32_t shape = static_cast<int32_t>(g.shape);
            if (bounce == 0) {
                probe.shape[p] = shape, probe.distance[p] = h.ray.tfar;
                const Vec3 ng = normalize_or_zero(Vec3{h.hit.Ng_x, h.hit.Ng_y, h.hit.Ng_z});
                probe.normal[p] = dot(ng, dir[p]) > 0 ? -ng : ng;
            }
            probe.detected[p] = shape;
            if (scene.material_of(h.hit.geomID).type != MaterialType::kMirror) continue;
            // Continue as the mirror's reflection.
            Vec3 ng = normalize_or_zero(Vec3{h.hit.Ng_x, h.hit.Ng_y, h.hit.Ng_z});
            if (ng == Vec3{}) continue;
            Vec3 d = dir[p];
            Vec3 hit = origin[p] + d * static_cast<double>(h.ray.tfar);
            Vec3 r = d - ng * (2 * dot(d, ng));
            origin[p] = hit + ng * (dot(r, ng) > 0 ? 1.0 : -1.0) * scene.embree->ray_epsilon();
            dir[p] = normalize_or_zero(r);
            next.push_back(p);
        }
        active = std::move(next);
    }
    return probe;
}

}  // namespace crex
