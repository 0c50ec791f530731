/// \file shade.h
/// Executing a chunk of one bin: trace it (one stream call), shade every hit in parallel
/// (emission by the rule of spec §1, direct light through shadow rays traced as one batch,
/// children by lobe splitting with weight limit and depth limit), then merge in ray order so
/// the result does not depend on the thread count.
#pragma once

#include <algorithm>
#include <array>
#include <functional>
#include <vector>

#include "runtime/render/bsdf.h"
#include "runtime/render/camera_samples.h"
#include "runtime/render/ray_batch.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/shadow_pass.h"
#include "runtime/render/surface.h"

namespace crex {

/// Everything a render traced, for benchmarks that replay the same rays through raw Embree.
struct RayCapture {
    std::vector<RTCRayHit> rays;
    std::vector<RTCRay> shadow_rays;
};

struct ShadeParams {
    uint32_t shadow_rays = 1;       ///< shadow rays per hit; with a per-pixel table, its maximum
    /// Selective variables (spec/pipeline.md §1), per pixel when given:
    const std::vector<uint16_t>* shadow_rays_per_pixel = nullptr;  ///< each <= shadow_rays
    double specular_threshold = 0;  ///< S and G rays whose lobe weight is below it are not spawned
    const std::vector<float>* specular_threshold_per_pixel = nullptr;
    double weight_limit = 1e-3;     ///< `lw`
    bool roulette = true;           ///< below lw: Russian roulette (unbiased) instead of dropping
    uint32_t max_depth = 256;       ///< no ray is spawned beyond this depth
    RayCapture* capture = nullptr;  ///< benchmarks only: keep a copy of every ray traced
    /// With an irradiance cache, D "rays" are queries: origin at the hit, direction the normal
    /// on the side the light comes from (flag kRayIcQuery); the D step interpolates them.
    bool ic_queries = false;
    /// The scene's hot surfaces (hot_surfaces.h) are lights of every hit's direct light, and
    /// rays of diffuse and glossy lobes that meet them take no direct light there.
    bool hot_surface_lights = true;
    /// With a medium: single-scatter samples along each camera ray (`media_samples`; one along
    /// every other ray, none where it is 0); with a per-pixel table, its maximum.
    uint32_t media_samples = 1;
    const std::vector<uint16_t>* media_samples_per_pixel = nullptr;  ///< each <= media_samples
    /// Path tracing without the cache: the caustic photon map's irradiance at a point, on the
    /// side a unit normal points to (runtime/cache/caustic_photons.h). Set, a hit's diffuse lobe
    /// adds the light of paths L S+ D from the map, and its D ray reaching a `light` emitter
    /// through mirrors and glass alone brings nothing (kRayCausticPath): those rare rays onto a
    /// small lamp's image were the fireflies of a default render. Unset: path traced.
    std::function<Vec3(const Vec3&, const Vec3&)> caustic_irradiance;
};

/// Shadow rays for the direct light at a hit of a ray of `pixel` with `flags`: the pixel's
/// (shadow_rays, or its entry of the per-pixel table) on a surface the camera sees
/// (kRaySeenByCamera), where penumbrae show; one deeper, where the path's own sampling noise
/// dominates (at 8 rays at every bounce, direct light was a third of a path-traced render).
inline uint32_t shadow_rays_at(const ShadeParams& params, uint32_t pixel, uint8_t flags) {
    if (!(flags & kRaySeenByCamera)) return std::min<uint32_t>(params.shadow_rays, 1);
    return params.shadow_rays_per_pixel ? std::min<uint32_t>(params.shadow_rays, (*params.shadow_rays_per_pixel)[pixel]) : params.shadow_rays;
}

/// Rays are shaded in blocks of at most this many; each block spawns into its own buffers,
/// which are joined in block order, so bins do not depend on the thread count.
inline constexpr size_t kShadeBlock = 512;
/// A chunk of fewer than 16 full blocks is cut into 16 (of at least this many rays): most bins
/// of a crex's loop hold a few thousand rays, and in 512-ray blocks the last block of such a
/// chunk kept one thread busy while the others waited at the join.
inline constexpr size_t kMinShadeBlock = 64;
/// Rays per block for a chunk of n rays: n alone decides it, so the blocks, and the sums made
/// in block order, are the same at any thread count.
inline size_t shade_block_rays(size_t n) { return std::clamp<size_t>((n + 15) / 16, kMinShadeBlock, kShadeBlock); }

/// The shadow rays of one block of rays, traced as soon as the block is shaded
/// (its hits still in cache), only those aimed: a slot per possible shadow ray, most of them
/// empty where a deeper hit takes one of `--shadow-rays 8`, was written, skipped by Embree and
/// read back for nothing.
struct BlockShadows {
    std::vector<RTCRay> rays;
    std::vector<Vec3> value;
    std::vector<uint8_t> weak;     ///< aimed at a glow or an illum
    std::vector<uint32_t> owner;   ///< the ray of the chunk whose light it carries
    std::vector<Vec3> through;     ///< what the thin glass and trans it crossed let through
    /// The single-scatter samples of the ray being shaded, added after its direct light's (the
    /// order of a ray's sum).
    std::vector<ShadowSample> media;
    std::vector<RTCRay> captured;  ///< ShadeParams::capture: the rays as aimed, before tracing
    /// Shadow rays that a shadow ray's light must pass first: the light a hot surface's point
    /// reflects (hot_surface_sample()) is what reaches that point. Traced before the others;
    /// relay k scales the light of shadow ray relay_of[k].
    /// `relay_extra`: light the shadow ray carries whatever its relay meets.
    std::vector<RTCRay> relay;
    std::vector<uint8_t> relay_weak;
    std::vector<uint32_t> relay_of;
    std::vector<Vec3> relay_extra, relay_through;

