#include "runtime/render/shade.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "runtime/base/sampling.h"
#include "runtime/render/camera_samples.h"
#include "runtime/render/hot_surfaces.h"
#include "runtime/trace/trace_batch.h"

namespace crex {

// Roulette always starts at least here, whatever `lw` says: with --lw 0 glass split into T and
// R at every interface without end (2^depth rays until bad_alloc). Below 1e-4 of a camera ray's
// weight a ray survives with probability weight / 1e-4, so the expected rays per sample stay
// bounded and the estimate unbiased.
constexpr double kMinWeightLimit = 1e-4;

// Beyond the camera's own hits the caustic map answers one diffuse lobe in this many, its
// answer weighted up as much (unbiased): each answer is a nearest-neighbour search, and at
// every hit they made a default render 2.5 times slower. The map's answer is smooth, so the
// extra variance is small beside the fireflies it replaces; at camera hits, where a caustic
// is seen sharp, every lobe asks.
constexpr double kDeepCausticLookups = 0.25;

int spawn_children(const Bsdf& b, const HitFrame& f, const RayRecord& ray, const HitRandom& random, const ShadeParams& params,
                   SpawnScratch& scratch) {
    const std::array<Lobe, kMaxLobes>& lobes = scratch.lobes;
    int n = scatter(b, f, random, scratch.lobes);
    scratch.caustic = {};
    if (ray.depth + 1u > params.max_depth) {  // what the children would have carried is left out
        for (int l = 0; l < n; ++l) {
            const Vec3 beta = ray.beta * lobes[static_cast<size_t>(l)].weight;
            if (is_finite(beta)) scratch.cut_by_depth += luminance(beta);
        }
        return 0;
    }
    const double weight_limit = std::max(params.weight_limit, kMinWeightLimit);
    const bool photon_caustics = params.caustic_irradiance && !params.ic_queries;
    int out = 0;
    double st = params.specular_threshold_per_pixel ? (*params.specular_threshold_per_pixel)[ray.pixel] : params.specular_threshold;
    for (int l = 0; l < n; ++l) {
        const Lobe& lobe = lobes[static_cast<size_t>(l)];
        // The specular threshold (RADIANCE -st, thesis 5.7): weak specular reflections are not sampled.
        if (st > 0 && (lobe.component == Component::kS || lobe.component == Component::kG) && max_component(lobe.weight) < st)
            continue;
        Vec3 beta = ray.beta * lobe.weight;
        // The caustic map's light at this diffuse lobe, whatever becomes of its ray below: the
        // map's estimate stands for every path L S+ D through it (kRayCausticPath).
        if (photon_caustics && lobe.component == Component::kD && is_finite(beta)) {
            const double asked = ray.depth == 0 ? 1.0 : kDeepCausticLookups;
            if (asked >= 1 || random(RandomUse::kCausticLookup, static_cast<uint32_t>(l)) < asked)
                scratch.caustic += beta * params.caustic_irradiance(f.position, lobe.transmits ? -f.shading : f.shading) * (kInvPi / asked);
        }
        double mx = max_component(beta);
        if (!(mx > 0) || !is_finite(beta)) continue;
        // Under the cache a diffuse lobe asks it for its indirect light, and so does a glossy
        // lobe as wide as one (glossy_like_diffuse()), whose light then counts as D's: in the
        // diffuse lobe's query where there is one, else in one of its own.
        const bool query = params.ic_queries && (lobe.component == Component::kD || (lobe.component == Component::kG && glossy_like_diffuse(b)));
        if (query && lobe.component == Component::kG) {
            RayRecord* same = nullptr;
            for (int k = 0; k < out && !same; ++k) {
                RayRecord& other = scratch.children[static_cast<size_t>(k)];
                if ((other.flags & kRayIcQuery) && other.direction == f.shading) same = &other;
            }
            if (same) {
                same->beta += beta;
                continue;
            }
        }
        if (mx < weight_limit) {
            if (!params.roulette && mx < params.weight_limit) {
                scratch.cut_by_weight += luminance(beta);
                continue;
            }
            double q = mx / weight_limit;  // survive with probability q, re-weighted by 1/q
            if (random(RandomUse::kRoulette, static_cast<uint32_t>(l)) >= q) continue;
            beta = beta / q;
        }
        RayRecord& c = scratch.children[static_cast<size_t>(out)];
        const Component component = query ? Component::kD : lobe.component;
        // A camera hit's children start a branch; deeper rays stay in their parent's.
        const uint8_t branch = ray.depth == 0 ? static_cast<uint8_t>((1u + static_cast<unsigned>(component)) << kRayBranchShift)
                                              : static_cast<uint8_t>(ray.flags & kRayBranchMask);
        if (query) {  // an irradiance-cache query: the hit and the normal on the lit side
            c.origin = f.position;
            c.direction = lobe.transmits ? -f.shading : f.shading;
            c.flags = static_cast<uint8_t>(kRayIcQuery | (ray.flags & kRayOddSample) | branch);
        } else {
            c.origin = f.position + (lobe.transmits ? -f.normal : f.normal) * f.epsilon;
            c.direction = lobe.direction;
            const bool seen = lobe.delta && (ray.depth == 0 || (ray.flags & kRaySeenByCamera));
            // Straight through thin glass or trans, a ray sees emitters as its parent did: direct
            // lighting's shadow rays cross those surfaces, so a ray from a diffuse lobe that
            // goes on through them must not count the emitters again.
            const bool sees_emitters = lobe.straight ? ray.depth == 0 || (ray.flags & kRayFromDeltaLobe) : lobe.delta;
            const bool caustic_path = photon_caustics && (lobe.component == Component::kD || (lobe.delta && (ray.flags & kRayCausticPath)));
            c.flags = static_cast<uint8_t>((sees_emitters ? kRayFromDeltaLobe : 0) | (seen ? kRaySeenByCamera : 0) | (ray.flags & kRayOddSample) |
                                           (caustic_path ? kRayCausticPath : 0) | branch);
        }
        c.beta = beta;
        c.pixel = ray.pixel;
        c.depth = static_cast<uint16_t>(ray.depth + 1);
        c.path = child_path(ray.path, l, lobe.component);
        scratch.components[static_cast<size_t>(out)] = component;
        ++out;
    }
    return out;
}

LightSampling LightSampling::camera_hit(uint64_t camera_path) {
    return {true, camera_sample_index(camera_path), camera_pixel_key(camera_path), true};
}

HitLighting hit_lighting(const ShadeParams& params, const RayRecord& ray, bool camera) {
    HitLighting out{shadow_rays_at(params, ray.pixel, camera ? uint8_t{kRaySeenByCamera} : ray.flags),
                    camera ? LightSampling::camera_hit(ray.path) : LightSampling{.glossy_mis = true}};
    out.sampling.glossy_cached = params.ic_queries;
    return out;
}

namespace {

// A direction towards a distant source (the sun, a sky): its shadow ray has no end.
bool distant_light_sample(const RenderScene& scene, const Bsdf& b, const HitFrame& f, const Vec3& beta, const LightSample& ls,
                          uint32_t n, ShadowSample& out) {
    if (!(ls.pdf_direction > 0)) return false;
    const Vec3& wi = ls.direction;
    Vec3 fr;
    if (b.lambertian) {
        const double c = dot(wi, f.normal);
        if (c > 0) fr = b.diffuse * (c * kInvPi);
    } else if (b.directional && ls.weak) {
        // RADIANCE never samples a sky (a distant glow) for direct light: its light reaches a
        // plasfunc, metfunc or transfunc only as indirect light, which the function does not
        // shape (m_brdf.c: the colour less what it transmits in front, what it transmits behind,
        // the weights of crex's own D lobes there).
        const double c = dot(wi, f.shading);
        if (c != 0 && (dot(wi, f.normal) > 0) == (c > 0)) fr = (c > 0 ? b.diffuse : b.diffuse_transmit) * (std::fabs(c) * kInvPi);
    } else {
        fr = eval_direct(b, f, wi);
    }
    if (!(max_component(fr) > 0)) return false;
    out.value = beta * fr * ls.radiance * (1.0 / (ls.pdf_direction * n));
    if (scene.medium) out.value = out.value * scene.medium->transmittance(f.position, wi, INFINITY);
    if (!is_finite(out.value) || !(max_component(out.value) > 0)) return false;
    out.origin = f.position + (dot(wi, f.geometric) > 0 ? f.geometric : -f.geometric) * f.epsilon;
    out.direction = wi;
    out.tfar = INFINITY;
    out.weak_target = ls.weak;
    return true;
}

// Whether a local emitter's sample lights a point `dist` away along unit `wi` (from the point to
// the emitter), and the factor its light falls off by there: a glow lights nothing beyond its
// reach (rays see it instead), a spotlight nothing outside its cone, and its light falls off as
// from the focus behind it (RADIANCE's spotlight).
bool reaches(const LightSample& ls, const Vec3& wi, double dist, double& falloff) {
    falloff = 1;
    if (!ls.limits) return true;
    if (dist > ls.limits->max_distance) return false;
    if (ls.limits->spot_cos >= -1) {
        if (-dot(wi, ls.limits->spot_axis) < ls.limits->spot_cos) return false;
        const double from_focus = dist + ls.limits->focal;
        falloff = dist * dist / (from_focus * from_focus);
    }
    return true;
}

// Veach's power heuristic: the weight of a strategy whose density is `mine` beside another's.
double power_heuristic(double mine, double other) {
    if (!(mine > 0)) return 0;
    if (!(other > 0)) return 1;
    const double r = other / mine;  // as a ratio: squares of a sharp lobe's density overflow
    return 1 / (1 + r * r);
}

// Which strategy drew a light point, and so how its value is weighed: light sampling alone, or
// one of the pair a glossy lobe weighs between (weighs_glossy_light()).
enum class LightStrategy { kLight, kLightOfTwo, kGlossyOfTwo };

// The shadow sample of a local emitter's point ls at hit f: the value (beta included, over the
// strategy's density) and the shadow ray; false where it brings nothing.
bool light_point_sample(const RenderScene& scene, const Bsdf& b, const HitFrame& f, const LightSample& ls, const Vec3& beta, uint32_t n,
                        LightStrategy strategy, double glossy_pdf_of_wi, ShadowSample& out) {
    Vec3 to = ls.position - f.position;
    double d2 = dot(to, to);
    if (!(d2 > 0) || !(ls.pdf_area > 0)) return false;
    double dist = std::sqrt(d2);
    Vec3 wi = to / dist;
    double cos_l = -dot(ls.normal, wi);
    if (cos_l <= 0) return false;  // emitters radiate from their front side only
    double falloff = 1;
    if (!reaches(ls, wi, dist, falloff)) return false;
    const Vec3 radiance = patterned_radiance(ls, wi, dist);
    Vec3 fr;
    double scale;  // what fr x radiance is divided by
    if (strategy == LightStrategy::kGlossyOfTwo) {
        // The glossy lobe drew wi: its share of the pair, over its own density.
        fr = eval_glossy(b, f, wi);
        const double light_pdf = ls.pdf_area * d2 / cos_l;  // per steradian, as n light samples each draw it
        scale = glossy_pdf_of_wi / power_heuristic(glossy_pdf_of_wi, n * light_pdf);
    } else {
        if (b.lambertian && f.shading == f.normal) {  // the common case, inline: D reflection only
            double c = dot(wi, f.normal);
            if (c > 0) fr = b.diffuse * (c * kInvPi);
        } else if (strategy == LightStrategy::kLightOfTwo) {
            // The glossy lobe's part of fr, weighed against glossy_light_sample()'s chance of wi.
            Vec3 glossy;
            fr = eval_direct(b, f, wi, true, &glossy);
            if (max_component(glossy) > 0) fr = fr - glossy * (1 - power_heuristic(n * ls.pdf_area * d2 / cos_l, glossy_pdf(b, f, wi)));
        } else {
            fr = eval_direct(b, f, wi);
        }
        scale = d2 * ls.pdf_area * n / cos_l;
    }
    if (!(max_component(fr) > 0) || !(scale > 0) || !std::isfinite(scale)) return false;
    out.value = beta * fr * radiance * (falloff / scale);
    if (scene.medium) out.value = out.value * scene.medium->transmittance(f.position, wi, dist);
    if (!is_finite(out.value)) return false;
    out.origin = f.position + (dot(wi, f.geometric) > 0 ? f.geometric : -f.geometric) * f.epsilon;
    out.direction = wi;
    out.weak_target = ls.weak;
    // The origin moved by the hit's epsilon, so the light point is at least dist - eps away
    // (eps the larger of the hit's and the light point's own): stopping at dist - 3 eps keeps a
    // 2 eps margin before the emitter without a second square root.
    const double eps = std::max(f.epsilon, scene.embree->epsilon_at(ls.position, dist));
    // Embree finds the distance to an analytic sphere less precisely (about 1e-4 of it near
    // the silhouette, a square root of a difference in float): shadow rays to a sphere ended
    // on the sphere itself and a lamp much larger than eps lit 2.2 % too dark
    // (tests/numerics/sphere_light_test.cpp). Their margin scales with the distance.
    out.tfar = dist - (ls.sphere ? std::max(3 * eps, 1e-3 * dist) : 3 * eps);
    return out.tfar > 0;
}

}  // namespace

bool direct_light_sample(const RenderScene& scene, const Bsdf& b, const HitFrame& f, const LightSampler::LocalWeights& weights,
                         const Vec3& beta, const HitRandom& random, uint32_t j, uint32_t n, ShadowSample& out,
                         const LightSampling& sampling) {
    // Made where it is returned (a sample default-made and then assigned was zeroed first).
    const LightSample ls = [&] {
        if (sampling.pixel_sequence) {
            // Point sample * n + j of the pixel's scrambled (0,2)-sequence; its first coordinate
            // also chooses the emitter (LightSampler::sample_reusing), so each emitter's share of
            // the points is itself stratified.
            double u, v;
            owen_sobol_2d(sampling.sample * n + j, mix64(sampling.pixel_key ^ 0x5851f42d4c957f2dull), u, v);
            return scene.lights->sample_reusing(weights, u, v);
        }
        // Low-discrepancy over the n samples of this hit: a rotated Halton set for the point
        // on the emitter, stratified picks between emitters.
        double u, v, r0, r1;
        random.pair(RandomUse::kLight, r0, r1);
        rotated_halton(j, r0, r1, u, v);
        return scene.lights->sample(weights, (j + random(RandomUse::kLightPick, j)) / n, u, v);
    }();
    if (ls.distant) return distant_light_sample(scene, b, f, beta, ls, n, out);
    return light_point_sample(scene, b, f, ls, beta, n, weighs_glossy_light(b, weights, sampling) ? LightStrategy::kLightOfTwo : LightStrategy::kLight,
                              0, out);
}

bool glossy_light_sample(const RenderScene& scene, const Bsdf& b, const HitFrame& f, const LightSampler::LocalWeights& weights,
                         const Vec3& beta, const HitRandom& random, uint32_t n, ShadowSample& out) {
    // The G child's direction (scatter()'s draw, the same random numbers).
    double u1, u2;
    random.pair(RandomUse::kLobeG, u1, u2);
    const Vec3 wi = sample_glossy(b, f, u1, u2);
    if (!(dot(wi, f.shading) > 0)) return false;
    const double pdf = glossy_pdf(b, f, wi);
    if (!(pdf > 0) || !std::isfinite(pdf)) return false;
    const LightSample ls = scene.lights->along(weights, wi);
    return ls.pdf_area > 0 && light_point_sample(scene, b, f, ls, beta, n, LightStrategy::kGlossyOfTwo, pdf, out);
}


namespace {

// Light the hot surfaces (hot_surfaces.h) reflect to hit f, sample j of n: a point y on them,
// chosen by the light it receives; y's direct light by one light sample there, whose shadow
// ray `to_light` that light must pass as well (BlockShadows::add_relay; `has_relay` false
// when there is none), and on a lit side what the hot surfaces give each other (`extra`, which
// needs no relay); seen from f through `out`. `glossy_only`: the irradiance cache's records
// answer for the diffuse lobes (they sample the hot surfaces themselves). What glossy rays that
// met a shade's inside by chance brought, one in a few hundred from anywhere in a room, were
// white specks over the image.
bool hot_surface_sample(const RenderScene& scene, const Bsdf& b, const HitFrame& f, const RayRecord& ray, const HitRandom& random,
                        uint32_t j, uint32_t n, bool glossy_only, ShadowSample& out, ShadowSample& to_light, bool& has_relay, Vec3& extra) {
    const HotSurfaces& hot = *scene.hot;
    const HotSurfaces::Point y = hot.sample(random(RandomUse::kHotLight, 3 * j), random(RandomUse::kHotLight, 3 * j + 1),
                                            random(RandomUse::kHotLight, 3 * j + 2));
    if (!(y.pdf_area > 0)) return false;
    const Vec3 to = y.position - f.position;
    const double d2 = dot(to, to);
    if (!(d2 > 0)) return false;
    const double dist = std::sqrt(d2);
    const Vec3 wi = to / dist;
    const Vec3 fr = glossy_only ? eval_glossy(b, f, wi) : eval_direct(b, f, wi);
    if (!(max_component(fr) > 0)) return false;
    const HotSurfaces::Reflected at_y =
        hot.reflected(scene, y, wi, dist, HitRandom(hash_combine(ray.path, 0x4074ull + j), static_cast<uint32_t>(ray.depth) + 1));
    if (!at_y.seen) return false;
    const Vec3 to_radiance = ray.beta * fr * (at_y.cos_y / (d2 * y.pdf_area * n));
    has_relay = at_y.lit;
    if (has_relay) to_light = at_y.to_light;
    out.value = has_relay ? to_radiance * to_light.value : Vec3{};
    extra = to_radiance * at_y.each_other;
    if (!is_finite(out.value) || !is_finite(extra)) return false;
    if (!(max_component(out.value) > 0) && !(max_component(extra) > 0)) return false;
    if (!has_relay) out.value = extra, extra = {};
    out.origin = f.position + (dot(wi, f.geometric) > 0 ? f.geometric : -f.geometric) * f.epsilon;
    out.direction = wi;
    out.weak_target = false;
    out.tfar = dist - 3 * std::max(f.epsilon, at_y.epsilon);
    return out.tfar > 0;
}

// Removes the D children of spawn_children()'s `n`; returns how many are left.
int drop_diffuse_children(SpawnScratch& spawn, int n) {
    int kept = 0;
    for (int l = 0; l < n; ++l) {
        const auto k = static_cast<size_t>(l);
        if (spawn.components[k] == Component::kD) continue;
        spawn.children[static_cast<size_t>(kept)] = spawn.children[k];
        spawn.components[static_cast<size_t>(kept)] = spawn.components[k];
        ++kept;
    }
    return kept;
}

}  // namespace

void BlockShadows::trace_relays(const RenderScene& scene) {
    if (relay.empty()) return;
    relay_through.resize(relay.size());
    trace_shadow_rays_in_this_task(scene, relay.data(), relay_weak.data(), relay_through.data(), relay.size());
    for (size_t k = 0; k < relay.size(); ++k) value[relay_of[k]] = value[relay_of[k]] * relay_through[k] + relay_extra[k];
}

bool single_scatter_sample(const RenderScene& scene, const MediumModel& medium, const Vec3& origin, const Vec3& dir, double tmax,
                           const Vec3& beta, const HitRandom& random, uint32_t k, uint32_t n, ShadowSample& out) {
    if (scene.lights->empty() || !(max_component(medium.sigma_s) > 0)) return false;
    // The lamp by power alone (the point that matters moves along the ray), a point on it,
    // then a distance along the ray by equiangular sampling toward that point; the n samples
    // are stratified in the distance's angle.
    double r0, r1, u, v;
    random.pair(RandomUse::kMediumLight, r0, r1);
    rotated_halton(k, r0, r1, u, v);
    LightSample ls = scene.lights->sample((k + random(RandomUse::kMediumPick, k)) / n, u, v);
    if (!(ls.pdf_area > 0)) return false;
    // Only the part of the ray inside the medium scatters (all of it, unless it fills a box).
    double t0, t1;
    if (!medium.inside(origin, dir, tmax, t0, t1)) return false;
    DistanceSample ds = sample_equiangular(origin, dir, t1, ls.position, (k + random(RandomUse::kMediumDistance, k)) / n, t0);
    if (!(ds.pdf > 0)) return false;
    const Vec3 x = origin + dir * ds.t;
    const Vec3 to = ls.position - x;
    const double d2 = dot(to, to);
    if (!(d2 > 0)) return false;
    const double dist = std::sqrt(d2);
    const Vec3 wi = to / dist;
    const double cos_l = -dot(ls.normal, wi);
    if (cos_l <= 0) return false;
    double falloff = 1;
    if (!reaches(ls, wi, dist, falloff)) return false;  // a spotlight's beam lights only its cone
    // Light travels along -wi to x and on along -dir to the eye: the scattering angle's cosine
    // is dot(-wi, -dir).
    const double phase = henyey_greenstein(dot(wi, dir), medium.g);
    out.value = beta * medium.transmittance(origin, dir, ds.t) * medium.sigma_s * patterned_radiance(ls, wi, dist) * medium.transmittance(x, wi, dist) *
                (falloff * phase * cos_l / (d2 * ls.pdf_area * ds.pdf * n));
    if (!is_finite(out.value) || !(max_component(out.value) > 0)) return false;
    const double eps = scene.embree->epsilon_at(ls.position, dist);  // x is on no surface
    out.origin = x;
    out.direction = wi;
    out.weak_target = ls.weak;
    out.tfar = dist - (ls.sphere ? std::max(3 * eps, 1e-3 * dist) : 3 * eps);
    return out.tfar > 0;
}

void ShadeOutput::append_children_to(std::array<RayBatch, kComponentCount>& bins) const {
    std::array<std::vector<const RayBatch*>, kComponentCount> parts;
    size_t total = 0;
    for (size_t c = 0; c < kComponentCount; ++c)
        for (size_t b = 0; b < blocks; ++b)
            if (!block_children[b][c].empty()) parts[c].push_back(&block_children[b][c]), total += block_children[b][c].size();
    auto copy = [&](size_t task) {
        size_t c = task / RayBatch::kArrays;
        if (!parts[c].empty()) bins[c].append_array(task % RayBatch::kArrays, parts[c]);
    };
    const size_t tasks = kComponentCount * RayBatch::kArrays;
    if (total < kShadeBlock) {  // the tails of paths: a few rays, not worth 78 tasks
        for (size_t task = 0; task < tasks; ++task) copy(task);
        return;
    }
    tbb::parallel_for(size_t{0}, tasks, copy);
}

void trace_and_shade(const RenderScene& scene, const RayBatch& rays, size_t begin, size_t end, bool camera,
                     const ShadeParams& params, ShadeOutput& out) {
    const size_t n = end - begin;
    const MediumModel* medium = scene.medium ? &*scene.medium : nullptr;
    // Shadow rays of a ray: direct light at the hit, then (in a medium) the single-scatter
    // samples along the ray: media_samples along a camera ray, one along any other, since light
    // scattered into a segment reaches the eye by the surfaces the path goes on from (RADIANCE
    // scatters into every ray: a fog's glow lights the walls).
    const uint32_t nm = !medium ? 0 : camera ? params.media_samples : std::min<uint32_t>(params.media_samples, 1);
    out.reset();
    ShadeScratch& scratch = out.scratch;
    std::vector<RTCRayHit>& hits = scratch.hits;
    hits.resize(n);
    auto aim = [&](size_t from, size_t to) {
        for (size_t i = from; i < to; ++i) {
            size_t r = begin + i;
            set_ray(hits[i], rays.ox[r], rays.oy[r], rays.oz[r], rays.dx[r], rays.dy[r], rays.dz[r], static_cast<unsigned>(i));
        }
    };
    // A block's rays are aimed and traced by the task that shades them (one fork and join a
    // chunk, not three, and its hits still in cache); a capture takes every ray first.
    const bool captured = params.capture != nullptr;
    if (captured) {
        aim(0, n);
        params.capture->rays.insert(params.capture->rays.end(), hits.begin(), hits.end());
    }

    out.contribution.resize(n);
    if (camera) out.emission.resize(n);
    const size_t block_rays = shade_block_rays(n), blocks = (n + block_rays - 1) / block_rays;
    if (out.block_children.size() < blocks) out.block_children.resize(blocks);
    if (out.block_spawned.size() < blocks) out.block_spawned.resize(blocks);
    if (scratch.block_shadows.size() < blocks) scratch.block_shadows.resize(blocks);
    out.blocks = blocks;
    scratch.block_hits.assign(blocks, 0);
    scratch.block_cut_by_depth.assign(blocks, 0.0);
    scratch.block_cut_by_weight.assign(blocks, 0.0);
    scratch.block_shadow_rays.assign(blocks, 0);
    const Vec3 background = scene.scene.background;
    const bool lights = !scene.lights->empty();
    const bool hot_lights = lights && params.hot_surface_lights && scene.hot && !scene.hot->empty();

    // Shade: emission, shadow rays, children into the block's own bins; then the block's shadow
    // rays are traced and their light added, each ray's in the order it aimed them.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks, 1), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t block = range.begin(); block < range.end(); ++block) {
            std::array<RayBatch, kComponentCount>& children = out.block_children[block];
            std::array<std::vector<RayRecord>, kComponentCount>& spawned_rays = out.block_spawned[block];
            for (auto& v : spawned_rays) v.clear();
            BlockShadows& shadows = scratch.block_shadows[block];
            shadows.clear();
            const size_t first = block * block_rays, last = std::min(n, first + block_rays);
            if (!captured) aim(first, last);
            intersect_serial(*scene.embree, hits.data() + first, last - first, camera);
            SpawnScratch spawn;
            // Filled by direct_light_sample() wherever it returns true: one made for every
            // sample was zeroed first (a `rep stos` of 88 bytes).
            ShadowSample light_sample, hot_light;
            Bsdf textured;  // surface_at()'s, made once a block: a Bsdf made at every hit was zeroed at every hit
            uint32_t block_hits = 0;
            // One ray: its emission or what it escaped to, direct light's shadow rays, children.
            auto shade = [&](size_t i) {
                if (camera) out.emission[i] = {};
                const size_t r = begin + i;
                const Vec3 beta{rays.br[r], rays.bg[r], rays.bb[r]};
                const RTCRayHit& h = hits[i];
                const bool miss = h.hit.geomID == RTC_INVALID_GEOMETRY_ID;
                out.contribution[i] = {};
                if (nm > 0) {
                    const Vec3 o{h.ray.org_x, h.ray.org_y, h.ray.org_z}, d{h.ray.dir_x, h.ray.dir_y, h.ray.dir_z};
                    const uint32_t nmi = params.media_samples_per_pixel ? std::min<uint32_t>(nm, (*params.media_samples_per_pixel)[rays.pixel[r]]) : nm;
                    const HitRandom random(rays.path[r], rays.depth[r]);
                    for (uint32_t k = 0; k < nmi; ++k) {
                        ShadowSample sample;
                        if (single_scatter_sample(scene, *medium, o, d, miss ? INFINITY : double(h.ray.tfar), beta, random, k, nmi, sample))
                            shadows.media.push_back(sample);
                    }
                }
                if (miss) {
                    // Camera rays and rays from delta lobes see the distant sources (the sun, a
                    // sky); direct lighting samples them for the rest.
                    Vec3 sources;
                    if (camera || (rays.flags[r] & kRayFromDeltaLobe))
                        sources = scene.lights->distant().escaped(Vec3{h.ray.dir_x, h.ray.dir_y, h.ray.dir_z});
                    const Vec3 through =
                        beta * (medium ? medium->transmittance(Vec3{h.ray.org_x, h.ray.org_y, h.ray.org_z}, Vec3{h.ray.dir_x, h.ray.dir_y, h.ray.dir_z}, INFINITY)
                                       : Vec3{1, 1, 1});
                    Vec3 c = through * (background + sources);
                    out.contribution[i] = is_finite(c) ? c : Vec3{};
                    if (camera && is_finite(through * sources)) out.emission[i] = through * sources;  // a sky seen is emission
                    return;
                }
                ++block_hits;
                // Origin and direction from the hit record (in cache, unlike six of the bin's
                // arrays); directions are unit already (sampled, reflected or normalised).
                double t = h.ray.tfar;
                // Through a medium, all the hit gives back is seen through the segment's
                // transmittance: it scales the ray's throughput (emission, direct light, children).
                const RayRecord ray{{h.ray.org_x, h.ray.org_y, h.ray.org_z},
                                    {h.ray.dir_x, h.ray.dir_y, h.ray.dir_z},
                                    medium ? beta * medium->transmittance(Vec3{h.ray.org_x, h.ray.org_y, h.ray.org_z},
                                                                          Vec3{h.ray.dir_x, h.ray.dir_y, h.ray.dir_z}, t)
                                           : beta,
                                    rays.pixel[r],
                                    rays.depth[r],
                                    rays.flags[r],
                                    rays.path[r]};
                HitFrame f = hit_frame(*scene.embree, h.hit, ray.origin + ray.direction * t, ray.direction, t);
                if (!camera && !(ray.flags & kRayFromDeltaLobe) && illum_front(scene, h.hit, f)) {
                    out.contribution[i] = {};  // direct lighting brought the illum's light
                    return;
                }
                const Bsdf& b = surface_at(scene, h.hit, f, textured, surface_detail(camera, ray.flags));
                const HitRandom random = hit_random(ray, camera);
                // A `light` reached along a caustic path is the photon map's, given at the diffuse hit.
                const bool photons_gave_it = (ray.flags & kRayCausticPath) && b.type == MaterialType::kLight;
                Vec3 c = b.emits && !photons_gave_it ? ray.beta * emitted(b, f, camera || (ray.flags & kRayFromDeltaLobe), camera) : Vec3{};
                out.contribution[i] = is_finite(c) ? c : Vec3{};
                if (camera) out.emission[i] = out.contribution[i];
                // A hot surface's direct light is every hit's (hot_surface_sample()), but where
                // the ray came from a mirror or straight through glass, which those do not follow.
                const bool lit_as_hot = hot_lights && !camera && !(ray.flags & kRayFromDeltaLobe) && scene.hot->contains(h.hit.geomID, h.hit.primID);
                // On its lit side all the light it reflects diffusely came with the hit's direct
                // light before (the hot surfaces' own light included): no more is gathered here.
                const bool lit_side_of_hot = lit_as_hot && scene.hot->from_lit_side(h.hit.geomID, h.hit.primID, ray.direction);
                if (lights && b.direct_response && !lit_as_hot) {
                    const HitLighting lighting = hit_lighting(params, ray, camera);
                    const LightSampler::LocalWeights weights = scene.lights->weights_at(f.position, horizon_of(b, f));
                    for (uint32_t j = 0; j < lighting.shadow_rays; ++j) {
                        if (direct_light_sample(scene, b, f, weights, ray.beta, random, j, lighting.shadow_rays, light_sample, lighting.sampling))
                            shadows.add(light_sample, static_cast<uint32_t>(i));
                    }
                    if (weighs_glossy_light(b, weights, lighting.sampling) &&
                        glossy_light_sample(scene, b, f, weights, ray.beta, random, lighting.shadow_rays, light_sample))
                        shadows.add(light_sample, static_cast<uint32_t>(i));
                }
                if (hot_lights && b.direct_response && !lit_side_of_hot && (!params.ic_queries || (b.glossy && !glossy_like_diffuse(b)) || b.directional)) {
                    const uint32_t m = hit_lighting(params, ray, camera).shadow_rays;
                    for (uint32_t j = 0; j < m; ++j) {
                        bool relay = false;
                        Vec3 extra;
                        if (hot_surface_sample(scene, b, f, ray, random, j, m, params.ic_queries, light_sample, hot_light, relay, extra)) {
                            shadows.add(light_sample, static_cast<uint32_t>(i));
                            if (relay) shadows.add_relay(hot_light, extra);
                        }
                    }
                }
                int spawned = spawn_children(b, f, ray, random, params, spawn);
                // On a hot surface's lit side the diffuse light it reflects, what the hot
                // surfaces give each other, came with the hit's direct light as well.
                if (lit_side_of_hot) spawned = drop_diffuse_children(spawn, spawned);
                if (is_finite(spawn.caustic)) out.contribution[i] += spawn.caustic;
                for (size_t l = 0; l < static_cast<size_t>(spawned); ++l)
                    spawned_rays[static_cast<size_t>(spawn.components[l])].push_back(spawn.children[l]);
            };
            for (size_t i = first; i < last; ++i) {
                shade(i);
                for (const ShadowSample& sample : shadows.media) shadows.add(sample, static_cast<uint32_t>(i));
                shadows.media.clear();
            }
            for (size_t c = 0; c < kComponentCount; ++c) children[c].append(spawned_rays[c].data(), spawned_rays[c].size());
            scratch.block_hits[block] = block_hits;
            scratch.block_cut_by_depth[block] = spawn.cut_by_depth;
            scratch.block_cut_by_weight[block] = spawn.cut_by_weight;
            scratch.block_shadow_rays[block] = static_cast<uint32_t>(shadows.size() + shadows.relay.size());
            if (params.capture) shadows.captured = shadows.rays;
            shadows.trace_relays(scene);
            // Unoccluded samples add their light, each ray's in the order it aimed them.
            shadows.through.resize(shadows.size());
            trace_shadow_rays_in_this_task(scene, shadows.rays.data(), shadows.weak.data(), shadows.through.data(), shadows.size());
            for (size_t k = 0; k < shadows.size(); ++k)
                if (max_component(shadows.through[k]) > 0) out.contribution[shadows.owner[k]] += shadows.value[k] * shadows.through[k];
        }
    });
    for (size_t block = 0; block < blocks; ++block) {
        out.hits += scratch.block_hits[block];
        out.cut_by_depth += scratch.block_cut_by_depth[block];  // in block order: the same sum at any thread count
        out.cut_by_weight += scratch.block_cut_by_weight[block];
        out.shadow_rays += scratch.block_shadow_rays[block];
        if (params.capture) {
            const std::vector<RTCRay>& c = scratch.block_shadows[block].captured;
            params.capture->shadow_rays.insert(params.capture->shadow_rays.end(), c.begin(), c.end());
        }
    }
}

