#include "runtime/cache/irradiance_cache.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <numbers>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include "base/input_file.h"
#include "runtime/base/atomic_file.h"
#include "runtime/base/sampling.h"
#include "runtime/cache/cbor_shape.h"
#include "runtime/render/bsdf.h"
#include "runtime/render/shade.h"
#include "runtime/trace/trace_batch.h"

namespace crex {
namespace {

double clamp_accuracy(double aa) { return std::isfinite(aa) ? std::clamp(aa, 1e-3, 1.0) : 1.0; }

}  // namespace

IrradianceCache::IrradianceCache(const RenderScene& scene, const IcSettings& settings) : scene_(scene), settings_(settings) {
    double extent = scene.embree->extent();
    r_min_ = settings.min_radius > 0 ? settings.min_radius : extent / (settings.resolution > 0 ? settings.resolution : 2000);
    r_max_ = settings.max_radius > 0 ? settings.max_radius : 0.25 * extent;
    r_max_ = std::max(r_max_, r_min_);
    // Local coordinates lie within the extent: float positions are off by at most 6e-8 of it
    // per coordinate, so a margin of 5e-7 of it keeps the float test conservative.
    position_slack_ = static_cast<float>(5e-7 * extent);
    max_aa_ = clamp_accuracy(settings.max_accuracy > 0 ? std::max(settings.max_accuracy, settings.accuracy) : settings.accuracy);
    // Validity radii lie in [aa_min r_min, r_max]: one grid level per halving.
    double top = 2 * r_max_;
    for (double c = top; c >= 2 * 1e-3 * r_min_ && cell_size_.size() < 24; c /= 2) cell_size_.push_back(c);
    if (settings.caustic_photons > 0) {
        const auto start = std::chrono::steady_clock::now();
        CausticPhotonSettings cs;
        cs.photons = settings.caustic_photons;
        cs.seed = settings.seed;
        caustics_ = std::make_unique<CausticPhotons>(scene, cs);
        if (caustics_->empty()) caustics_.reset();  // no delta shape or no emitter: nothing to add
        else stats_.caustic_photons = caustics_->size();
        stats_.caustic_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
}

IrradianceCache::~IrradianceCache() = default;

double IcStats::throughput_past_last_bounce() const {
    if (albedo_rays.empty()) return 0;
    double t = 1;
    for (size_t l = 0; l < albedo_rays.size(); ++l) t *= albedo_rays[l] > 0 ? albedo_sum[l] / static_cast<double>(albedo_rays[l]) : 0.0;
    return t;
}

double IrradianceCache::level_accuracy(double aa, uint32_t level) const {
    return clamp_accuracy(std::min(aa, max_aa_) * static_cast<double>(1u << std::min(level, 10u)));
}

uint64_t IrradianceCache::cell_key(int x, int y, int z) const {
    auto u = [](int v) { return static_cast<uint64_t>(static_cast<uint32_t>(v) & 0x1fffffu); };
    return (u(x) << 42) | (u(y) << 21) | u(z);
}

void IrradianceCache::insert(const IrradianceRecord& r) {
    uint32_t index = static_cast<uint32_t>(records_.size());
    records_.push_back(r);
    // The largest radius at which any query may use it: its level's coarsest accuracy times R.
    double rad = level_accuracy(max_aa_, r.level) * r.harmonic_distance;
    size_t L = 0;
    while (L + 1 < cell_size_.size() && cell_size_[L + 1] >= 2 * rad) ++L;
    double cell = cell_size_[L];
    int x0 = static_cast<int>(std::floor((r.position.x - rad) / cell)), x1 = static_cast<int>(std::floor((r.position.x + rad) / cell));
    int y0 = static_cast<int>(std::floor((r.position.y - rad) / cell)), y1 = static_cast<int>(std::floor((r.position.y + rad) / cell));
    int z0 = static_cast<int>(std::floor((r.position.z - rad) / cell)), z1 = static_cast<int>(std::floor((r.position.z + rad) / cell));
    for (int x = x0; x <= x1; ++x)
        for (int y = y0; y <= y1; ++y)
            for (int z = z0; z <= z1; ++z) {
                if (grids_.size() <= r.level) grids_.resize(r.level + 1u);
                if (grids_[r.level].empty()) grids_[r.level].resize(cell_size_.size());
                grids_[r.level][L].at(cell_key(x, y, z))
                    .push_back({static_cast<float>(r.position.x), static_cast<float>(r.position.y), static_cast<float>(r.position.z),
                                static_cast<float>(r.harmonic_distance), r.quality, index});
            }
}

bool IrradianceCache::lookup(const Vec3& x, const Vec3& n, double aa, uint32_t level, Vec3& e) const {
    aa = level_accuracy(aa, level);
    const double aa2 = aa * aa;
    double sum_w = 0;
    Vec3 sum{};
    if (level >= grids_.size()) return false;
    const std::vector<CellTable>& grids = grids_[level];
    const float xf = static_cast<float>(x.x), yf = static_cast<float>(x.y), zf = static_cast<float>(x.z);
    const float aa_f = static_cast<float>(aa) * 1.001f;
    for (size_t L = 0; L < grids.size(); ++L) {
        if (grids[L].empty()) continue;
        double cell = cell_size_[L];
        const std::vector<GridEntry>* entries = grids[L].find(cell_key(
            static_cast<int>(std::floor(x.x / cell)), static_cast<int>(std::floor(x.y / cell)), static_cast<int>(std::floor(x.z / cell))));
        if (!entries) continue;
        for (const GridEntry& g : *entries) {
            if (g.quality > aa + 1e-6) continue;  // never from records of lower quality
            // w > 1/aa needs |x - x_i| < aa R_i: most candidates fail this cheap test, first
            // on the entry (in float, with a margin), then exactly on the record.
            const float dx = xf - g.x, dy = yf - g.y, dz = zf - g.z, reach = aa_f * g.radius + position_slack_;
            if (!(dx * dx + dy * dy + dz * dz < reach * reach)) continue;
            const IrradianceRecord& r = records_[g.index];
            Vec3 dv = x - r.position;
            if (!(dot(dv, dv) < aa2 * r.harmonic_distance * r.harmonic_distance)) continue;
            double w = ward_weight(r, x, n);
            if (!(w > 1 / aa) || in_front(r, x, n)) continue;
            sum_w += w;
            sum += extrapolate(r, x, n) * w;
        }
    }
    if (!(sum_w > 0)) return false;
    e = sum / sum_w;
    return is_finite(e);
}

void IrradianceCache::irradiance(const std::vector<IcQuery>& queries, uint32_t level, std::vector<Vec3>& out) {
    using Clock = std::chrono::steady_clock;
    const auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
    const auto start = Clock::now();
    double lookups = 0;
    out.assign(queries.size(), Vec3{});
    std::vector<uint32_t> pending(queries.size());
    std::iota(pending.begin(), pending.end(), 0u);
    // Important pixels first: their records are made at their own (finer) accuracy.
    std::stable_sort(pending.begin(), pending.end(), [&](uint32_t a, uint32_t b) { return queries[a].priority > queries[b].priority; });
    stats_.lookups += queries.size();
    bool first = true;
    for (int round = 0; !pending.empty(); ++round) {
        // Lookups in parallel (the records do not change here); misses kept in order.
        std::vector<uint8_t> found(pending.size());
        const auto lookup_start = Clock::now();
        tbb::parallel_for(size_t{0}, pending.size(), [&](size_t k) {
            const IcQuery& q = queries[pending[k]];
            found[k] = lookup(q.position, q.normal, q.accuracy, level, out[pending[k]]) ? 1 : 0;
        });
        lookups += since(lookup_start);
        std::vector<uint32_t> misses;
        for (size_t k = 0; k < pending.size(); ++k)
            if (!found[k]) misses.push_back(pending[k]);
        if (first) stats_.interpolated += pending.size() - misses.size();
        first = false;
        if (misses.empty()) break;
        ++stats_.rounds;
        // Sites: sparse first, four times denser each round down to the cache's resolution
        // (records no closer than aa r_min, RADIANCE's -ar); after 8 rounds every miss is a site.
        // (Dropping to "every miss" as soon as the spacing passed r_min made a coarser -ar
        // create more records: 22,910 against 11,339 at -ar 32 on the Cornell box.)
        double spacing = round < 8 ? std::max(r_max_ / std::pow(4.0, round), r_min_) : 0;
        std::vector<IcQuery> sites;
        std::unordered_map<uint64_t, std::vector<uint32_t>> taken;  // spatial hash of chosen sites
        for (uint32_t q : misses) {
            const IcQuery& query = queries[q];
            double s = spacing * level_accuracy(query.accuracy, level);
            bool near = false;
            if (s > 0) {
                int cx = static_cast<int>(std::floor(query.position.x / s)), cy = static_cast<int>(std::floor(query.position.y / s)),
                    cz = static_cast<int>(std::floor(query.position.z / s));
                for (int dx = -1; dx <= 1 && !near; ++dx)
                    for (int dy = -1; dy <= 1 && !near; ++dy)
                        for (int dz = -1; dz <= 1 && !near; ++dz) {
                            auto t = taken.find(cell_key(cx + dx, cy + dy, cz + dz));
                            if (t == taken.end()) continue;
                            for (uint32_t si : t->second)
                                if (length(sites[si].position - query.position) < s && dot(sites[si].normal, query.normal) > 0.9) {
                                    near = true;
                                    break;
                                }
                        }
                if (!near) taken[cell_key(cx, cy, cz)].push_back(static_cast<uint32_t>(sites.size()));
            }
            if (!near) sites.push_back(query);
        }
        // In pieces of about 256 Ki hemisphere rays (~70 MB of rays, hits and throughputs),
        // so memory stays bounded: a piece's records ask the next bounce for theirs while its
        // buffers are alive, so up to `bounces` pieces are held at once (at 1 Mi rays a piece,
        // prog_dis_all at 512x512 peaked at 1.18 GB).
        size_t per_piece = std::max<size_t>(1, (size_t{1} << 18) / std::max(16u, settings_.divisions >> std::min(level, 16u)));
        for (size_t begin = 0; begin < sites.size(); begin += per_piece) {
            std::vector<IcQuery> piece(sites.begin() + static_cast<std::ptrdiff_t>(begin),
                                       sites.begin() + static_cast<std::ptrdiff_t>(std::min(sites.size(), begin + per_piece)));
            for (const auto& r : compute(piece, level)) insert(r);
            if (progress_) progress_(stats_);
        }
        pending = std::move(misses);
        if (round > 40) {  // cannot happen (a record covers its own site); never loop forever
            for (uint32_t q : pending) out[q] = settings_.ambient * kPi;
            break;
        }
    }
    const double before_caustics = since(start);
    if (caustics_ && level == 0)
        tbb::parallel_for(size_t{0}, queries.size(), [&](size_t q) { out[q] += caustics_->irradiance(queries[q].position, queries[q].normal); });
    if (level == 0) {
        stats_.lookup_seconds += lookups;
        stats_.record_seconds += before_caustics - lookups;
        stats_.caustic_lookup_seconds += since(start) - before_caustics;
    }
}

std::vector<IrradianceRecord> IrradianceCache::compute(const std::vector<IcQuery>& sites, uint32_t level) {
    const uint32_t ad = std::max(16u, settings_.divisions >> std::min(level, 16u));
    const int M = std::max(1, static_cast<int>(std::lround(std::sqrt(ad / kPi))));
    const int N = std::max(1, static_cast<int>(std::lround(static_cast<double>(ad) / M)));
    const size_t per = static_cast<size_t>(M) * static_cast<size_t>(N), n = sites.size() * per;
    stats_.records += sites.size();
    stats_.hemisphere_rays += n;
    const double eps = scene_.embree->ray_epsilon();
    std::vector<RTCRayHit> rays(n);
    std::vector<Vec3> dirs(n);
    tbb::parallel_for(size_t{0}, sites.size(), [&](size_t s) {
        Vec3 t, b;
        orthonormal_basis(sites[s].normal, t, b);
        for (int j = 0; j < M; ++j)
            for (int k = 0; k < N; ++k) {
                size_t i = s * per + static_cast<size_t>(j * N + k);
                uint32_t cell = static_cast<uint32_t>(j * N + k);
                double u = (j + random_at(sites[s].key, level, RandomUse::kIcTheta, cell)) / M;
                double phi = 2 * kPi * (k + random_at(sites[s].key, level, RandomUse::kIcPhi, cell)) / N;
                double sin_t = std::sqrt(u), cos_t = std::sqrt(std::fmax(0.0, 1 - u));
                Vec3 d = t * (sin_t * std::cos(phi)) + b * (sin_t * std::sin(phi)) + sites[s].normal * cos_t;
                dirs[i] = d;
                Vec3 o = sites[s].position + sites[s].normal * eps;
                set_ray(rays[i], static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z), static_cast<float>(d.x),
                        static_cast<float>(d.y), static_cast<float>(d.z), static_cast<unsigned>(i));
            }
    });
    intersect_batch(*scene_.embree, rays.data(), n, false);

    // Hemisphere rays that reach mirrors, glass or dielectrics continue through them (one lobe
    // chosen by its weight, up to 8 interfaces), so light arriving through them (caustics)
    // is in E. A translucent (trans) surface passes a ray through its specular transmission
    // with that lobe's share of the surface's weight, else the ray is shaded there, each
    // divided by its probability: without it, what a frosted screen lets through was missing
    // from E behind it. The first hit's distance stays what the harmonic mean uses.
    std::vector<RTCRayHit> last = rays;
    std::vector<Vec3> throughput(n, Vec3{1, 1, 1}), last_dir = dirs;
    // passed: the ray reached what it shades through a delta shape or a trans surface's
    // specular transmission (emitters are seen along it; `light` ones are the photon map's).
    std::vector<uint8_t> passed(n, 0), settled(n, 0);
    auto is_delta = [&](const RTCRayHit& h) {
        return h.hit.geomID != RTC_INVALID_GEOMETRY_ID && is_delta_material(scene_.material_of(h.hit.geomID).type);
    };
    auto ray_key = [&](size_t i) { return hash_combine(sites[i / per].key, 0x1c0000ull + i % per); };
    for (uint32_t bounce = 0; bounce < 8; ++bounce) {
        std::vector<size_t> go;
        std::vector<uint8_t> through_trans(n, 0);
        for (size_t i = 0; i < n; ++i) {
            if (settled[i] || last[i].hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
            if (is_delta(last[i])) {
                go.push_back(i);
                continue;
            }
            const double pass = transmission_share(scene_.bsdf_of(last[i].hit.geomID));
            if (!(pass > 0)) continue;
            if (random_at(ray_key(i), level * 16 + bounce, RandomUse::kIcTrans) < pass) {
                through_trans[i] = 1;
                go.push_back(i);
            } else {
                throughput[i] = throughput[i] / (1 - pass);
                settled[i] = 1;  // shaded here
            }
        }
        if (go.empty()) break;
        std::vector<RTCRayHit> batch(go.size());
        tbb::parallel_for(size_t{0}, go.size(), [&](size_t g) {
            size_t i = go[g];
            const RTCRayHit& h = last[i];
            Vec3 o{h.ray.org_x, h.ray.org_y, h.ray.org_z};
            double t = h.ray.tfar;
            HitFrame f = hit_frame(*scene_.embree, h.hit, o + last_dir[i] * t, last_dir[i], t);
            RTCRayHit& r = batch[g];
            r = RTCRayHit{};
            r.ray.tnear = 1.0f, r.ray.tfar = 0.0f;  // a hole unless a lobe is chosen
            r.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            r.ray.mask = 0xFFFFFFFFu;
            // Passing a trans surface is decided on the material's constants (above); the lobes
            // a ray scatters into are the surface's own.
            Bsdf textured;
            const Bsdf& b = through_trans[i] ? scene_.bsdf_of(h.hit.geomID) : surface_at(scene_, h.hit, f, textured);
            Lobe lobe;
            double prob = 0;
            if (through_trans[i]) {
                lobe = {Component::kT, last_dir[i], b.specular_transmit, true, true};
                prob = transmission_share(b);
            } else {
                std::array<Lobe, kMaxLobes> lobes;
                uint64_t key = ray_key(i);
                int nl = scatter(b, f, HitRandom(key, level * 16 + bounce + 1), lobes);
                const int pick = choose_lobe(lobes, nl, random_at(key, level * 16 + bounce, RandomUse::kIcLobe), prob);
                if (pick < 0) {
                    throughput[i] = {};
                    return;
                }
                lobe = lobes[static_cast<size_t>(pick)];
            }
            throughput[i] = throughput[i] * lobe.weight / prob;
            passed[i] = 1;
            Vec3 no = f.position + (lobe.transmits ? -f.normal : f.normal) * eps;
            last_dir[i] = lobe.direction;
            set_ray(r, static_cast<float>(no.x), static_cast<float>(no.y), static_cast<float>(no.z), static_cast<float>(lobe.direction.x),
                    static_cast<float>(lobe.direction.y), static_cast<float>(lobe.direction.z), static_cast<unsigned>(i));
        });
        intersect_batch(*scene_.embree, batch.data(), batch.size(), false);
        for (size_t g = 0; g < go.size(); ++g) last[go[g]] = batch[g];
    }

    // Radiance of every hemisphere ray: emission, one direct-light sample, the next bounce
    // (on the side the ray arrived from, and through a trans surface's diffuse transmission
    // on its other side).
    std::vector<Vec3> radiance(n), albedo(n), albedo_far(n);
    std::vector<RTCRay> shadows(n);
    std::vector<Vec3> shadow_value(n);
    std::vector<IcQuery> next(n), next_far(n);
    std::vector<uint8_t> wants_next(n, 0), wants_far(n, 0);
    const bool deeper = level + 1 < settings_.bounces;
    tbb::parallel_for(size_t{0}, n, [&](size_t i) {
        RTCRay& s = shadows[i];
        s = RTCRay{};
        s.tnear = 1.0f, s.tfar = 0.0f, s.dir_z = 1, s.mask = 0xFFFFFFFFu;  // a hole unless filled below
        const RTCRayHit& h = last[i];
        // In a medium, what the last segment reaches is seen through its transmittance (the
        // segments before it, inside glass, are not attenuated: a simplification).
        const Vec3 beta = scene_.medium ? throughput[i] * scene_.medium->transmittance(h.ray.tfar) : throughput[i];
        if (!(max_component(beta) > 0) || is_delta(h)) return;  // absorbed, or still inside glass
        if (h.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
            // Distant sources are direct lighting's, unless the ray came through glass or a mirror.
            Vec3 seen = scene_.scene.background;
            if (passed[i]) seen += scene_.lights->distant().escaped(normalize_or_zero(last_dir[i]));
            radiance[i] = beta * seen;
            return;
        }
        double dist = h.ray.tfar;
        Vec3 origin{h.ray.org_x, h.ray.org_y, h.ray.org_z};
        HitFrame f = hit_frame(*scene_.embree, h.hit, origin + last_dir[i] * dist, last_dir[i], dist);
        Bsdf textured;
        const Bsdf& b = surface_at(scene_, h.hit, f, textured);
        // Through a mirror, glass or a trans surface's specular transmission, emitters are
        // seen; a `light` emitter's light along those paths is the photon map's when there is
        // one (its photons follow the same lobes), else a rare ray onto a small bright lamp
        // seen through a frosted screen lit a whole record's disc behind it.
        const bool caustic = caustics_ && passed[i] && b.type == MaterialType::kLight;
        Vec3 l = caustic ? Vec3{} : emitted(b, f, passed[i] != 0, false);
        uint64_t key = ray_key(i);
        if (!scene_.lights->empty() && b.direct_response) {
            Vec3 value, so, sd;
            double tfar;
            if (direct_light_sample(scene_, b, f, beta, HitRandom(key, static_cast<uint16_t>(level + 1)), 0, 1, value, so, sd, tfar)) {
                aim_shadow_ray(s, so, sd, tfar);
                shadow_value[i] = value;
            }
        }
        albedo[i] = beta * b.diffuse;
        albedo_far[i] = beta * b.diffuse_transmit;
        l = l * beta;
        if (max_component(albedo[i]) > 0) {
            if (deeper) {
                next[i] = {f.position, f.shading, sites[i / per].accuracy, sites[i / per].priority, key};
                wants_next[i] = 1;
            } else {
                l += albedo[i] * settings_.ambient;  // av beyond the last bounce: rho/pi * (pi av)
            }
        }
        if (max_component(albedo_far[i]) > 0) {
            if (deeper) {
                next_far[i] = {f.position, -f.shading, sites[i / per].accuracy, sites[i / per].priority, hash_combine(key, 0xfa5ull)};
                wants_far[i] = 1;
            } else {
                l += albedo_far[i] * settings_.ambient;
            }
        }
        radiance[i] = is_finite(l) ? l : Vec3{};
    });
    // What the next level brings to this one, on average (IcStats): in order, so the same sum at
    // any thread count.
    if (stats_.albedo_sum.size() <= level) stats_.albedo_sum.resize(level + 1), stats_.albedo_rays.resize(level + 1);
    for (size_t i = 0; i < n; ++i)
        if (const Vec3 a = albedo[i] + albedo_far[i]; is_finite(a)) stats_.albedo_sum[level] += luminance(a);
    stats_.albedo_rays[level] += n;
    occluded_batch(*scene_.embree, shadows.data(), n);
    for (size_t i = 0; i < n; ++i) {
        const RTCRay& s = shadows[i];
        if (!(s.tnear > s.tfar && s.tfar == 0.0f) && s.tfar != -INFINITY) radiance[i] += shadow_value[i];
    }
    if (deeper) {
        std::vector<IcQuery> q;
        std::vector<size_t> from;
        std::vector<Vec3> weight;
        for (size_t i = 0; i < n; ++i) {
            if (wants_next[i]) q.push_back(next[i]), from.push_back(i), weight.push_back(albedo[i]);
            if (wants_far[i]) q.push_back(next_far[i]), from.push_back(i), weight.push_back(albedo_far[i]);
        }
        std::vector<Vec3> e;
        irradiance(q, level + 1, e);
        for (size_t k = 0; k < q.size(); ++k) radiance[from[k]] += weight[k] * e[k] / kPi;
    }

    // Per site: E, harmonic mean distance, and the Ward-Heckbert gradients.
    std::vector<IrradianceRecord> out(sites.size());
    tbb::parallel_for(size_t{0}, sites.size(), [&](size_t s) {
        const IcQuery& site = sites[s];
        Vec3 t, b;
        orthonormal_basis(site.normal, t, b);
        auto L = [&](int j, int k) { return radiance[s * per + static_cast<size_t>(j * N + k)]; };
        auto r = [&](int j, int k) {
            float d = rays[s * per + static_cast<size_t>(j * N + k)].ray.tfar;
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
                double theta = std::asin(std::sqrt((j + 0.5) / M));
                rot_k += L(j, k) * -std::tan(std::min(theta, 1.5533));  // 89 degrees at most
                double sin_minus = std::sqrt(static_cast<double>(j) / M), sin_plus = std::sqrt(static_cast<double>(j + 1) / M);
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
        out[s] = rec;
    });
    return out;
}

// The cache file (version 2): CBOR (nlohmann-json), a header of the settings the records
// depend on, and the records as one byte string of little-endian float32, kRecordFloats each
// (position, normal, E, R, rotation and translation gradients, quality, level). The JSON of
// version 1 took 19.6 MB for a 256x256 render's records; version-1 files are still read.
namespace {
constexpr size_t kRecordFloats = 30;

void put_floats(std::vector<std::uint8_t>& out, std::initializer_list<double> values) {
    for (double d : values) {
        float f = static_cast<float>(d);
        std::uint8_t b[4];
        std::memcpy(b, &f, 4);  // x86 and ARM Linux are little-endian; the header says so
        out.insert(out.end(), b, b + 4);
    }
}
}  // namespace

std::string IrradianceCache::save(const std::string& path) const { return write_file_atomically(path, to_bytes()); }

std::string IrradianceCache::to_bytes() const {
    nlohmann::json j;
    j["format"] = "crex-irradiance-cache";
    j["version"] = 2;
    j["settings"] = {{"divisions", settings_.divisions}, {"bounces", settings_.bounces}, {"min_radius", r_min_}, {"max_radius", r_max_},
                     {"extent", scene_.embree->extent()}, {"caustic_photons", caustics_ ? settings_.caustic_photons : 0u}};
    j["layout"] = "float32 little-endian x 30: p n e r rot[3] tra[3] q level";
    j["count"] = records_.size();
    std::vector<std::uint8_t> bytes;
    bytes.reserve(records_.size() * kRecordFloats * 4);
    for (const auto& r : records_) {
        put_floats(bytes, {r.position.x, r.position.y, r.position.z, r.normal.x, r.normal.y, r.normal.z, r.irradiance.x, r.irradiance.y,
                           r.irradiance.z, r.harmonic_distance});
        for (const auto& g : {r.rotation[0], r.rotation[1], r.rotation[2], r.translation[0], r.translation[1], r.translation[2]})
            put_floats(bytes, {g.x, g.y, g.z});
        put_floats(bytes, {r.quality, static_cast<double>(r.level)});
    }
    j["records"] = nlohmann::json::binary(std::move(bytes));
    std::vector<std::uint8_t> cbor = nlohmann::json::to_cbor(j);
    return std::string(cbor.begin(), cbor.end());
}

std::string IrradianceCache::load(const std::string& path) {
    std::string error;
    auto data = read_input_file(path, error, kMaxDataInputBytes);  // a regular file, bounded
    return data ? load_bytes(*data, path) : error;
}

namespace {

// The most irradiance this scene can give: every emitter, the background and the ambient value
// at their brightest, seen from the whole hemisphere, raised by inter-reflections of albedo up
// to 1 - 1e-6. A record beyond it (1e38 read from a damaged file) is not this scene's.
double brightest_irradiance(const Scene& scene, const Vec3& ambient) {
    double l = std::max(max_component(scene.background), max_component(ambient));
    for (const auto& m : scene.materials) {
        if (m.type == MaterialType::kLight || m.type == MaterialType::kGlow) l = std::max(l, max_component(m.color));
        if (m.emission) l = std::max(l, max_component(*m.emission));
    }
    return std::numbers::pi * l * 1e6;
}

// Why a record read from a file cannot be this scene's ("" if it can): everything finite, the
// position inside the scene, irradiance from 0 to what the scene can give, a positive radius.
std::string broken_record(const IrradianceRecord& r, double extent, double max_irradiance, uint32_t bounces) {
    if (!is_finite(r.position)) return "its position is not finite";
    if (std::fabs(r.position.x) > extent || std::fabs(r.position.y) > extent || std::fabs(r.position.z) > extent)
        return fmt::format("its position ({:g}, {:g}, {:g}) is outside the scene", r.position.x, r.position.y, r.position.z);
    if (!is_finite(r.normal) || normalize_or_zero(r.normal) == Vec3{}) return "its normal is zero or not finite";
    const Vec3& e = r.irradiance;
    if (!is_finite(e)) return "its irradiance is not finite (NaN or Inf)";
    if (std::min({e.x, e.y, e.z}) < 0) return fmt::format("its irradiance ({:g}, {:g}, {:g}) is negative", e.x, e.y, e.z);
    if (max_component(e) > max_irradiance)
        return fmt::format("its irradiance {:g} is beyond what this scene's emitters can give (at most {:g})", max_component(e), max_irradiance);
    for (size_t c = 0; c < 3; ++c)
        if (!is_finite(r.rotation[c]) || !is_finite(r.translation[c])) return "its gradients are not finite";
    if (!(r.harmonic_distance > 0) || !std::isfinite(r.harmonic_distance)) return "its harmonic distance is not a positive number";
    if (!(r.quality > 0 && r.quality <= 1)) return "its accuracy is not in (0, 1]";
    if (r.level > bounces) return fmt::format("its bounce {} is past the cache's {} bounces", r.level, bounces);
    return "";
}

// nlohmann's "[json.exception.type_error.302] type must be number, but is string" as
// "type must be number, but is string".
std::string plain_json_error(const std::exception& e) {
    std::string what = e.what();
    if (what.rfind("[json.exception.", 0) == 0)
        if (size_t at = what.find("] "); at != std::string::npos) what = what.substr(at + 2);
    return what;
}

}  // namespace

std::string IrradianceCache::load_bytes(const std::string& data, const std::string& path) {
    // Version 2 is CBOR; version 1 was JSON text. nlohmann's CBOR reader recurses per nesting
    // level and per chunk of an indefinite-length string: damaged bytes overflowed the stack
    // (SIGSEGV) before cbor_shape.h checked them, without recursion, first.
    const bool json_text = !data.empty() && data.front() == '{';
    if (!json_text)
        if (std::string shape = check_cbor_shape(std::vector<std::uint8_t>(data.begin(), data.end()), 8); !shape.empty())
            return "'" + path + "' is not a crex irradiance cache or is damaged: " + shape;
    auto j = json_text ? nlohmann::json::parse(data, nullptr, false) : nlohmann::json::from_cbor(data, true, false);
    // Compared as JSON values: value("format", "") threw out of load() when "format" was not
    // a string (found by tests/fuzz/ic_file_fuzzer.cpp).
    if (j.is_discarded() || !j.is_object() || !j.contains("format") || j.at("format") != "crex-irradiance-cache")
        return "'" + path + "' is not a crex irradiance cache";
    size_t records_in_file = 0;
    try {
        const auto& s = j.at("settings");
        // Records made with a caustic map leave caustics out (the map adds them), and records
        // made without one hold them: the two cannot be mixed.
        if (s.at("divisions").get<uint32_t>() != settings_.divisions || s.at("bounces").get<uint32_t>() != settings_.bounces ||
            s.value("caustic_photons", 0u) != (caustics_ ? settings_.caustic_photons : 0u) ||
            std::fabs(s.at("extent").get<double>() - scene_.embree->extent()) > 1e-6 * scene_.embree->extent())
            return "'" + path + "' was made with other cache settings or for another scene";
        auto v = [](const nlohmann::json& a) { return Vec3{a.at(0).get<double>(), a.at(1).get<double>(), a.at(2).get<double>()}; };
        std::vector<IrradianceRecord> loaded;
        const double extent = scene_.embree->extent(), max_irradiance = brightest_irradiance(scene_.scene, settings_.ambient);
        std::string broken;
        auto keep = [&](IrradianceRecord rec) -> bool {
            // Positions are local (recentred): a record far outside the scene sent insert()'s
            // grid indices past int (undefined behaviour); levels past `bounces` are no cache's;
            // an irradiance of 1e38 or -5 took the image's indirect light away (issue 37).
            if (std::string why = broken_record(rec, extent, max_irradiance, settings_.bounces); !why.empty()) {
                broken = fmt::format("'{}' holds a broken record: record {} of {}: {}; delete the file (crex makes the cache again)", path,
                                     loaded.size() + 1, records_in_file, why);
                return false;
            }
            rec.normal = normalize_or_zero(rec.normal);
            rec.harmonic_distance = std::clamp(rec.harmonic_distance, r_min_, r_max_);
            loaded.push_back(rec);
            return true;
        };
        const int version = j.value("version", 1);
        if (version == 2) {
            const auto& bin = j.at("records").get_binary();
            const size_t count = j.at("count").get<size_t>();
            records_in_file = count;
            if (bin.size() / (kRecordFloats * 4) != count || bin.size() % (kRecordFloats * 4) != 0)
                return fmt::format("'{}' is truncated: {} bytes of records for {}", path, bin.size(), count);
            std::vector<float> f(count * kRecordFloats);
            if (!f.empty()) std::memcpy(f.data(), bin.data(), bin.size());
            for (size_t i = 0; i < count; ++i) {
                const float* x = &f[i * kRecordFloats];
                IrradianceRecord rec;
                rec.position = {x[0], x[1], x[2]}, rec.normal = {x[3], x[4], x[5]}, rec.irradiance = {x[6], x[7], x[8]};
                rec.harmonic_distance = x[9];
                for (size_t c = 0; c < 3; ++c) {
                    rec.rotation[c] = {x[10 + 3 * c], x[11 + 3 * c], x[12 + 3 * c]};
                    rec.translation[c] = {x[19 + 3 * c], x[20 + 3 * c], x[21 + 3 * c]};
                }
                rec.quality = x[28];
                if (!(x[29] >= 0 && x[29] < 65536))
                    return fmt::format("'{}' holds a broken record: record {} of {}: its bounce is not a level", path, i + 1, count);
                rec.level = static_cast<uint16_t>(x[29]);
                if (!keep(rec)) return broken;
            }
        } else if (version == 1) {
            records_in_file = j.at("records").size();
            for (const auto& r : j.at("records")) {
                IrradianceRecord rec;
                rec.position = v(r.at("p")), rec.normal = v(r.at("n")), rec.irradiance = v(r.at("e"));
                rec.harmonic_distance = r.at("r").get<double>();
                for (size_t c = 0; c < 3; ++c) rec.rotation[c] = v(r.at("rot").at(c)), rec.translation[c] = v(r.at("tra").at(c));
                rec.quality = r.at("q").get<float>();
                rec.level = r.at("level").get<uint16_t>();
                if (!keep(rec)) return broken;
            }
        } else {
            return fmt::format("'{}' is a version {} cache; this crex reads versions 1 and 2", path, version);
        }
        for (const auto& r : loaded) insert(r);
    } catch (const std::exception& e) {  // a field missing or of another type
        return fmt::format("'{}' is damaged or not a crex irradiance cache ({}); delete it (crex makes the cache again)", path,
                           plain_json_error(e));
    }
    return "";
}

std::function<void(const RayBatch&, size_t, size_t, std::vector<Vec3>&)> executor_hook(
    IrradianceCache& cache, double aa, const std::vector<float>* aa_per_pixel, const std::vector<float>* priority,
    std::vector<IcAnswer>* log) {
    return executor_hook([&cache](const std::vector<IcQuery>& q, std::vector<Vec3>& e) { cache.irradiance(q, 0, e); }, aa, aa_per_pixel,
                         priority, log);
}

std::function<void(const RayBatch&, size_t, size_t, std::vector<Vec3>&)> executor_hook(
    IcAnswerFn answer, double aa, const std::vector<float>* aa_per_pixel, const std::vector<float>* priority,
    std::vector<IcAnswer>* log) {
    return [answer = std::move(answer), aa, aa_per_pixel, priority, log](const RayBatch& rays, size_t begin, size_t end, std::vector<Vec3>& e) {
        std::vector<IcQuery> q(end - begin);
        for (size_t i = begin; i < end; ++i) {
            uint32_t p = rays.pixel[i];
            IcQuery& x = q[i - begin];
            x.position = {rays.ox[i], rays.oy[i], rays.oz[i]};
            x.normal = normalize_or_zero(Vec3{rays.dx[i], rays.dy[i], rays.dz[i]});
            x.accuracy = aa_per_pixel ? (*aa_per_pixel)[p] : static_cast<float>(aa);
            x.priority = priority ? (*priority)[p] : 0.0f;
            x.key = rays.path[i];
        }
        answer(q, e);
        if (log)
            for (size_t i = begin; i < end; ++i) log->push_back({rays.get(i), e[i - begin], q[i - begin].accuracy});
    };
}

}  // namespace crex
