// How IrradianceCache makes a batch of records (compute()), in its four phases: cast the
// stratified hemisphere rays of every site; carry the rays that met glass, a mirror or a
// translucent surface through them; shade what each ray reached (emission, one light sample,
// the next bounce from records one level deeper); fold each site's rays into a record (E,
// harmonic distance, Ward-Heckbert gradients). Every phase works on the whole batch (shading
// in fixed blocks of rays, each tracing its own shadow rays), so Embree sees large batches and
// the order of every sum is fixed (images do not depend on threads).
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "runtime/base/sampling.h"
#include "runtime/cache/irradiance_cache.h"
#include "runtime/render/bsdf.h"
#include "runtime/render/shade.h"
#include "runtime/render/surface.h"
#include "runtime/trace/trace_batch.h"

namespace crex {

namespace {

// Frees a buffer's memory now (clear() keeps it).
template <typename T>
void release(std::vector<T>& v) {
    std::vector<T>().swap(v);
}

// Hemisphere rays shaded (and their shadow rays traced) by one task at a time.
constexpr size_t kHemisphereBlock = 1024;

}  // namespace

/// The hemisphere rays of a batch of sites: `per` = M x N stratified rays each, site s's rays
/// at [s per, (s + 1) per). What each phase leaves for the next.
struct IrradianceCache::Hemispheres {
    int M = 1, N = 1;  ///< strata in cos^2 theta and in phi
    size_t per = 1, n = 0;
    std::vector<float> first_distance;  ///< to the first hits: they make R and the gradients
    std::vector<RTCRayHit> last;        ///< what each ray reached after any specular interfaces
    std::vector<Vec3> last_dir, throughput;
    /// The ray reached what it shades through a delta shape or a trans surface's specular
    /// transmission (emitters are seen along it; `light` ones are the photon map's).
    std::vector<uint8_t> passed;
    std::vector<Vec3> radiance;
    /// What shading asks the next bounce, per block of kHemisphereBlock rays, in ray order:
    /// each ray's reflected query (on the side it arrived from) before its diffusely
    /// transmitted one (the other side), each with the ray and the albedo its answer is
    /// weighted by.
    struct NextBounce {
        std::vector<IcQuery> queries;
        std::vector<uint32_t> from;
        std::vector<Vec3> weight;
        double albedo_sum = 0;  ///< the block's rays' albedo (luminance), in ray order (IcStats)
    };
    std::vector<NextBounce> next;

