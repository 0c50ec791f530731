#include "runtime/render/shade.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "runtime/base/sampling.h"
#include "runtime/trace/trace_batch.h"

namespace crex {

HitFrame hit_frame(const EmbreeScene& scene, uint32_t geom, uint32_t prim, double u, double v, const Vec3& approx,
                   const Vec3& dir, double t) {
    const GeometryInfo& g = scene.geometries()[geom];
    HitFrame f;
    if (g.sphere) {
        Vec3 n = normalize_or_zero(approx - g.center);
        if (n == Vec3{}) n = -dir;
        f.geometric = n;
        f.position = g.center + n * g.radius;  // back onto the surface: float error does not accumulate
    } else {
        const auto& tri = g.indices[prim];
        const Vec3 &p0 = g.positions[tri[0]], &p1 = g.positions[tri[1]], &p2 = g.positions[tri[2]];
        f.geometric = normalize_or_zero(cross(p1 - p0, p2 - p0));
        if (f.geometric == Vec3{}) f.geometric = -dir;
        f.position = p0 * (1 - u - v) + p1 * u + p2 * v;
    }
    f.incoming = dir;
    f.front = dot(dir, f.geometric) < 0;
    f.normal = f.front ? f.geometric : -f.geometric;
    f.distance = t;
    return f;
}

int spawn_children(const Material& m, const HitFrame& f, const RayRecord& ray, double epsilon, const ShadeParams& params,
                   std::array<RayRecord, kMaxLobes>& slots, std::array<Component, kMaxLobes>& components) {
    std::array<Lobe, kMaxLobes> lobes;
    int n = scatter(m, f, ray.path, ray.depth, lobes);
    int out = 0;
    if (ray.depth + 1u > params.max_depth) return 0;
    double st = params.specular_threshold_per_pixel ? (*params.specular_threshold_per_pixel)[ray.pixel] : params.specular_threshold;
    for (int l = 0; l < n; ++l) {
        const Lobe& lobe_l = lobes[static_cast<size_t>(l)];
        // The specular threshold (RADIANCE -st, thesis 5.7): weak specular reflections are not sampled.
        if (st > 0 && (lobe_l.component == Component::kS || lobe_l.component == Component::kG) &&
            max_component(lobe_l.weight) < st)
            continue;
        Vec3 beta = ray.beta * lobe_l.weight;
        double mx = max_component(beta);
        if (!(mx > 0) || !is_finite(beta)) continue;
        if (mx < params.weight_limit) {
            if (!params.roulette) continue;
            double q = mx / params.weight_limit;  // survive with probability q, re-weighted by 1/q
            if (random_at(ray.path, ray.depth, RandomUse::kRoulette, static_cast<uint32_t>(l)) >= q) continue;
            beta = beta / q;
        }
        const Lobe& lobe = lobes[static_cast<size_t>(l)];
        RayRecord& c = slots[static_cast<size_t>(out)];
        c.origin = f.position + (lobe.transmits ? -f.normal : f.normal) * epsilon;
        c.direction = lobe.direction;
        if (params.ic_queries && lobe.component == Component::kD) {
            c.origin = f.position;
            c.direction = lobe.transmits ? -f.normal : f.normal;
        }
        c.beta = beta;
        c.pixel = ray.pixel;
        c.depth = static_cast<uint16_t>(ray.depth + 1);
        c.flags = lobe.delta ? kRayFromDeltaLobe : 0;
        if (params.ic_queries && lobe.component == Component::kD) c.flags = kRayIcQuery;
        c.path = child_path(ray.path, l, lobe.component);
        components[static_cast<size_t>(out)] = lobe.component;
        ++out;
    }
    return out;
}

bool direct_light_sample(const RenderScene& scene, const Material& m, const HitFrame& f, const RayRecord& ray, uint32_t j,
                         uint32_t n, Vec3& value, Vec3& shadow_origin, Vec3& shadow_dir, double& shadow_tfar) {
    // Low-discrepancy over the n samples of this hit: a rotated Halton set for the point on
    // the emitter, stratified picks between emitters.
    double u, v;
    rotated_halton(j, random_at(ray.path, ray.depth, RandomUse::kLight, 0), random_at(ray.path, ray.depth, RandomUse::kLight, 1),
                   u, v);
    double pick = (j + random_at(ray.path, ray.depth, RandomUse::kLightPick, j)) / n;
    LightSample ls = scene.lights->sample(pick, u, v);
    Vec3 to = ls.position - f.position;
    double d2 = dot(to, to);
    if (!(d2 > 0) || !(ls.pdf_area > 0)) return false;
    double dist = std::sqrt(d2);
    Vec3 wi = to / dist;
    double cos_l = -dot(ls.normal, wi);
    if (cos_l <= 0) return false;  // emitters radiate from their front side only
    Vec3 fr = eval_direct(m, f, wi);
    if (!(max_component(fr) > 0)) return false;
    value = ray.beta * fr * ls.radiance * (cos_l / (d2 * ls.pdf_area * n));
    if (!is_finite(value)) return false;
    double eps = scene.embree->ray_epsilon();
    shadow_origin = f.position + (dot(wi, f.geometric) > 0 ? f.geometric : -f.geometric) * eps;
    shadow_dir = wi;
    shadow_tfar = length(ls.position - shadow_origin) - 2 * eps;
    return shadow_tfar > 0;
}

void trace_and_shade(const RenderScene& scene, const RayBatch& rays, size_t begin, size_t end, bool camera,
                     const ShadeParams& params, ShadeOutput& out) {
    const size_t n = end - begin;
    const uint32_t ns = params.shadow_rays;
    const double eps = scene.embree->ray_epsilon();
    out.reset();
    ShadeScratch& scratch = out.scratch;
    scratch.hits.resize(n);
    std::vector<RTCRayHit>& hits = scratch.hits;
    for (size_t i = 0; i < n; ++i) {
        size_t r = begin + i;
        set_ray(hits[i], rays.ox[r], rays.oy[r], rays.oz[r], rays.dx[r], rays.dy[r], rays.dz[r], static_cast<unsigned>(i));
    }
    if (params.capture) params.capture->rays.insert(params.capture->rays.end(), hits.begin(), hits.end());
    intersect_batch(*scene.embree, hits.data(), n, camera);

    out.contribution.assign(n, Vec3{});
    if (camera) out.emission.assign(n, Vec3{});
    scratch.shadows.resize(n * ns);
    scratch.shadow_value.resize(n * ns);
    scratch.child_slots.resize(n * kMaxLobes);
    scratch.child_components.resize(n);
    scratch.child_count.assign(n, 0);
    std::vector<RTCRay>& shadows = scratch.shadows;
    std::vector<Vec3>& shadow_value = scratch.shadow_value;
    std::vector<RayRecord>& child_slots = scratch.child_slots;
    std::vector<std::array<Component, kMaxLobes>>& child_components = scratch.child_components;
    std::vector<uint8_t>& child_count = scratch.child_count;
    const Vec3 background = scene.scene.background;

    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i < range.end(); ++i) {
            for (uint32_t j = 0; j < ns; ++j) {  // every slot starts as a hole (tnear > tfar)
                RTCRay& s = shadows[i * ns + j];
                s.tnear = 1.0f;
                s.tfar = 0.0f;
                s.org_x = s.org_y = s.org_z = 0;
                s.dir_x = 0, s.dir_y = 0, s.dir_z = 1;
                s.mask = 0xFFFFFFFFu;
                s.flags = 0;
                s.time = 0;
                s.id = static_cast<unsigned>(i);
            }
            RayRecord ray = rays.get(begin + i);
            const RTCRayHit& h = hits[i];
            if (h.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
                out.contribution[i] = ray.beta * background;
                continue;
            }
            Vec3 dir = normalize_or_zero(ray.direction);
            double t = h.ray.tfar;
            HitFrame f = hit_frame(*scene.embree, h.hit.geomID, h.hit.primID, h.hit.u, h.hit.v, ray.origin + ray.direction * t,
                                   dir, t);
            const Material& m = scene.material_of(h.hit.geomID);
            Vec3 c = ray.beta * emitted(m, f, camera || (ray.flags & kRayFromDeltaLobe), camera);
            out.contribution[i] = is_finite(c) ? c : Vec3{};
            if (camera) out.emission[i] = out.contribution[i];
            if (!scene.lights->empty() && has_direct_response(m)) {
                uint32_t nsi = params.shadow_rays_per_pixel ? std::min<uint32_t>(ns, (*params.shadow_rays_per_pixel)[ray.pixel]) : ns;
                for (uint32_t j = 0; j < nsi; ++j) {
                    Vec3 value, so, sd;
                    double tfar;
                    if (!direct_light_sample(scene, m, f, ray, j, nsi, value, so, sd, tfar)) continue;
                    RTCRay& s = shadows[i * ns + j];
                    s.org_x = static_cast<float>(so.x), s.org_y = static_cast<float>(so.y), s.org_z = static_cast<float>(so.z);
                    s.dir_x = static_cast<float>(sd.x), s.dir_y = static_cast<float>(sd.y), s.dir_z = static_cast<float>(sd.z);
                    s.tnear = 0.0f;
                    s.tfar = static_cast<float>(tfar);
                    shadow_value[i * ns + j] = value;
                }
            }
            std::array<RayRecord, kMaxLobes> slots;
            child_count[i] = static_cast<uint8_t>(spawn_children(m, f, ray, eps, params, slots, child_components[i]));
            for (int l = 0; l < child_count[i]; ++l) child_slots[i * kMaxLobes + static_cast<size_t>(l)] = slots[static_cast<size_t>(l)];
        }
    });

    if (params.capture) params.capture->shadow_rays.insert(params.capture->shadow_rays.end(), shadows.begin(), shadows.end());
    occluded_batch(*scene.embree, shadows.data(), shadows.size());

    // Ordered merge, in parallel but into fixed places: each ray's children land after those
    // of every earlier ray (per component), so the bins' order does not depend on threads.
    std::vector<std::array<uint32_t, kComponentCount>> offset(n + 1);
    offset[0] = {};
    for (size_t i = 0; i < n; ++i) {
        offset[i + 1] = offset[i];
        for (int l = 0; l < child_count[i]; ++l) ++offset[i + 1][static_cast<size_t>(child_components[i][static_cast<size_t>(l)])];
    }
    for (size_t c = 0; c < kComponentCount; ++c) out.children[c].resize(offset[n][c]);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i < range.end(); ++i) {
            for (uint32_t j = 0; j < ns; ++j) {
                const RTCRay& s = shadows[i * ns + j];
                if (s.tnear > s.tfar && s.tfar == 0.0f) continue;  // hole: no sample
                if (s.tfar != -INFINITY) out.contribution[i] += shadow_value[i * ns + j];
            }
            std::array<uint32_t, kComponentCount> at = offset[i];
            for (int l = 0; l < child_count[i]; ++l) {
                size_t c = static_cast<size_t>(child_components[i][static_cast<size_t>(l)]);
                out.children[c].set(at[c]++, child_slots[i * kMaxLobes + static_cast<size_t>(l)]);
            }
        }
    });
    for (size_t i = 0; i < n; ++i) {
        if (hits[i].hit.geomID != RTC_INVALID_GEOMETRY_ID) ++out.hits;
        for (uint32_t j = 0; j < ns; ++j) {
            const RTCRay& s = shadows[i * ns + j];
            out.shadow_rays += !(s.tnear > s.tfar && s.tfar == 0.0f);
        }
    }
}

}  // namespace crex