uint64_t redo_camera_direct_light(const RenderScene& scene, const RayBatch& rays, uint32_t base, bool cached,
                                  const std::vector<uint16_t>& shadow_rays_per_pixel, std::vector<Vec3>& delta) {
    delta.assign(rays.size(), Vec3{});
    if (scene.lights->empty() || rays.empty()) return 0;
    const MediumModel* medium = scene.medium ? &*scene.medium : nullptr;
    // Slots per ray: the preview's `base` estimates (taken back out), then the new ones, each
    // with one more for its glossy lobe's sample (glossy_light_sample()). Chunks hold at most
    // ~1 M slots, so memory stays bounded whatever the image size.
    auto wanted = [&](size_t r) { return std::max<uint32_t>(base, shadow_rays_per_pixel[rays.pixel[r]]); };
    constexpr size_t kMaxSlots = size_t{1} << 20;
    std::vector<RTCRayHit> hits;
    std::vector<RTCRay> shadows;
    std::vector<Vec3> values, through;
    std::vector<uint8_t> weak;
    std::vector<size_t> first;
    uint64_t traced = 0;
    for (size_t begin = 0; begin < rays.size();) {
        first.assign(1, 0);
        size_t end = begin;
        while (end < rays.size() && (end == begin || first.back() + base + wanted(end) + 2 <= kMaxSlots))
            first.push_back(first.back() + base + wanted(end) + 2), ++end;
        const size_t n = end - begin;
        hits.resize(n);
        for (size_t i = 0; i < n; ++i) {
            const size_t r = begin + i;
            set_ray(hits[i], rays.ox[r], rays.oy[r], rays.oz[r], rays.dx[r], rays.dy[r], rays.dz[r], static_cast<unsigned>(i));
        }
        intersect_batch(*scene.embree, hits.data(), n, true);
        shadows.resize(first.back());
        values.assign(first.back(), Vec3{});
        weak.assign(first.back(), 0);
        through.resize(first.back());
        tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kShadeBlock), [&](const tbb::blocked_range<size_t>& range) {
            for (size_t i = range.begin(); i < range.end(); ++i) {
                for (size_t s = first[i]; s < first[i + 1]; ++s) make_hole(shadows[s], static_cast<unsigned>(i));
                const RTCRayHit& h = hits[i];
                if (h.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
                const GeometryInfo& g = scene.embree->geometries()[h.hit.geomID];
                if (!scene.bsdf_of(h.hit.geomID).direct_response && !(scene.textures && scene.textures->textured(g.material)) && g.colors.empty())
                    continue;
                // As trace_and_shade() shades a camera hit: the same frame, throughput and random numbers.
                const size_t r = begin + i;
                const double t = h.ray.tfar;
                const Vec3 origin{h.ray.org_x, h.ray.org_y, h.ray.org_z}, dir{h.ray.dir_x, h.ray.dir_y, h.ray.dir_z};
                Vec3 beta{rays.br[r], rays.bg[r], rays.bb[r]};
                if (medium) beta = beta * medium->transmittance(origin, dir, t);
                HitFrame f = hit_frame(*scene.embree, h.hit, origin + dir * t, dir, t);
                Bsdf textured;
                const Bsdf& b = surface_at(scene, h.hit, f, textured, SurfaceDetail::kSeen);
                if (!b.direct_response) continue;
                const HitRandom random(rays.path[r], rays.depth[r]);
                LightSampling sampling = LightSampling::camera_hit(rays.path[r]);
                sampling.glossy_cached = cached;
                const uint32_t k = wanted(r);
                const LightSampler::LocalWeights weights = scene.lights->weights_at(f.position, horizon_of(b, f));
                auto slot_of = [&](const ShadowSample& s, size_t slot, double sign) {
                    aim_shadow_ray(shadows[slot], s);
                    values[slot] = s.value * sign;
                    weak[slot] = s.weak_target;
                };
                // The glossy lobe's sample draws as the camera hit's lobes do (hit_random()).
                const HitRandom lobes = HitRandom::camera_hit(rays.path[r], rays.depth[r], camera_pixel_key(rays.path[r]),
                                                              camera_sample_index(rays.path[r]));
                const bool glossy = weighs_glossy_light(b, weights, sampling);
                auto estimate = [&](uint32_t of, size_t slot, double sign) {
                    ShadowSample s;
                    for (uint32_t j = 0; j < of; ++j)
                        if (direct_light_sample(scene, b, f, weights, beta, random, j, of, s, sampling)) slot_of(s, slot + j, sign);
                    if (glossy && glossy_light_sample(scene, b, f, weights, beta, lobes, of, s)) slot_of(s, slot + of, sign);
                };
                estimate(base, first[i], -1.0);
                estimate(k, first[i] + base + 1, 1.0);
            }
        });
        trace_shadow_rays(scene, shadows.data(), weak.data(), through.data(), shadows.size());
        for (size_t i = 0; i < n; ++i)
            for (size_t s = first[i]; s < first[i + 1]; ++s)
                if (!is_hole(shadows[s])) {
                    ++traced;
                    if (max_component(through[s]) > 0) delta[begin + i] += values[s] * through[s];
                }
        begin = end;
    }
    return traced;
}

}  // namespace crex