    void clear() {
        rays.clear(), value.clear(), weak.clear(), owner.clear();
        relay.clear(), relay_weak.clear(), relay_of.clear(), relay_extra.clear();
    }
    size_t size() const { return rays.size(); }
    void add(const ShadowSample& sample, uint32_t ray) {
        rays.emplace_back();
        make_hole(rays.back(), ray);  // mask, flags and time; the aim below makes it a ray
        aim_shadow_ray(rays.back(), sample);
        value.push_back(sample.value);
        weak.push_back(sample.weak_target);
        owner.push_back(ray);
    }
    /// The light of the shadow ray added last must also pass `first`'s; `extra` it carries
    /// whatever `first` meets.
    void add_relay(const ShadowSample& first, const Vec3& extra) {
        relay.emplace_back();
        make_hole(relay.back(), static_cast<uint32_t>(relay.size() - 1));
        aim_shadow_ray(relay.back(), first);
        relay_weak.push_back(first.weak_target);
        relay_of.push_back(static_cast<uint32_t>(rays.size() - 1));
        relay_extra.push_back(extra);
    }
    /// Traces the relays and scales the light of the shadow rays they belong to.
    void trace_relays(const RenderScene& scene);
};

/// Per-chunk buffers, reused from chunk to chunk: allocating and zero-filling them for every
/// chunk cost more than a third of the executor's time (page faults and memset).
struct ShadeScratch {
    std::vector<RTCRayHit> hits;
    std::vector<BlockShadows> block_shadows;
    std::vector<uint32_t> block_hits, block_shadow_rays;  ///< per block, summed in block order
    std::vector<double> block_cut_by_depth, block_cut_by_weight;  ///< per block, as the SpawnScratch of each
};

struct ShadeOutput {
    std::vector<Vec3> contribution;  ///< per input ray, times its beta
    std::vector<Vec3> emission;      ///< camera rays: the emitted part of it
    /// Spawned rays, per block of input rays (shade_block_rays), per component.
    std::vector<std::array<RayBatch, kComponentCount>> block_children;
    /// The same, as records while a block is shaded (converted to arrays at its end).
    std::vector<std::array<std::vector<RayRecord>, kComponentCount>> block_spawned;
    size_t blocks = 0;  ///< blocks used by the last chunk
    uint64_t shadow_rays = 0;
    uint64_t hits = 0;
    /// Luminance of the throughput of the children the limits did not spawn (SpawnScratch).
    double cut_by_depth = 0, cut_by_weight = 0;
    ShadeScratch scratch;

