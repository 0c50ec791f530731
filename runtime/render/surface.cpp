#include "runtime/render/surface.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "runtime/base/sampling.h"
#include "runtime/render/render_scene.h"
#include "runtime/scene/shapes.h"

namespace crex {

void interpolate_uv(const GeometryInfo& g, const std::array<uint32_t, 3>& t, double b1, double b2, double& u, double& v) {
    const double b0 = 1 - b1 - b2;
    u = b0 * g.uvs[t[0]][0] + b1 * g.uvs[t[1]][0] + b2 * g.uvs[t[2]][0];
    v = b0 * g.uvs[t[0]][1] + b1 * g.uvs[t[1]][1] + b2 * g.uvs[t[2]][1];
}

namespace {

// Derivatives of a triangle's position in its (u, v) (pbrt's formula); zero when its texture
// coordinates are degenerate.
void triangle_dpduv(const GeometryInfo& g, const std::array<uint32_t, 3>& t, Vec3& dpdu, Vec3& dpdv) {
    const auto &uv0 = g.uvs[t[0]], &uv1 = g.uvs[t[1]], &uv2 = g.uvs[t[2]];
    const double du02 = double(uv0[0]) - uv2[0], dv02 = double(uv0[1]) - uv2[1];
    const double du12 = double(uv1[0]) - uv2[0], dv12 = double(uv1[1]) - uv2[1];
    const Vec3 dp02 = g.positions[t[0]] - g.positions[t[2]], dp12 = g.positions[t[1]] - g.positions[t[2]];
    const double det = du02 * dv12 - dv02 * du12;
    const double scale = std::fabs(du02 * dv12) + std::fabs(dv02 * du12);
    if (!(std::fabs(det) > 1e-9 * scale) || !(scale > 0)) {
        dpdu = dpdv = Vec3{};
        return;
    }
    dpdu = (dp02 * dv12 - dp12 * dv02) / det;
    dpdv = (dp12 * du02 - dp02 * du12) / det;
}

// The mesh's vertex colour at barycentrics (b1, b2) of triangle t.
Vec3 interpolate_color(const GeometryInfo& g, const std::array<uint32_t, 3>& t, double b1, double b2) {
    const auto &c0 = g.colors[t[0]], &c1 = g.colors[t[1]], &c2 = g.colors[t[2]];
    const double b0 = 1 - b1 - b2;
    auto channel = [&](int k) { return std::fmax(b0 * c0[size_t(k)] + b1 * c1[size_t(k)] + b2 * c2[size_t(k)], 0.0); };
    return {channel(0), channel(1), channel(2)};
}

// Least-squares (u, v) change for a position change `dp` on the surface (pbrt's), bounded.
void uv_change(const Vec3& dpdu, const Vec3& dpdv, const Vec3& dp, double& du, double& dv) {
    const double a00 = dot(dpdu, dpdu), a01 = dot(dpdu, dpdv), a11 = dot(dpdv, dpdv);
    const double det = a00 * a11 - a01 * a01;
    du = dv = 0;
    if (!(std::fabs(det) > 0) || !std::isfinite(det)) return;
    const double b0 = dot(dpdu, dp), b1 = dot(dpdv, dp);
    du = std::clamp((a11 * b0 - a01 * b1) / det, -1e8, 1e8);
    dv = std::clamp((a00 * b1 - a01 * b0) / det, -1e8, 1e8);
    if (!std::isfinite(du) || !std::isfinite(dv)) du = dv = 0;
}

uint64_t mix(uint64_t h, uint64_t x) {
    h ^= x + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h ^= h >> 31;
    h *= 0xbf58476d1ce4e5b9ull;
    return h ^ (h >> 29);
}

}  // namespace

PixelFootprint::PixelFootprint(const Camera& c, int width, int height, const Vec3& eye, double pixels) : eye_(eye) {
    // The same pinhole as CameraRays: forward, right and up, the image plane at distance 1.
    forward_ = normalize_or_zero(c.direction);
    const Vec3 right = normalize_or_zero(cross(forward_, c.up));
    const Vec3 up = cross(right, forward_);
    double tan_y = std::tan(c.vfov_deg * kPi / 360.0);
    const double aspect = static_cast<double>(width) / std::max(height, 1);
    double tan_x = tan_y * aspect;
    if (c.hfov_deg > 0) {
        const double tx = std::tan(c.hfov_deg * kPi / 360.0);
        if (tx / tan_y > aspect) tan_x = tan_y * aspect;
        else tan_x = tx, tan_y = tx / aspect;
    }
    right_step_ = right * (2 * tan_x * pixels / std::max(width, 1));
    down_step_ = up * (-2 * tan_y * pixels / std::max(height, 1));
    valid_ = forward_ != Vec3{} && right != Vec3{} && is_finite(right_step_) && is_finite(down_step_) && width > 0 && height > 0;
}

void PixelFootprint::at(const Vec3& p, const Vec3& n, Vec3& dpdx, Vec3& dpdy) const {
    dpdx = dpdy = Vec3{};
    if (!valid_) return;
    const Vec3 d = p - eye_;
    const double z = dot(d, forward_);
    if (!(z > 0)) return;  // behind the camera (a reflection's hit): no footprint, the sharpest lookup
    const Vec3 dir = d / z;  // through p, with unit depth
    const double plane = dot(d, n);
    auto meet = [&](const Vec3& step) {
        const Vec3 ray = dir + step;
        const double along = dot(ray, n);
        // Grazing: the neighbour's ray runs along the plane; bound the footprint by a hundred
        // times its size seen face on.
        const double face_on = length(d) * length(step);
        if (!(std::fabs(along) > 1e-12)) return Vec3{};
        Vec3 delta = ray * (plane / along) - d;
        const double len = length(delta);
        if (!std::isfinite(len)) return Vec3{};
        if (len > 100 * face_on) delta = delta * (100 * face_on / len);
        return delta;
    };
    dpdx = meet(right_step_);
    dpdy = meet(down_step_);
}

SceneCutouts::SceneCutouts(const Scene& scene, const SurfaceTextures* textures) : scene_(scene), textures_(textures) {
    clipped_by_.resize(scene.materials.size());
    for (const Material& a : scene.materials) {
        if (a.clips.empty()) continue;
        Solid s;
        s.lo = Vec3{INFINITY, INFINITY, INFINITY}, s.hi = -s.lo;
        for (const Shape& sh : scene.shapes) {
            if (sh.material != a.name) continue;
            TriangleMesh mesh;
            tessellate(sh, mesh);
            for (const auto& t : mesh.indices) {
                s.triangles.push_back({mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]});
                for (uint32_t k : t) s.lo = vmin(s.lo, mesh.positions[k]), s.hi = vmax(s.hi, mesh.positions[k]);
            }
        }
        if (s.triangles.empty()) continue;
        const auto index = static_cast<uint32_t>(solids_.size());
        solids_.push_back(std::move(s));
        for (const std::string& name : a.clips)
            for (uint32_t m = 0; m < scene.materials.size(); ++m)
                if (scene.materials[m].name == name) clipped_by_[m].push_back(index);
    }
}

