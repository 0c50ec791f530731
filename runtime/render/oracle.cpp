#include "runtime/render/oracle.h"

#include <tbb/parallel_for.h>

#include "runtime/render/camera_samples.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/shade.h"
#include "runtime/trace/trace_batch.h"

namespace crex {
namespace {

struct Oracle {
    const RenderScene& scene;
    const ShadeParams& params;

    Vec3 trace(const RayRecord& ray, bool camera) const {
        RTCRayHit h{};
        h.ray.org_x = static_cast<float>(ray.origin.x), h.ray.org_y = static_cast<float>(ray.origin.y);
        h.ray.org_z = static_cast<float>(ray.origin.z);
        h.ray.dir_x = static_cast<float>(ray.direction.x), h.ray.dir_y = static_cast<float>(ray.direction.y);
        h.ray.dir_z = static_cast<float>(ray.direction.z);
        h.ray.tnear = 0;
        h.ray.tfar = INFINITY;
        h.ray.mask = 0xFFFFFFFFu;
        h.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        h.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        intersect_batch(*scene.embree, &h, 1, camera);  // the same traversal flags as the bins
        // Rays are stored as float in bins: use the same rounded values here.
        RayRecord r = ray;
        r.origin = {h.ray.org_x, h.ray.org_y, h.ray.org_z};
        r.direction = {h.ray.dir_x, h.ray.dir_y, h.ray.dir_z};
        r.beta = {static_cast<float>(ray.beta.x), static_cast<float>(ray.beta.y), static_cast<float>(ray.beta.z)};
        if (h.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
            Vec3 seen = scene.scene.background;
            if (camera || (r.flags & kRayFromDeltaLobe)) seen += scene.lights->distant().escaped(normalize_or_zero(r.direction));
            return r.beta * seen;
        }
        Vec3 dir = normalize_or_zero(r.direction);
        double t = h.ray.tfar;
        HitFrame f = hit_frame(*scene.embree, h.hit, r.origin + r.direction * t, dir, t);
        if (!camera && !(r.flags & kRayFromDeltaLobe) && illum_front(scene, h.hit, f)) return {};  // direct lighting's
        Bsdf textured;
        const Bsdf& b = surface_at(scene, h.hit, f, textured, surface_detail(camera, r.flags));
        const HitRandom random = hit_random(r, camera);
        Vec3 total = r.beta * emitted(b, f, camera || (r.flags & kRayFromDeltaLobe), camera);
        if (!is_finite(total)) total = {};
        if (!scene.lights->empty() && b.direct_response) {
            const HitLighting lighting = hit_lighting(params, r, camera);
            const LightSampler::LocalWeights weights = scene.lights->weights_at(f.position, horizon_of(b, f));
            auto light = [&](const ShadowSample& sample) {
                RTCRay s{};
                s.mask = 0xFFFFFFFFu;
                aim_shadow_ray(s, sample);
                const uint8_t weak = sample.weak_target;
                Vec3 through;
                trace_shadow_rays(scene, &s, &weak, &through, 1);
                total += sample.value * through;
            };
            ShadowSample sample;
            for (uint32_t j = 0; j < lighting.shadow_rays; ++j)
                if (direct_light_sample(scene, b, f, weights, r.beta, random, j, lighting.shadow_rays, sample, lighting.sampling)) light(sample);
            if (weighs_glossy_light(b, weights, lighting.sampling) &&
                glossy_light_sample(scene, b, f, weights, r.beta, random, lighting.shadow_rays, sample))
                light(sample);
        }
        SpawnScratch spawn;
        int n = spawn_children(b, f, r, random, params, spawn);
        for (int l = 0; l < n; ++l) total += trace(spawn.children[static_cast<size_t>(l)], false);
        return total;
    }
};

}  // namespace

std::vector<float> render_oracle(const Scene& scene, const OracleOptions& options) {
    RenderScene rs(scene);
    rs.set_view(options.width, options.height);
    CameraRays camera(scene.camera, options.width, options.height, rs.embree->origin_offset());
    size_t pixels = static_cast<size_t>(options.width) * static_cast<size_t>(options.height);
    std::vector<float> image(3 * pixels, 0.0f);
    Oracle oracle{rs, options.shade};
    tbb::parallel_for(size_t{0}, pixels, [&](size_t p) {
        uint32_t x = static_cast<uint32_t>(p % static_cast<size_t>(options.width));
        uint32_t y = static_cast<uint32_t>(p / static_cast<size_t>(options.width));
        Vec3 sum;
        for (uint32_t k = options.first_sample; k < options.first_sample + options.spp; ++k) {
            double u, v;
            camera_sample_offset(options.seed, static_cast<uint32_t>(p), k, u, v);
            RayRecord r;
            if (!camera.generate(x + u, y + v, r.origin, r.direction)) continue;  // outside a fisheye's circle: black
            r.beta = {1, 1, 1};
            r.pixel = static_cast<uint32_t>(p);
            r.path = camera_path_id(options.seed, static_cast<uint32_t>(p), k);
            sum += oracle.trace(r, true);
        }
        sum = sum / options.spp;
        image[3 * p] = static_cast<float>(sum.x);
        image[3 * p + 1] = static_cast<float>(sum.y);
        image[3 * p + 2] = static_cast<float>(sum.z);
    });
    return image;
}

}  // namespace crex
