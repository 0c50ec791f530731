#include "runtime/render/hot_surfaces.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "runtime/base/sampling.h"
#include "runtime/render/bsdf.h"
#include "runtime/render/shade.h"
#include "runtime/trace/trace_batch.h"

namespace crex {
namespace {

// The angle between unit vectors, accurate near 0 and pi (pbrt's AngleBetween).
double angle_between(const Vec3& a, const Vec3& b) {
    if (dot(a, b) < 0) return kPi - 2 * std::asin(std::min(1.0, 0.5 * length(a + b)));
    return 2 * std::asin(std::min(1.0, 0.5 * length(b - a)));
}

// The solid angle of triangle (v0, v1, v2) seen from p (Van Oosterom and Strackee).
double solid_angle(const Vec3& p, const Vec3& v0, const Vec3& v1, const Vec3& v2) {
    const Vec3 a = v0 - p, b = v1 - p, c = v2 - p;
    const double la = length(a), lb = length(b), lc = length(c);
    const double numerator = std::fabs(dot(a, cross(b, c)));
    const double denominator = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
    const double omega = 2 * std::atan2(numerator, denominator);
    return std::isfinite(omega) ? std::fabs(omega) : 0.0;
}

// A direction uniform in the solid angle of triangle v seen from p (Arvo 1995, as pbrt-v4's
// SampleSphericalTriangle), as the barycentrics (b1, b2) where it meets the triangle; false
// for a triangle too thin or too far to sample.
bool sample_spherical_triangle(const std::array<Vec3, 3>& v, const Vec3& p, double u0, double u1, double& b1, double& b2) {
    const Vec3 a = normalize_or_zero(v[0] - p), b = normalize_or_zero(v[1] - p), c = normalize_or_zero(v[2] - p);
    Vec3 n_ab = normalize_or_zero(cross(a, b)), n_bc = normalize_or_zero(cross(b, c)), n_ca = normalize_or_zero(cross(c, a));
    if (n_ab == Vec3{} || n_bc == Vec3{} || n_ca == Vec3{}) return false;
    const double alpha = angle_between(n_ab, -n_ca), beta = angle_between(n_bc, -n_ab), gamma = angle_between(n_ca, -n_bc);
    const double area_pi = alpha + beta + gamma;
    if (!(area_pi - kPi > 0)) return false;
    const double sampled = kPi + u0 * (area_pi - kPi);  // the sub-triangle's area plus pi
    const double cos_alpha = std::cos(alpha), sin_alpha = std::sin(alpha);
    const double sin_phi = std::sin(sampled) * cos_alpha - std::cos(sampled) * sin_alpha;
    const double cos_phi = std::cos(sampled) * cos_alpha + std::sin(sampled) * sin_alpha;
    const double k1 = cos_phi + cos_alpha, k2 = sin_phi - sin_alpha * dot(a, b);
    double cos_bp = (k2 + (k2 * cos_phi - k1 * sin_phi) * cos_alpha) / ((k2 * sin_phi + k1 * cos_phi) * sin_alpha);
    if (!std::isfinite(cos_bp)) return false;
    cos_bp = std::clamp(cos_bp, -1.0, 1.0);
    const double sin_bp = std::sqrt(std::max(0.0, 1 - cos_bp * cos_bp));
    const Vec3 cp = a * cos_bp + normalize_or_zero(c - a * dot(c, a)) * sin_bp;
    const double cos_t = 1 - u1 * (1 - dot(cp, b)), sin_t = std::sqrt(std::max(0.0, 1 - cos_t * cos_t));
    const Vec3 w = b * cos_t + normalize_or_zero(cp - b * dot(cp, b)) * sin_t;
    // Where w meets the triangle's plane (Moller-Trumbore), clamped into it.
    const Vec3 e1 = v[1] - v[0], e2 = v[2] - v[0], s1 = cross(w, e2);
    const double divisor = dot(s1, e1);
    if (!(std::fabs(divisor) > 0)) return false;
    const Vec3 s = p - v[0];
    b1 = std::clamp(dot(s, s1) / divisor, 0.0, 1.0);
    b2 = std::clamp(dot(w, cross(s, e1)) / divisor, 0.0, 1.0);
    if (b1 + b2 > 1) {
        const double sum = b1 + b2;
        b1 /= sum, b2 /= sum;
    }
    return std::isfinite(b1) && std::isfinite(b2);
}

}  // namespace

HotSurfaces::HotSurfaces(const RenderScene& scene) : embree_(*scene.embree) {
    if (!scene.lights || scene.lights->empty() || scene.medium) return;
    const auto& geometries = embree_.geometries();
    const double reach = kReach * embree_.extent();
    std::vector<std::vector<uint32_t>> hits(geometries.size());
    std::vector<std::vector<uint32_t>> lit_by(geometries.size());  // the first lamp whose rays met it
    std::vector<std::vector<int32_t>> front_lit(geometries.size());  // its rays that met its front, less those that met its back
    auto small_lamp = [&](const GeometryInfo& g) {
        return g.sphere && !g.inward && g.radius <= reach && scene.scene.materials[g.emitter].type == MaterialType::kLight;
    };
    const size_t lamps = static_cast<size_t>(std::count_if(geometries.begin(), geometries.end(), small_lamp));
    if (lamps == 0) return;
    // Bounded work on a scene of thousands of bulbs.
    const uint32_t probes = static_cast<uint32_t>(std::clamp<size_t>(kProbeBudget / lamps, kFewestProbeRays, kProbeRays));
    std::vector<RTCRayHit> rays(probes);
    for (uint32_t li = 0; li < geometries.size(); ++li) {
        const GeometryInfo& lamp = geometries[li];
        if (!small_lamp(lamp)) continue;
        // Evenly spread directions (a Fibonacci sphere) from just outside the bulb.
        const double golden = kPi * (3 - std::sqrt(5.0));
        for (uint32_t k = 0; k < probes; ++k) {
            const double z = 1 - 2 * (k + 0.5) / probes, r = std::sqrt(std::max(0.0, 1 - z * z)), phi = golden * k;
            const Vec3 d{r * std::cos(phi), r * std::sin(phi), z};
            const Vec3 o = lamp.center + d * (lamp.radius + embree_.epsilon_at(lamp.center, lamp.radius));
            set_ray(rays[k], static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z), static_cast<float>(d.x),
                    static_cast<float>(d.y), static_cast<float>(d.z), k);
            rays[k].ray.tfar = static_cast<float>(reach);
        }
        intersect_batch(embree_, rays.data(), rays.size(), false);
        auto hot = [&](const RTCRayHit& r) {
            if (r.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
            const GeometryInfo& g = geometries[r.hit.geomID];
            const Bsdf& b = scene.bsdf_of(r.hit.geomID);
            const bool opaque_reflector = b.type == MaterialType::kPlastic || b.type == MaterialType::kMetal;
            const bool holes = scene.cutouts && scene.cutouts->cuts_out(g.material);  // alpha-cut: points in its holes would shine
            return !g.sphere && opaque_reflector && !holes && !b.emits && !g.may_pass_shadows && max_component(b.diffuse) > 0;
        };
        if (static_cast<double>(std::count_if(rays.begin(), rays.end(), hot)) < kEnclosed * probes) continue;
        for (const RTCRayHit& r : rays) {
            if (!hot(r)) continue;
            const GeometryInfo& g = geometries[r.hit.geomID];
            if (hits[r.hit.geomID].empty())
                hits[r.hit.geomID].assign(g.indices.size(), 0), lit_by[r.hit.geomID].assign(g.indices.size(), 0), front_lit[r.hit.geomID].assign(g.indices.size(), 0);
            if (!hits[r.hit.geomID][r.hit.primID]) lit_by[r.hit.geomID][r.hit.primID] = li;
            if (lit_by[r.hit.geomID][r.hit.primID] != li) continue;
            ++hits[r.hit.geomID][r.hit.primID];
            const double facing = dot(g.normals[r.hit.primID], Vec3{r.ray.dir_x, r.ray.dir_y, r.ray.dir_z});
            front_lit[r.hit.geomID][r.hit.primID] += facing < 0 ? 1 : -1;
        }
    }
    double total = 0;
    index_.resize(geometries.size());
    for (uint32_t gi = 0; gi < hits.size(); ++gi)
        for (uint32_t p = 0; p < hits[gi].size(); ++p) {
            if (!hits[gi][p]) continue;
            const GeometryInfo& g = geometries[gi];
            const auto& t = g.indices[p];
            const Vec3 lamp = geometries[lit_by[gi][p]].center;
            const double omega = solid_angle(lamp, g.positions[t[0]], g.positions[t[1]], g.positions[t[2]]);
            if (!(omega > 1e-12)) continue;  // too thin to sample: its rays' own, as before
            if (index_[gi].empty()) index_[gi].assign(g.indices.size(), 0);
            // The side its lamp's rays met (a pole below a bulb is met nearly edge-on: the
            // direction from its middle to the bulb would not tell).
            const Vec3& n = g.normals[p];
            triangles_.push_back({gi, p, lamp, omega, front_lit[gi][p] >= 0 ? n : -n});
            index_[gi][p] = static_cast<uint32_t>(triangles_.size());
            // Chosen by the light it receives (the probe rays it took); sample() places the point.
            total += hits[gi][p];
            cdf_.push_back(total);
            probability_.push_back(hits[gi][p]);
        }
    for (size_t i = 0; i < cdf_.size(); ++i) cdf_[i] /= total, probability_[i] /= total;
    if (!cdf_.empty()) cdf_.back() = 1;
    solve_interreflection(scene);
}

void HotSurfaces::solve_interreflection(const RenderScene& scene) {
    const size_t count = triangles_.size();
    if (count == 0) return;
    // As many cells a side as the budget allows at kMostLinks samples each (4 for a shade or
    // two), down to one on scenes of many shades.
    cells_ = 4;
    while (cells_ > 1 && count * cells_ * cells_ * kMostLinks > kInterreflectionSamples) --cells_;
    const size_t used = count * cells_ * cells_, slots = 2 * count * cells_ * cells_;
    const uint32_t per = static_cast<uint32_t>(std::clamp<size_t>(kInterreflectionSamples / used, kFewestLinks, kMostLinks));
    interreflected_.assign(slots, Vec3{});
    // A ray from a cell's centre: the cell `to` it met, that point's direct light towards the
    // centre, and the factor that turns radiance from there into irradiance at the cell.
    struct Link {
        uint32_t to;
        double weight;
        Vec3 direct;
    };
    std::vector<std::vector<Link>> links(slots);
    const auto& geometries = embree_.geometries();
    tbb::parallel_for(size_t{0}, slots, [&](size_t cell) {
        const size_t ti = cell / (2 * cells_ * cells_), square = cell / 2 % (cells_ * cells_);
        const uint32_t i = static_cast<uint32_t>(square / cells_), j = static_cast<uint32_t>(square % cells_);
        const bool upper = cell % 2 == 1;
        if (i + j >= cells_ || (upper && i + j == cells_ - 1)) return;  // outside the triangle
        const Triangle& tri = triangles_[ti];
        const GeometryInfo& g = geometries[tri.geometry];
        const auto& v = g.indices[tri.primitive];
        const double third = upper ? 2.0 / 3 : 1.0 / 3, b1 = (i + third) / cells_, b2 = (j + third) / cells_;
        const Vec3 centre = g.positions[v[0]] * (1 - b1 - b2) + g.positions[v[1]] * b1 + g.positions[v[2]] * b2;
        const Vec3 o = centre + tri.lit_normal * embree_.epsilon_at(centre);
        // Cosine-weighted rays from the centre, stratified; those that meet a hot surface's lit
        // side take its direct light (one light sample, its shadow ray traced below). Each
        // stands for pi / per of the irradiance. Sampled from the cell rather than from the
        // lamp: points chosen by the lamp's light fell beside the cell as often as anywhere,
        // and their 1 / d^2 made the answer of a box's corners vary by a tenth between seeds.
        std::vector<RTCRayHit> first(per);
        const uint32_t strata = static_cast<uint32_t>(std::sqrt(static_cast<double>(per)));
        for (uint32_t k = 0; k < per; ++k) {
            const uint64_t key = hash_combine(0x407ull + cell, k);
            const double u1 = k < strata * strata ? (k / strata + random_at(key, 0, RandomUse::kHotLight, 0)) / strata : random_at(key, 0, RandomUse::kHotLight, 0);
            const double u2 = k < strata * strata ? (k % strata + random_at(key, 0, RandomUse::kHotLight, 1)) / strata : random_at(key, 0, RandomUse::kHotLight, 1);
            const Vec3 d = sample_cosine(tri.lit_normal, u1, u2);
            set_ray(first[k], static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z), static_cast<float>(d.x), static_cast<float>(d.y),
                    static_cast<float>(d.z), k);
        }
        intersect_batch(embree_, first.data(), first.size(), false);
        std::vector<RTCRay> rays(per);  // to the light from what each ray met
        std::vector<uint8_t> weak(per, 0);
        std::vector<Vec3> through(per);
        std::vector<Link> candidates(per, Link{0, 0.0, Vec3{}});
        for (uint32_t k = 0; k < per; ++k) {
            make_hole(rays[k], k);
            const RTCRayHit& r = first[k];
            if (r.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
            const int to = index_of(r.hit.geomID, r.hit.primID);
            const Vec3 dir{r.ray.dir_x, r.ray.dir_y, r.ray.dir_z};
            if (to < 0 || !(dot(dir, triangles_[static_cast<size_t>(to)].lit_normal) < 0)) continue;  // not a hot surface's lit side
            const double t = r.ray.tfar;
            HitFrame f = hit_frame(embree_, r.hit, o + dir * t, dir, t);
            Bsdf textured;
            const Bsdf& b = surface_at(scene, r.hit, f, textured, SurfaceDetail::kAveraged);
            ShadowSample light;
            if (!b.direct_response ||
                !direct_light_sample(scene, b, f, scene.lights->weights_at(f.position, horizon_of(b, f)), Vec3{1, 1, 1},
                                     HitRandom(hash_combine(0x407ull + cell, k), 1), 0, 1, light) ||
                !is_finite(light.value))
                light.value = {};
            else
                aim_shadow_ray(rays[k], light), weak[k] = light.weak_target;
            candidates[k] = {static_cast<uint32_t>(cell_of(static_cast<uint32_t>(to), r.hit.u, r.hit.v)), kPi / per, light.value};
        }
        trace_shadow_rays_in_this_task(scene, rays.data(), weak.data(), through.data(), rays.size());
        for (uint32_t k = 0; k < per; ++k) {
            if (!(candidates[k].weight > 0)) continue;
            Link l = candidates[k];
            l.direct = is_hole(rays[k]) ? Vec3{} : l.direct * through[k];
            links[cell].push_back(l);
        }
    });
    // Bounce after bounce: E(c) = sum over its samples of weight (direct + rho / pi E(to)),
    // until a bounce adds less than 1e-6 of the total. Each returns less than the last (rho < 1,
    // and the weights hold at most a hemisphere): a closed box of walls of 0.9 takes about 130.
    std::vector<Vec3> rho(slots), next(slots);
    for (size_t c = 0; c < slots; ++c) rho[c] = scene.bsdf_of(triangles_[c / (2 * cells_ * cells_)].geometry).diffuse * kInvPi;
    std::vector<Vec3>& e = interreflected_;
    double before = 0;
    for (int bounce = 0; bounce < 1000; ++bounce) {
        double total = 0;
        for (size_t c = 0; c < slots; ++c) {
            Vec3 sum;
            for (const Link& l : links[c]) sum += (l.direct + rho[l.to] * e[l.to]) * l.weight;
            next[c] = is_finite(sum) ? sum : Vec3{};
            total += luminance(next[c]);
        }
        e.swap(next);
        if (!(total - before > 1e-6 * total)) break;
        before = total;
    }
}

HotSurfaces::Reflected HotSurfaces::reflected(const RenderScene& scene, const Point& y, const Vec3& dir, double t,
                                              const HitRandom& random) const {
    Reflected r;
    const RTCHit hit = hit_at(y);
    HitFrame f = hit_frame(embree_, hit, y.position, dir, t);  // surface_at() may bend its shading normal
    if (!f.front && !scene.scene.back_faces_visible) return r;  // rays pass its back: the viewer sees through it
    r.cos_y = -dot(f.normal, dir);
    if (!(r.cos_y > 0)) return r;
    Bsdf textured;
    const Bsdf& b = surface_at(scene, hit, f, textured, SurfaceDetail::kAveraged);
    if (!b.direct_response) return r;
    r.seen = true;
    r.epsilon = f.epsilon;
    r.lit = direct_light_sample(scene, b, f, scene.lights->weights_at(f.position, horizon_of(b, f)), Vec3{1, 1, 1}, random, 0, 1, r.to_light);
    if (dot(dir, lit_normal(y.triangle)) < 0) r.each_other = b.diffuse * interreflected(y.triangle, y.b1, y.b2) * kInvPi;
    return r;
}

HotSurfaces::Point HotSurfaces::sample(double u0, double u1, double u2) const {
    const size_t i = std::min<size_t>(static_cast<size_t>(std::upper_bound(cdf_.begin(), cdf_.end(), u0) - cdf_.begin()), cdf_.size() - 1);
    const Triangle& tri = triangles_[i];
    const GeometryInfo& g = embree_.geometries()[tri.geometry];
    const auto& t = g.indices[tri.primitive];
    const std::array<Vec3, 3> v{g.positions[t[0]], g.positions[t[1]], g.positions[t[2]]};
    Point p;
    p.geometry = tri.geometry, p.primitive = tri.primitive, p.triangle = static_cast<uint32_t>(i);
    if (!sample_spherical_triangle(v, tri.lamp, u1, u2, p.b1, p.b2)) return p;
    p.position = v[0] * (1 - p.b1 - p.b2) + v[1] * p.b1 + v[2] * p.b2;
    // Uniform in solid angle: per unit area, the cosine at the point over its squared distance.
    const Vec3 to = p.position - tri.lamp;
    const double r2 = dot(to, to);
    const double cosine = std::fabs(dot(g.normals[tri.primitive], to)) / std::sqrt(r2);
    const double pdf = probability_[i] / tri.solid_angle * cosine / r2;
    p.pdf_area = std::isfinite(pdf) && pdf > 0 ? pdf : 0.0;
    return p;
}

}  // namespace crex