bool SceneCutouts::any() const {
    for (uint32_t m = 0; m < scene_.materials.size(); ++m)
        if (cuts_out(m)) return true;
    return false;
}

bool SceneCutouts::Solid::inside(const Vec3& p) const {
    if (p.x < lo.x || p.y < lo.y || p.z < lo.z || p.x > hi.x || p.y > hi.y || p.z > hi.z) return false;
    // A direction no axis-aligned or diagonal edge lies along; Moller-Trumbore per triangle.
    const Vec3 d = normalize_or_zero(Vec3{0.5773, 0.5831, 0.5707});
    int crossings = 0;
    for (const auto& t : triangles) {
        const Vec3 e1 = t[1] - t[0], e2 = t[2] - t[0];
        const Vec3 q = cross(d, e2);
        const double det = dot(e1, q);
        if (std::fabs(det) < 1e-300) continue;
        const Vec3 s = p - t[0];
        const double a = dot(s, q) / det;
        if (a < 0 || a > 1) continue;
        const Vec3 r = cross(s, e1);
        const double b = dot(d, r) / det;
        if (b < 0 || a + b > 1) continue;
        if (dot(e2, r) / det > 0) ++crossings;
    }
    return crossings & 1;
}

bool SceneCutouts::solid(uint32_t geometry, uint32_t prim, float u, float v, const Vec3& origin, const Vec3& dir, float t) const {
    const GeometryInfo& g = embree_->geometries()[geometry];
    const Material& m = scene_.materials[g.material];
    SurfacePoint p;
    p.position = origin + dir * double(t) + embree_->origin_offset();
    if (g.material < clipped_by_.size())
        for (uint32_t s : clipped_by_[g.material])
            if (solids_[s].inside(p.position)) return false;  // inside an antimatter: no surface here
    if (!textures_ || !textures_->cuts_out(g.material)) return true;
    if (!g.sphere && !g.uvs.empty()) interpolate_uv(g, g.indices[prim], u, v, p.u, p.v);
    const double opacity = textures_->opacity(g.material, p);
    if (m.alpha_mode == AlphaMode::kMask) return opacity >= m.alpha_cutoff;
    // Blend: a hole with probability 1 - opacity, the same for the same ray and hit.
    uint64_t h = mix(geometry, prim);
    for (float x : {origin.x, origin.y, origin.z, dir.x, dir.y, dir.z}) h = mix(h, std::bit_cast<uint32_t>(x));
    const double xi = static_cast<double>(h >> 11) * 0x1.0p-53;
    return xi < opacity;
}

bool illum_front(const RenderScene& scene, const RTCHit& hit, const HitFrame& f) {
    const GeometryInfo& g = scene.embree->geometries()[hit.geomID];
    return f.front && g.emitter != g.material && scene.scene.materials[g.emitter].type == MaterialType::kIllum;
}