    /// Ready for the next chunk, keeping every buffer's memory.
    void reset() {
        contribution.clear();
        emission.clear();
        for (auto& block : block_children)
            for (auto& c : block) c.reset();
        blocks = 0;
        shadow_rays = hits = 0;
        cut_by_depth = cut_by_weight = 0;
    }
    /// Appends the spawned rays to `bins`, in input ray order per component (each array of
    /// each bin is one task: a serial copy was 10 % of a 2-thread render).
    void append_children_to(std::array<RayBatch, kComponentCount>& bins) const;
    size_t children(Component c) const {
        size_t n = 0;
        for (size_t b = 0; b < blocks; ++b) n += block_children[b][static_cast<size_t>(c)].size();
        return n;
    }
};

/// One single-scatter sample (k of n) along the ray origin + t dir, t in [0, tmax] (tmax
/// infinite for a ray that leaves the scene): the light it gathers and its shadow ray. False:
/// nothing to trace.
bool single_scatter_sample(const RenderScene& scene, const MediumModel& medium, const Vec3& origin, const Vec3& dir, double tmax,
                           const Vec3& beta, const HitRandom& random, uint32_t k, uint32_t n, ShadowSample& out);

/// Shades rays [begin, end) of `rays`. `camera`: these are camera rays.
void trace_and_shade(const RenderScene& scene, const RayBatch& rays, size_t begin, size_t end, bool camera,
                     const ShadeParams& params, ShadeOutput& out);

/// Progressive direct light (thesis 8.2): the preview shaded its camera samples with `base`
/// shadow rays per hit; where a pixel's shadow_rays is now larger, each such sample's camera-hit
/// direct light is estimated again with that many rays, in place of the old estimate. The same
/// camera rays are traced again (same hits, same random numbers), so delta[i] = the new estimate
/// minus exactly what the preview added for ray i. `cached`: the preview had an irradiance
/// cache (LightSampling::glossy_cached). Returns the shadow rays traced.
uint64_t redo_camera_direct_light(const RenderScene& scene, const RayBatch& camera_rays, uint32_t base, bool cached,
                                  const std::vector<uint16_t>& shadow_rays_per_pixel, std::vector<Vec3>& delta);

/// The path id of the child spawned through lobe `index` (shared with the oracle).
inline uint64_t child_path(uint64_t parent, int lobe_index, Component c) {
    return (parent ^ (0x9e3779b97f4a7c15ull * (static_cast<uint64_t>(lobe_index) + 1))) * 0xff51afd7ed558ccdull +
           static_cast<uint64_t>(c);
}

/// The random numbers of a hit of `ray` (a camera ray's when `camera`: its lobes follow its
/// pixel's sequence, HitRandom::camera_hit). The bins and the oracle draw alike through it.
inline HitRandom hit_random(const RayRecord& ray, bool camera) {
    return camera ? HitRandom::camera_hit(ray.path, ray.depth, camera_pixel_key(ray.path), camera_sample_index(ray.path))
                  : HitRandom(ray.path, ray.depth);
}

/// The geometry of Embree's `hit` at `point` (the ray's origin plus t times its direction;
/// spheres put it back onto the surface), for a ray along unit `dir`.
inline HitFrame hit_frame(const EmbreeScene& scene, const RTCHit& hit, const Vec3& point, const Vec3& dir, double t) {
    const GeometryInfo& g = scene.geometries()[hit.geomID];
    Vec3 position, geometric;
    if (g.sphere) {
        Vec3 n = normalize_or_zero(point - g.center);
        if (n == Vec3{}) n = -dir;
        geometric = g.inward ? -n : n;       // a bubble faces its centre
        position = g.center + n * g.radius;  // back onto the surface: float error does not accumulate
    } else {
        // Embree's Ng (cross(v1 - v0, v2 - v0), as ours) and the ray's own point, whose error
        // (~1e-7 of its coordinates and of t) is far below the hit's epsilon: no vertex or
        // normal fetch, which on large meshes were cache misses at every hit.
        geometric = normalize_or_zero(Vec3{hit.Ng_x, hit.Ng_y, hit.Ng_z});
        if (geometric == Vec3{}) geometric = g.normals[hit.primID];  // underflowed in float
        if (geometric == Vec3{}) geometric = -dir;
        position = point;
    }
    const bool front = dot(dir, geometric) < 0;
    const Vec3 normal = front ? geometric : -geometric;
    // Every field named: a default-constructed frame filled in afterwards was zeroed first
    // (a `rep stos` of 136 bytes per hit).
    return HitFrame{.position = position,
                    .geometric = geometric,
                    .normal = normal,
                    .shading = normal,
                    .incoming = dir,
                    .front = front,
                    .distance = t,
                    .epsilon = scene.epsilon_at(position, t)};
}

/// Where spawn_children() works and leaves its result; made once per block of rays, not per
/// hit (zero-filling these arrays at every hit was 7 % of shading).
struct SpawnScratch {
    std::array<Lobe, kMaxLobes> lobes;
    std::array<RayRecord, kMaxLobes> children;
    std::array<Component, kMaxLobes> components;
    /// Light a truncated path leaves out, as the luminance of the throughput of the children
    /// not spawned, summed over the hits shaded with this scratch: past max_depth, and below
    /// lw without roulette (roulette's ends are unbiased: the survivors carry their weight).
    double cut_by_depth = 0, cut_by_weight = 0;
    /// The hit's light of paths L S+ D from the caustic map (ShadeParams::caustic_irradiance),
    /// set by each call: its diffuse lobes' weight times the irradiance over pi.
    Vec3 caustic;
};

/// Spawns the children of one hit into `out.children` (at most kMaxLobes); returns how many,
/// with their components in `out.components`. Applies weight limit, roulette and depth
/// limit. `random` is the hit's: HitRandom(ray.path, ray.depth).
int spawn_children(const Bsdf& b, const HitFrame& f, const RayRecord& ray, const HitRandom& random, const ShadeParams& params,
                   SpawnScratch& out);

/// Where a hit's light samples come from. Elsewhere: the hit's own n points (a Halton set
/// rotated by the hit's random numbers). At a camera hit: point sample * n + j of its pixel's
/// scrambled Sobol' sequence, so the light samples of all the pixel's camera samples are
/// stratified together (16 samples of one shadow ray spread over the lamp as one sample's
/// 16 rays would; independent ones left the direct light grainy at 16 spp).
struct LightSampling {
    bool pixel_sequence = false;
    uint32_t sample = 0;     ///< the camera sample's index in its pixel
    uint64_t pixel_key = 0;  ///< seeds the pixel's scramble
    /// The hit also takes glossy_light_sample(): the light samples' glossy share is weighed
    /// against it (multiple importance sampling). Off where nothing samples the glossy lobe's
    /// light (the irradiance cache's records, the hot surfaces' points).
    bool glossy_mis = false;
    /// The irradiance cache answers for the indirect light of a glossy lobe as wide as a
    /// diffuse one (glossy_like_diffuse()): its direct light is the light samples' alone.
    bool glossy_cached = false;
    static LightSampling camera_hit(uint64_t camera_path);
};

/// How the direct light at a hit of `ray` is sampled (a camera ray when `camera`): with how
/// many shadow rays (shadow_rays_at) and from which points (the pixel's sequence at a camera
/// hit, else the hit's own). The bins and the oracle shade alike through it.
struct HitLighting {
    uint32_t shadow_rays = 1;
    LightSampling sampling;
};
HitLighting hit_lighting(const ShadeParams& params, const RayRecord& ray, bool camera);

/// How finely a hit's textures are filtered: fully where the camera sees it (a camera ray, a
/// chain of S, T, R or M lobes from one), cheaply for every other.
inline SurfaceDetail surface_detail(bool camera, uint8_t flags) {
    return camera || (flags & kRaySeenByCamera) ? SurfaceDetail::kSeen : SurfaceDetail::kIndirect;
}

/// The horizon a hit's emitters are weighed against (LightSampler::weights_at): its normal
/// where the surface only reflects, none where light behind it counts too.
inline const Vec3* horizon_of(const Bsdf& b, const HitFrame& f) { return b.reflects_only ? &f.normal : nullptr; }

/// One direct-lighting sample j of n at a hit: the unoccluded contribution (beta included)
/// and the shadow ray to test; false if it contributes nothing. `weights` are the emitters'
/// at the hit (`scene.lights->weights_at(f.position, horizon_of(b, f))`), made once for its
/// n samples.
bool direct_light_sample(const RenderScene& scene, const Bsdf& b, const HitFrame& f, const LightSampler::LocalWeights& weights,
                         const Vec3& beta, const HitRandom& random, uint32_t j, uint32_t n, ShadowSample& out,
                         const LightSampling& sampling = {});

/// Whether a hit whose light is sampled by `sampling` weighs its glossy lobe's direct light
/// between its light samples and glossy_light_sample(): a glossy lobe of known density, and
/// emitters that LightSampler::along() can find.
inline bool weighs_glossy_light(const Bsdf& b, const LightSampler::LocalWeights& weights, const LightSampling& sampling) {
    return sampling.glossy_mis && glossy_pdf_known(b) && !(sampling.glossy_cached && glossy_like_diffuse(b)) && LightSampler::finds_along(weights);
}

/// The other half of a hit's glossy direct light (multiple importance sampling, Veach's power
/// heuristic, with the n light samples of direct_light_sample()): the direction its glossy
/// lobe draws (the G child's), and the emitter point it meets, if any, as a shadow sample.
/// A sharp lobe finds a large emitter's reflection this way where light samples landing in
/// it by chance were sparkles; light samples keep the small emitters and the rough lobes.
/// False where it brings nothing; only where weighs_glossy_light().
bool glossy_light_sample(const RenderScene& scene, const Bsdf& b, const HitFrame& f, const LightSampler::LocalWeights& weights,
                         const Vec3& beta, const HitRandom& random, uint32_t n, ShadowSample& out);

}  // namespace crex