    uint64_t ray_key(const std::vector<IcQuery>& sites, size_t i) const { return hash_combine(sites[i / per].key, 0x1c0000ull + i % per); }
};

std::vector<IrradianceRecord> IrradianceCache::compute(const std::vector<IcQuery>& sites, uint32_t level) {
    Hemispheres h = cast_hemispheres(sites, level);
    pass_specular_interfaces(h, sites, level);
    shade_hemispheres(h, sites, level);
    add_hot_surfaces(h, sites, level);
    // What shading alone needed goes before the next bounce's records are made: up to
    // `bounces` batches are alive at once, and each keeps only its radiance and distances
    // (28 of the 157 bytes a ray its arrays hold; prog_all's refinement at 960x540 once held
    // 350 MB of such arrays).
    release(h.last), release(h.last_dir), release(h.throughput), release(h.passed);
    add_next_bounce(h, level);
    if (stopped_) return {};  // set_stop: the caller drops this piece
    return records_from(h, sites, level);
}

// Stratified cosine-weighted directions (M strata in cos^2 theta, N in phi, jittered by the
// site's key), traced to their first hits as one batch.
IrradianceCache::Hemispheres IrradianceCache::cast_hemispheres(const std::vector<IcQuery>& sites, uint32_t level) {
    Hemispheres h;
    // Every site of a piece asks for the same rays (irradiance() groups them).
    const uint32_t ad = std::max(16u, (sites.empty() ? settings_.divisions : divisions_of(sites.front().divisions)) >> std::min(level, 16u));
    h.M = std::max(1, static_cast<int>(std::lround(std::sqrt(ad / kPi))));
    h.N = std::max(1, static_cast<int>(std::lround(static_cast<double>(ad) / h.M)));
    h.per = static_cast<size_t>(h.M) * static_cast<size_t>(h.N);
    h.n = sites.size() * h.per;
    stats_.hemisphere_rays += h.n;
    h.last.resize(h.n);
    h.last_dir.resize(h.n);
    const int M = h.M, N = h.N;
    tbb::parallel_for(size_t{0}, sites.size(), [&](size_t s) {
        Vec3 t, b;
        orthonormal_basis(sites[s].normal, t, b);
        for (int j = 0; j < M; ++j)
            for (int k = 0; k < N; ++k) {
                size_t i = s * h.per + static_cast<size_t>(j * N + k);
                uint32_t cell = static_cast<uint32_t>(j * N + k);
                double u = (j + random_at(sites[s].key, level, RandomUse::kIcTheta, cell)) / M;
                double cos_p, sin_p;  // of 2 pi times the turn: libm's sincos was 4 % of a cached walk
                sincos_2pi((k + random_at(sites[s].key, level, RandomUse::kIcPhi, cell)) / N, cos_p, sin_p);
                double sin_t = std::sqrt(u), cos_t = std::sqrt(std::fmax(0.0, 1 - u));
                Vec3 d = t * (sin_t * cos_p) + b * (sin_t * sin_p) + sites[s].normal * cos_t;
                h.last_dir[i] = d;
                Vec3 o = sites[s].position + sites[s].normal * scene_.embree->epsilon_at(sites[s].position);
                set_ray(h.last[i], static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z), static_cast<float>(d.x),
                        static_cast<float>(d.y), static_cast<float>(d.z), static_cast<unsigned>(i));
            }
    });
    intersect_batch(*scene_.embree, h.last.data(), h.n, false);
    h.first_distance.resize(h.n);
    for (size_t i = 0; i < h.n; ++i) h.first_distance[i] = h.last[i].ray.tfar;
    h.throughput.assign(h.n, Vec3{1, 1, 1});
    h.passed.assign(h.n, 0);
    return h;
}