namespace {

// Material `material`'s textured values at the hit, its normal or bump map applied to f.shading.
MaterialValues textured_values(const RenderScene& scene, const RTCHit& hit, HitFrame& f, const GeometryInfo& g, uint32_t material,
                               SurfaceDetail detail) {
    SurfacePoint p;
    p.position = f.position + scene.embree->origin_offset();
    p.indirect = detail != SurfaceDetail::kSeen;
    p.coarse = detail == SurfaceDetail::kAveraged;
    Vec3 dpdu, dpdv;
    scene.footprint.at(f.position, f.normal, p.dpdx, p.dpdy);
    if (!g.sphere && !g.uvs.empty()) {
        const auto& tri = g.indices[hit.primID];
        interpolate_uv(g, tri, hit.u, hit.v, p.u, p.v);
        triangle_dpduv(g, tri, dpdu, dpdv);
        uv_change(dpdu, dpdv, p.dpdx, p.dudx, p.dvdx);
        uv_change(dpdu, dpdv, p.dpdy, p.dudy, p.dvdy);
    }
    // A normal or bump map's detail is left out where light is averaged over many hits: read
    // from a coarse copy it bent the normals of records' hits texel by texel, so deeper records
    // served fewer neighbours (18 % more records in a textured room), for detail that the
    // average over hundreds of hemisphere rays does not keep.
    if (detail != SurfaceDetail::kAveraged && scene.textures->perturbs_normal(material))
        f.shading = scene.textures->perturbed_normal(material, p, f.shading, dpdu, dpdv);
    return scene.textures->values(material, p);
}

}  // namespace

const Bsdf& surface_at(const RenderScene& scene, const RTCHit& hit, HitFrame& f, Bsdf& scratch, SurfaceDetail detail) {
    const GeometryInfo& g = scene.embree->geometries()[hit.geomID];
    uint32_t material = g.material;
    if (const MixtureChain* mix = scene.patterns ? scene.patterns->mixture(material) : nullptr) {
        // RADIANCE's mixfunc: the foreground (this material) with the coefficient's
        // probability here, decided by the point itself so that every ray meeting it agrees.
        PatternRay r = pattern_ray_at(f);
        const double share = mix->share(r);
        if (share < 1) {
            uint64_t h = 0x9e3779b97f4a7c15ull;
            for (double x : {f.position.x, f.position.y, f.position.z}) h = (h ^ std::bit_cast<uint64_t>(x)) * 0xff51afd7ed558ccdull, h ^= h >> 33;
            if (share <= 0 || static_cast<double>(h >> 11) * 0x1.0p-53 >= share) material = mix->background;
        }
    }
    const bool textured = scene.textures && scene.textures->textured(material);
    if (!g.vertex_normals.empty()) {
        // The mesh's shading normal, on the side the ray came from; a vertex normal that bends
        // past the geometric surface (bad data) leaves the geometric normal.
        const auto& tri = g.indices[hit.primID];
        const double b1 = hit.u, b2 = hit.v, b0 = 1 - b1 - b2;
        Vec3 n = normalize_or_zero(g.vertex_normals[tri[0]] * b0 + g.vertex_normals[tri[1]] * b1 + g.vertex_normals[tri[2]] * b2);
        if (dot(n, f.normal) < 0) n = -n;
        if (n != Vec3{} && dot(n, f.normal) > 1e-3) f.shading = n;
    }
    if (const SurfaceChains* sc = scene.patterns ? scene.patterns->surface(material) : nullptr) {
        // RADIANCE's BRTDfunc: its lobes' weights are functions of this ray.
        scratch = scene.bsdfs[material];
        PatternRay r = pattern_ray_at(f);
        sc->apply(r, scratch);
        return scratch;
    }
    if (const PatternChain* pc = scene.patterns && !scene.bsdfs[material].emits ? scene.patterns->of(material) : nullptr) {
        // RADIANCE's patterns on a surface material: its colour times theirs here.
        PatternRay r = pattern_ray_at(f);
        if (!g.sphere && !g.uvs.empty()) interpolate_uv(g, g.indices[hit.primID], hit.u, hit.v, r.u, r.v);
        const Material& m = scene.scene.materials[material];
        MaterialValues values = constant_values(m);
        values.color = values.color * pc->value(r);
        scratch = Bsdf::of(m, values);
        scratch.directional = scene.bsdfs[material].directional;
        scratch.redirect = scene.bsdfs[material].redirect;
        return scratch;
    }
    const bool colored = !g.sphere && !g.colors.empty();
    if (!textured && !colored) return scene.bsdfs[material];
    const Material& m = scene.scene.materials[material];
    MaterialValues values = textured ? textured_values(scene, hit, f, g, material, detail) : constant_values(m);
    if (colored) values.color = values.color * interpolate_color(g, g.indices[hit.primID], hit.u, hit.v);
    scratch = Bsdf::of(m, values);
    scratch.directional = scene.bsdfs[material].directional;
    scratch.redirect = scene.bsdfs[material].redirect;
    // Direct lighting samples a textured emission's front (its triangles' winding); its back,
    // which `emission` lights too, stays every ray's to find.
    scratch.emission_sampled = f.front && material == g.material && scene.lights && scene.lights->samples_emission(hit.geomID);
    return scratch;
}

}  // namespace crex
