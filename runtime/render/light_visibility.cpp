#include "runtime/render/light_visibility.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "runtime/base/sampling.h"
#include "runtime/render/shade.h"
#include "runtime/render/shadow_pass.h"
#include "runtime/render/surface.h"
#include "runtime/trace/trace_batch.h"

namespace crex {
namespace {

constexpr int kGrid = 32;            // camera rays across and down
constexpr uint32_t kDirections = 4;  // shadow rays per source at each surface

}  // namespace

std::vector<double> distant_visibility(const RenderScene& scene, int width, int height) {
    const DistantEmitters& distant = scene.lights->distant();
    const size_t sources = distant.size();
    if (sources == 0 || width <= 0 || height <= 0) return std::vector<double>(sources, 1.0);
    const CameraRays camera(scene.scene.camera, width, height, scene.embree->origin_offset());
    const size_t n = static_cast<size_t>(kGrid) * kGrid;
    std::vector<RTCRayHit> hits(n);
    std::vector<uint8_t> aimed(n, 0);
    for (size_t p = 0; p < n; ++p) {
        const double px = (static_cast<double>(p % kGrid) + 0.5) * width / kGrid, py = (static_cast<double>(p / kGrid) + 0.5) * height / kGrid;
        Vec3 o, d;
        hits[p] = RTCRayHit{};
        hits[p].ray.tnear = 1.0f, hits[p].ray.tfar = 0.0f;  // a hole unless the camera has this ray
        hits[p].hit.geomID = RTC_INVALID_GEOMETRY_ID;
        if (!camera.generate(px, py, o, d)) continue;
        set_ray(hits[p], static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z), static_cast<float>(d.x),
                static_cast<float>(d.y), static_cast<float>(d.z), static_cast<unsigned>(p));
        aimed[p] = 1;
    }
    intersect_batch(*scene.embree, hits.data(), n, true);

    // Shadow rays from each surface hit (not mirrors or glass: light passes those by other
    // paths), into the surface's own hemisphere, where the source's light can be reflected,
    // and into the other one too where the surface transmits (a translucent window's outside).
    const size_t per = sources * kDirections;
    std::vector<RTCRay> shadows(n * per);
    std::vector<uint8_t> weak(n * per, 0);
    std::vector<Vec3> through(n * per);
    tbb::parallel_for(size_t{0}, n, [&](size_t p) {
        for (size_t k = 0; k < per; ++k) make_hole(shadows[p * per + k], static_cast<unsigned>(p));  // unless aimed
        const RTCRayHit& h = hits[p];
        if (!aimed[p] || h.hit.geomID == RTC_INVALID_GEOMETRY_ID || is_delta_material(scene.material_of(h.hit.geomID).type)) return;
        const Vec3 o{h.ray.org_x, h.ray.org_y, h.ray.org_z}, d{h.ray.dir_x, h.ray.dir_y, h.ray.dir_z};
        const HitFrame f = hit_frame(*scene.embree, h.hit, o + d * double(h.ray.tfar), d, h.ray.tfar);
        const Bsdf& b = scene.bsdf_of(h.hit.geomID);
        const bool transmits = positive(b.diffuse_transmit) || positive(b.specular_transmit) || positive(b.directional_transmit);
        for (size_t i = 0; i < sources; ++i)
            for (uint32_t k = 0; k < kDirections; ++k) {
                const uint64_t key = hash_combine(hash_combine(0x6c69676874ull, p), i * kDirections + k);
                Vec3 dir, radiance;
                double pdf = 0;
                distant.sample(i, to_unit(mix64(key)), to_unit(mix64(key + 1)), dir, radiance, pdf);
                const double side = dot(dir, f.normal);
                if (!(pdf > 0) || !(side > 0 || (transmits && side < 0))) continue;
                const size_t slot = p * per + i * kDirections + k;
                aim_shadow_ray(shadows[slot], f.position + (side > 0 ? f.normal : -f.normal) * f.epsilon, dir, INFINITY);
                weak[slot] = distant.weak(i);
            }
    });
    trace_shadow_rays(scene, shadows.data(), weak.data(), through.data(), shadows.size());

    std::vector<double> fraction(sources);
    for (size_t i = 0; i < sources; ++i) {
        double tested = 0, reached = 0;
        for (size_t p = 0; p < n; ++p)
            for (uint32_t k = 0; k < kDirections; ++k) {
                const size_t slot = p * per + i * kDirections + k;
                if (is_hole(shadows[slot])) continue;  // not aimed
                tested += 1;
                reached += std::clamp(max_component(through[slot]), 0.0, 1.0);
            }
        fraction[i] = (reached + 1) / (tested + 2);
    }
    return fraction;
}

}  // namespace crex