// Hemisphere rays that reach mirrors, glass or dielectrics continue through them (one lobe
// chosen by its weight, up to 8 interfaces), so light arriving through them (caustics) is in
// E. A translucent (trans) surface passes a ray through its specular transmission with that
// lobe's share of the surface's weight, else the ray is shaded there, each divided by its
// probability: without it, what a frosted screen lets through was missing from E behind it.
// The first hit's distance stays what the harmonic mean uses.
void IrradianceCache::pass_specular_interfaces(Hemispheres& h, const std::vector<IcQuery>& sites, uint32_t level) {
    auto is_delta = [&](const RTCRayHit& r) {
        return r.hit.geomID != RTC_INVALID_GEOMETRY_ID && is_delta_material(scene_.material_of(r.hit.geomID).type);
    };
    std::vector<uint8_t> settled(h.n, 0);
    for (uint32_t bounce = 0; bounce < 8; ++bounce) {
        std::vector<size_t> go;
        std::vector<uint8_t> through_trans(h.n, 0);
        for (size_t i = 0; i < h.n; ++i) {
            if (settled[i] || h.last[i].hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
            const RTCRayHit& last = h.last[i];
            const Vec3 o{last.ray.org_x, last.ray.org_y, last.ray.org_z};
            if (illum_front(scene_, last.hit, hit_frame(*scene_.embree, last.hit, o + h.last_dir[i] * double(last.ray.tfar), h.last_dir[i],
                                                        last.ray.tfar))) {
                h.throughput[i] = {};  // an illum's front: direct lighting brings its light (illum_front())
                settled[i] = 1;
                continue;
            }
            if (is_delta(h.last[i])) {
                go.push_back(i);
                continue;
            }
            const double pass = transmission_share(scene_.bsdf_of(h.last[i].hit.geomID));
            if (!(pass > 0)) continue;
            if (random_at(h.ray_key(sites, i), level * 16 + bounce, RandomUse::kIcTrans) < pass) {
                through_trans[i] = 1;
                go.push_back(i);
            } else {
                h.throughput[i] = h.throughput[i] / (1 - pass);
                settled[i] = 1;  // shaded here
            }
        }
        if (go.empty()) break;
        std::vector<RTCRayHit> batch(go.size());
        tbb::parallel_for(size_t{0}, go.size(), [&](size_t g) {
            size_t i = go[g];
            const RTCRayHit& hit = h.last[i];
            Vec3 o{hit.ray.org_x, hit.ray.org_y, hit.ray.org_z};
            double t = hit.ray.tfar;
            HitFrame f = hit_frame(*scene_.embree, hit.hit, o + h.last_dir[i] * t, h.last_dir[i], t);
            RTCRayHit& r = batch[g];
            r = RTCRayHit{};
            r.ray.tnear = 1.0f, r.ray.tfar = 0.0f;  // a hole unless a lobe is chosen
            r.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            r.ray.mask = 0xFFFFFFFFu;
            // Passing a trans surface is decided on the material's constants (above); the lobes
            // a ray scatters into are the surface's own.
            Bsdf textured;
            const Bsdf& b = through_trans[i] ? scene_.bsdf_of(hit.hit.geomID) : surface_at(scene_, hit.hit, f, textured, SurfaceDetail::kAveraged);
            Lobe lobe;
            double prob = 0;
            if (through_trans[i]) {
                lobe = {Component::kT, h.last_dir[i], b.specular_transmit, true, true, b.clear_transmission};
                prob = transmission_share(b);
            } else {
                std::array<Lobe, kMaxLobes> lobes;
                uint64_t key = h.ray_key(sites, i);
                int nl = scatter(b, f, HitRandom(key, level * 16 + bounce + 1), lobes);
                const int pick = choose_lobe(lobes, nl, random_at(key, level * 16 + bounce, RandomUse::kIcLobe), prob);
                if (pick < 0) {
                    h.throughput[i] = {};
                    return;
                }
                lobe = lobes[static_cast<size_t>(pick)];
            }
            h.throughput[i] = h.throughput[i] * lobe.weight / prob;
            // Straight through thin glass or trans, emitters stay direct lighting's (its shadow
            // rays cross them too); after a bend (a mirror, refraction) the ray sees them.
            if (!lobe.straight) h.passed[i] = 1;
            Vec3 no = f.position + (lobe.transmits ? -f.normal : f.normal) * f.epsilon;
            h.last_dir[i] = lobe.direction;
            set_ray(r, static_cast<float>(no.x), static_cast<float>(no.y), static_cast<float>(no.z), static_cast<float>(lobe.direction.x),
                    static_cast<float>(lobe.direction.y), static_cast<float>(lobe.direction.z), static_cast<unsigned>(i));
        });
        intersect_batch(*scene_.embree, batch.data(), batch.size(), false);
        for (size_t g = 0; g < go.size(); ++g) h.last[go[g]] = batch[g];
    }
}

// Radiance of every hemisphere ray: emission and one direct-light sample here; the queries
// for the next bounce (on the side the ray arrived from, and through a trans surface's
// diffuse transmission on its other side) are left for add_next_bounce().
void IrradianceCache::shade_hemispheres(Hemispheres& h, const std::vector<IcQuery>& sites, uint32_t level) {
    const size_t n = h.n;
    h.radiance.assign(n, Vec3{});
    const size_t blocks = (n + kHemisphereBlock - 1) / kHemisphereBlock;
    h.next.assign(blocks, {});
    // Shadow rays: direct light at each ray's hit, then (in a medium) light scattered once into
    // its last segment, as into every path's (runtime/render/shade.cpp).
    const bool scatters = scene_.medium && max_component(scene_.medium->sigma_s) > 0 && !scene_.lights->empty();
    const size_t slots = scatters ? 2 : 1;
    const bool deeper = level + 1 < settings_.bounces;
    // Shadow rays are aimed, traced and added a block of rays at a time, by the task that
    // shades the block (as trace_and_shade() does), and the next bounce's queries are listed
    // per block: arrays of them for the whole batch (219 bytes a hemisphere ray, fresh memory
    // for every piece of records) were half the page faults of a cached render. Each ray adds
    // its own slots in order, and the lists join in block order: the same sums as before.
    struct HemisphereShadows {
        std::vector<RTCRay> rays;
        std::vector<Vec3> value, through;
        std::vector<uint8_t> weak;
    };
    // One hemisphere ray: its radiance but for direct light, whose shadow rays it aims in its
    // `slots` (holes where it has none).
    auto shade_ray = [&](size_t i, RTCRay* shadows, Vec3* shadow_value, uint8_t* weak, Hemispheres::NextBounce& next) {
        for (size_t k = 0; k < slots; ++k) make_hole(shadows[k], static_cast<unsigned>(k));
        RTCRay& s = shadows[0];
        const RTCRayHit& hit = h.last[i];
        const bool miss = hit.hit.geomID == RTC_INVALID_GEOMETRY_ID;
        const uint64_t key = h.ray_key(sites, i);
        if (scatters && max_component(h.throughput[i]) > 0 && (miss || !is_delta_material(scene_.material_of(hit.hit.geomID).type))) {
            ShadowSample sample;
            const Vec3 origin{hit.ray.org_x, hit.ray.org_y, hit.ray.org_z};
            if (single_scatter_sample(scene_, *scene_.medium, origin, h.last_dir[i], miss ? INFINITY : double(hit.ray.tfar), h.throughput[i],
                                      HitRandom(hash_combine(key, 0x5ca7ull), static_cast<uint16_t>(level + 1)), 0, 1, sample)) {
                aim_shadow_ray(shadows[1], sample);
                shadow_value[1] = sample.value;
                weak[1] = sample.weak_target;
            }
        }
        // In a medium, what the last segment reaches is seen through its transmittance (the
        // segments before it, inside glass, are not attenuated: a simplification).
        const Vec3 beta = scene_.medium ? h.throughput[i] * scene_.medium->transmittance(Vec3{hit.ray.org_x, hit.ray.org_y, hit.ray.org_z},
                                                                                          h.last_dir[i], hit.ray.tfar)
                                        : h.throughput[i];
        const bool still_in_glass = hit.hit.geomID != RTC_INVALID_GEOMETRY_ID && is_delta_material(scene_.material_of(hit.hit.geomID).type);
        if (!(max_component(beta) > 0) || still_in_glass) return;  // absorbed, or still inside glass
        if (hit.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
            // Distant sources are direct lighting's, unless the ray came through glass or a mirror.
            Vec3 seen = scene_.scene.background;
            if (h.passed[i]) seen += scene_.lights->distant().escaped(normalize_or_zero(h.last_dir[i]));
            h.radiance[i] = beta * seen;
            return;
        }
        double dist = hit.ray.tfar;
        Vec3 origin{hit.ray.org_x, hit.ray.org_y, hit.ray.org_z};
        HitFrame f = hit_frame(*scene_.embree, hit.hit, origin + h.last_dir[i] * dist, h.last_dir[i], dist);
        if (illum_front(scene_, hit.hit, f)) {  // a hemisphere ray is indirect: direct lighting brought the illum's light
            h.radiance[i] = {};
            h.throughput[i] = {};
            return;
        }
        Bsdf textured;
        const Bsdf& b = surface_at(scene_, hit.hit, f, textured, SurfaceDetail::kAveraged);
        // Through a mirror, glass or a trans surface's specular transmission, emitters are
        // seen; a `light` emitter's light along those paths is the photon map's when there is
        // one (its photons follow the same lobes), else a rare ray onto a small bright lamp
        // seen through a frosted screen lit a whole record's disc behind it.
        const bool caustic = caustics_ && h.passed[i] && b.type == MaterialType::kLight;
        Vec3 l = caustic ? Vec3{} : emitted(b, f, h.passed[i] != 0, false);
        // A hot surface's direct light is add_hot_surfaces()'s, but where the ray came by a
        // mirror or through glass, which its shadow rays do not follow.
        const bool hot = !h.passed[i] && hot_ && hot_->contains(hit.hit.geomID, hit.hit.primID);
        if (!scene_.lights->empty() && b.direct_response && !hot) {
            ShadowSample sample;
            if (direct_light_sample(scene_, b, f, scene_.lights->weights_at(f.position, horizon_of(b, f)), beta, HitRandom(key, static_cast<uint16_t>(level + 1)), 0, 1,
                                    sample)) {
                aim_shadow_ray(s, sample);
                shadow_value[0] = sample.value;
                weak[0] = sample.weak_target;
            }
        }
        // What the hit reflects of the next bounce's light: its diffuse lobe's, its glossy
        // lobe's by the weight scatter() gives the direction it draws, and a polished surface's
        // mirror reflection (a hemisphere ray is continued through neither). Left out, every
        // glTF material's 4 % specular lobe went missing at every bounce past the first: the
        // living room's lamp lit the far corner under its ceiling a fifth too dimly (path
        // tracing: 0.0886 in red; the cache, converged: 0.071).
        Vec3 reflects = b.diffuse;
        if (b.glossy) {
            double u1, u2;
            HitRandom(key, static_cast<uint16_t>(level + 1)).pair(RandomUse::kLobeG, u1, u2);
            Vec3 dir, weight;
            if (sample_glossy_lobe(b, f, u1, u2, dir, weight)) reflects += weight;
        } else if (b.mirror_like) {
            reflects += b.specular;  // scatter()'s S lobe of plastic and metal
        }
        const Vec3 albedo = beta * reflects, albedo_far = beta * b.diffuse_transmit;
        if (const Vec3 a = albedo + albedo_far; is_finite(a)) next.albedo_sum += luminance(a);
        l = l * beta;
        const IcQuery& site = sites[i / h.per];
        auto ask = [&](const Vec3& normal, uint64_t query_key, const Vec3& weight) {
            next.queries.push_back({f.position, normal, site.accuracy, site.priority, query_key, site.divisions});
            next.from.push_back(static_cast<uint32_t>(i));
            next.weight.push_back(weight);
        };
        // On a hot surface's lit side, what the hot surfaces give each other came with its
        // direct light (add_hot_surfaces()).
        const bool lit_hot = hot && deeper && hot_->from_lit_side(hit.hit.geomID, hit.hit.primID, h.last_dir[i]);
        if (max_component(albedo) > 0 && !lit_hot) {
            if (deeper) {
                ask(f.shading, key, albedo);
            } else {
                l += albedo * settings_.ambient;  // av beyond the last bounce: rho/pi * (pi av)
            }
        }
        if (max_component(albedo_far) > 0) {
            if (deeper) {
                ask(-f.shading, hash_combine(key, 0xfa5ull), albedo_far);
            } else {
                l += albedo_far * settings_.ambient;
            }
        }
        h.radiance[i] = is_finite(l) ? l : Vec3{};
    };
    tbb::enumerable_thread_specific<HemisphereShadows> block_shadows;
    tbb::parallel_for(size_t{0}, blocks, [&](size_t block) {
        const size_t first = block * kHemisphereBlock, last = std::min(n, first + kHemisphereBlock);
        HemisphereShadows& local = block_shadows.local();
        const size_t count = slots * (last - first);
        local.rays.resize(count);
        local.value.assign(count, Vec3{});
        local.through.resize(count);
        local.weak.assign(count, 0);
        Hemispheres::NextBounce& next = h.next[block];
        if (deeper) next.queries.reserve(last - first), next.from.reserve(last - first), next.weight.reserve(last - first);  // a query a ray, mostly
        for (size_t i = first; i < last; ++i) {
            const size_t at = slots * (i - first);
            shade_ray(i, local.rays.data() + at, local.value.data() + at, local.weak.data() + at, next);
        }
        trace_shadow_rays_in_this_task(scene_, local.rays.data(), local.weak.data(), local.through.data(), count);
        for (size_t j = 0; j < count; ++j)
            if (!is_hole(local.rays[j]) && max_component(local.through[j]) > 0) h.radiance[first + j / slots] += local.value[j] * local.through[j];
    });
    // What the next level brings to this one, on average (IcStats): block by block in order,
    // so the same sum at any thread count.
    if (stats_.albedo_sum.size() <= level) stats_.albedo_sum.resize(level + 1), stats_.albedo_rays.resize(level + 1);
    for (const Hemispheres::NextBounce& next : h.next) stats_.albedo_sum[level] += next.albedo_sum;
    stats_.albedo_rays[level] += n;
}

// The light the hot surfaces reflect onto each site (hot_surfaces.h), estimated as from a
// light: points chosen on them by the light they receive, each lit by one direct-light sample
// and, on a lit side while a further bounce is allowed, by what they give each other
// (HotSurfaces::interreflected()), and seen from the site through a shadow ray (the hemisphere
// rays that meet them take none of that there). A shade's inside, seen through its openings from a few cells of the hemisphere
// and many times as bright as the room, is met by the records' rays one or two times or none.
// Each point's light joins the cell its direction falls in, so the record's gradients (and the
// radius they limit) see it as they saw it when the rays brought it.
void IrradianceCache::add_hot_surfaces(Hemispheres& h, const std::vector<IcQuery>& sites, uint32_t level) {
    if (!hot_) return;
    const uint32_t per_site = std::max<uint32_t>(8, static_cast<uint32_t>(h.per / 4));
    // What the hot surfaces give each other is a bounce more, within `bounces` as the rays' is.
    const bool deeper = level + 1 < settings_.bounces;
    stats_.hot_points += sites.size() * per_site;
    struct Shadows {
        std::vector<RTCRay> rays;  // per point: to the light, then from the site
        std::vector<Vec3> value, extra, through;  // extra: what the hot surfaces give each other
        std::vector<uint8_t> weak;
    };
    tbb::enumerable_thread_specific<Shadows> block_shadows;
    tbb::parallel_for(size_t{0}, sites.size(), [&](size_t s) {
        Shadows& local = block_shadows.local();
        local.rays.resize(2 * per_site);
        local.value.assign(per_site, Vec3{});
        local.extra.assign(per_site, Vec3{});
        local.through.resize(2 * per_site);
        local.weak.assign(2 * per_site, 0);
        const IcQuery& site = sites[s];
        const Vec3 o = site.position + site.normal * scene_.embree->epsilon_at(site.position);
        for (uint32_t k = 0; k < per_site; ++k) {
            RTCRay& to_light = local.rays[2 * k];
            RTCRay& from_site = local.rays[2 * k + 1];
            make_hole(to_light, 2 * k), make_hole(from_site, 2 * k + 1);
            const HotSurfaces::Point y = hot_->sample(random_at(site.key, level, RandomUse::kIcHot, 3 * k),
                                                     random_at(site.key, level, RandomUse::kIcHot, 3 * k + 1),
                                                     random_at(site.key, level, RandomUse::kIcHot, 3 * k + 2));
            const Vec3 to = y.position - o;
            const double t = length(to);
            if (!(t > 0) || !(y.pdf_area > 0)) continue;
            const Vec3 dir = to / t;
            const double cos_site = dot(site.normal, dir);
            if (!(cos_site > 0)) continue;
            const HotSurfaces::Reflected at_y =
                hot_->reflected(scene_, y, dir, t, HitRandom(hash_combine(site.key, 0x4075ull + k), static_cast<uint16_t>(level + 1)));
            if (!at_y.seen) continue;
            const double g = cos_site * at_y.cos_y / (t * t) / y.pdf_area;
            if (!(g > 0) || !std::isfinite(g)) continue;
            if (at_y.lit) {
                local.value[k] = at_y.to_light.value * g;
                aim_shadow_ray(to_light, at_y.to_light);
                local.weak[2 * k] = at_y.to_light.weak_target;
            }
            if (deeper) local.extra[k] = at_y.each_other * g;
            aim_shadow_ray(from_site, o, dir, std::max(0.0, t - at_y.epsilon));
        }
        trace_shadow_rays_in_this_task(scene_, local.rays.data(), local.weak.data(), local.through.data(), 2 * per_site);
        // A cell's radiance stands for pi / per of E (records_from()).
        const double to_radiance = static_cast<double>(h.per) / (kPi * per_site);
        Vec3 tangent, bitangent;  // as cast_hemispheres() lays out the cells
        orthonormal_basis(site.normal, tangent, bitangent);
        for (uint32_t k = 0; k < per_site; ++k) {
            if (is_hole(local.rays[2 * k + 1])) continue;
            const Vec3 direct = is_hole(local.rays[2 * k]) ? Vec3{} : local.value[k] * local.through[2 * k];
            const Vec3 e = (direct + local.extra[k]) * local.through[2 * k + 1] * to_radiance;
            if (!is_finite(e)) continue;
            const RTCRay& r = local.rays[2 * k + 1];
            const Vec3 d{r.dir_x, r.dir_y, r.dir_z};
            const double c = dot(d, site.normal), sin2 = std::clamp(1 - c * c, 0.0, 1.0);
            double turn = std::atan2(dot(d, bitangent), dot(d, tangent)) / (2 * kPi);
            if (turn < 0) turn += 1;
            const int j = std::min(h.M - 1, static_cast<int>(sin2 * h.M)), kk = std::min(h.N - 1, static_cast<int>(turn * h.N));
            h.radiance[s * h.per + static_cast<size_t>(j * h.N + kk)] += e;
        }
    });
}

// rho/pi E from records one level deeper (made now where missing), for every ray shading
// asked it for. This recurses through irradiance(): up to `bounces` batches are alive at once.
void IrradianceCache::add_next_bounce(Hemispheres& h, uint32_t level) {
    if (level + 1 >= settings_.bounces) return;
    size_t total = 0;
    for (const Hemispheres::NextBounce& next : h.next) total += next.queries.size();
    std::vector<IcQuery> q;
    std::vector<uint32_t> from;
    std::vector<Vec3> weight;
    q.reserve(total), from.reserve(total), weight.reserve(total);
    for (Hemispheres::NextBounce& next : h.next) {  // in block order; each block's freed once copied
        q.insert(q.end(), next.queries.begin(), next.queries.end());
        from.insert(from.end(), next.from.begin(), next.from.end());
        weight.insert(weight.end(), next.weight.begin(), next.weight.end());
        next = {};
    }
    std::vector<Vec3> e;
    irradiance(q, level + 1, e);
    if (stopped_) return;  // e is empty: the records of this level are dropped
    for (size_t k = 0; k < q.size(); ++k) h.radiance[from[k]] += weight[k] * e[k] / kPi;
}

// Per site: E, the harmonic mean distance of the first hits, and the Ward-Heckbert gradients.
std::vector<IrradianceRecord> IrradianceCache::records_from(const Hemispheres& h, const std::vector<IcQuery>& sites, uint32_t level) const {
    const int M = h.M, N = h.N;
    const size_t per = h.per;
    // The rings' terms depend on j alone: made once, not per cell of every site (an asin and a
    // tan per hemisphere ray).
    struct Ring {
        double minus_tan_theta, sin_minus, sin_plus;
    };
    std::vector<Ring> rings(static_cast<size_t>(M));
    for (int j = 0; j < M; ++j) {
        const double theta = std::asin(std::sqrt((j + 0.5) / M));
        rings[static_cast<size_t>(j)] = {-std::tan(std::min(theta, 1.5533)),  // 89 degrees at most
                                         std::sqrt(static_cast<double>(j) / M), std::sqrt(static_cast<double>(j + 1) / M)};
    }
    std::vector<IrradianceRecord> out(sites.size());
    tbb::parallel_for(size_t{0}, sites.size(), [&](size_t s) {
        const IcQuery& site = sites[s];
        Vec3 t, b;
        orthonormal_basis(site.normal, t, b);
        auto L = [&](int j, int k) { return h.radiance[s * per + static_cast<size_t>(j * N + k)]; };
        auto r = [&](int j, int k) {
            float d = h.first_distance[s * per + static_cast<size_t>(j * N + k)];
            return std::isfinite(d) && d > 0 ? static_cast<double>(d) : 1e30;
        };
        Vec3 sum{};
        double inv = 0;
        for (int j = 0; j < M; ++j)
            for (int k = 0; k < N; ++k) {
                sum += L(j, k);
                inv += 1 / r(j, k);
            }
        IrradianceRecord rec;
        rec.position = site.position;
        rec.normal = site.normal;
        rec.irradiance = sum * (kPi / static_cast<double>(per));
        double R = inv > 0 ? static_cast<double>(per) / inv : r_max_;
        rec.harmonic_distance = std::clamp(std::isfinite(R) ? R : r_max_, r_min_, r_max_);
        // Deeper bounces take the caustic at the site (blurred by interpolation, as all of
        // their light is); the camera's queries add it at their own point (irradiance()).
        if (caustics_ && level > 0) rec.irradiance += caustics_->irradiance(site.position, site.normal);
        rec.quality = static_cast<float>(level_accuracy(site.accuracy, level));
        rec.divisions = site.divisions;
        rec.level = static_cast<uint16_t>(level);
        // Rotation: (pi / MN) sum_k v_k sum_j (-tan theta_j) L_jk, v_k at phi_k + pi/2.
        // Translation: Ward and Heckbert's cell-boundary differences, distances min'ed.
        std::array<Vec3, 3> rot{}, tra{};
        auto add = [](std::array<Vec3, 3>& g, const Vec3& dir, const Vec3& l) {
            g[0] += dir * l.x, g[1] += dir * l.y, g[2] += dir * l.z;
        };
        for (int k = 0; k < N; ++k) {
            double phi = 2 * kPi * (k + 0.5) / N, phi_minus = 2 * kPi * k / N;
            Vec3 u_k = t * std::cos(phi) + b * std::sin(phi);
            Vec3 v_k = t * -std::sin(phi) + b * std::cos(phi);
            Vec3 v_minus = t * -std::sin(phi_minus) + b * std::cos(phi_minus);
            Vec3 rot_k{}, tra_u{}, tra_v{};
            for (int j = 0; j < M; ++j) {
                const Ring& ring = rings[static_cast<size_t>(j)];
                rot_k += L(j, k) * ring.minus_tan_theta;
                const double sin_minus = ring.sin_minus, sin_plus = ring.sin_plus;
                if (j > 0) {
                    double cos2 = 1 - sin_minus * sin_minus;
                    tra_u += (L(j, k) - L(j - 1, k)) * (sin_minus * cos2 / std::min(r(j, k), r(j - 1, k)));
                }
                int kp = (k + N - 1) % N;
                tra_v += (L(j, k) - L(j, kp)) * ((sin_plus - sin_minus) / std::min(r(j, k), r(j, kp)));
            }
            add(rot, v_k, rot_k * (kPi / static_cast<double>(per)));
            add(tra, u_k, tra_u * (2 * kPi / N));
            add(tra, v_minus, tra_v);
        }
        for (int c = 0; c < 3; ++c) {
            if (!is_finite(rot[static_cast<size_t>(c)])) rot[static_cast<size_t>(c)] = {};
            if (!is_finite(tra[static_cast<size_t>(c)])) tra[static_cast<size_t>(c)] = {};
        }
        rec.rotation = rot;
        rec.translation = tra;
        if (!is_finite(rec.irradiance)) rec.irradiance = {};
        rec.harmonic_distance = gradient_limited_radius(rec, r_min_);
        out[s] = rec;
    });
    return out;
}

}  // namespace crex
