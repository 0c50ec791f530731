#include "runtime/render/render_scene.h"

#include <algorithm>
#include <cmath>

#include "runtime/base/sampling.h"

namespace crex {

LightSampler::LightSampler(const Scene& scene, const EmbreeScene& embree) {
    for (const auto& g : embree.geometries()) {
        const Material& m = scene.materials[g.material];
        if (m.type != MaterialType::kLight || max_component(m.color) <= 0) continue;
        if (g.sphere) {
            Entry e;
            e.sphere = true;
            e.a = e.centre = g.center;
            e.b = {g.radius, 0, 0};
            e.radiance = m.color;
            e.area = 4 * kPi * g.radius * g.radius;
            entries_.push_back(e);
            continue;
        }
        for (const auto& t : g.indices) {
            Entry e;
            e.a = g.positions[t[0]];
            e.b = g.positions[t[1]];
            e.c = g.positions[t[2]];
            e.radiance = m.color;
            e.area = 0.5 * length(cross(e.b - e.a, e.c - e.a));
            e.normal = normalize_or_zero(cross(e.b - e.a, e.c - e.a));
            e.centre = (e.a + e.b + e.c) / 3.0;
            if (e.area > 0) entries_.push_back(e);
        }
    }
    double total = 0;
    for (const auto& e : entries_) total += e.area * std::fmax(luminance(e.radiance), 1e-12);
    double acc = 0;
    for (auto& e : entries_) {
        e.power = e.area * std::fmax(luminance(e.radiance), 1e-12);
        double p = e.power / total;
        e.pdf_area = p / e.area;
        acc += p;
        cdf_.push_back(acc);
    }
    if (!cdf_.empty()) cdf_.back() = 1.0;
}

void LightSampler::sample_sphere(const Entry& e, double u, double v, LightSample& s) {
    double z = 1 - 2 * u, r = std::sqrt(std::fmax(0.0, 1 - z * z)), phi = 2 * kPi * v;
    s.normal = {r * std::cos(phi), r * std::sin(phi), z};
    s.position = e.a + s.normal * e.b.x;
}

CameraRays::CameraRays(const Camera& c, int width, int height, const Vec3& origin_offset)
    : width_(width), height_(height) {
    origin_ = c.position - origin_offset;
    forward_ = normalize_or_zero(c.direction);
    right_ = normalize_or_zero(cross(forward_, c.up));
    up_ = cross(right_, forward_);
    tan_y_ = std::tan(c.vfov_deg * kPi / 360.0);
    const double aspect = static_cast<double>(width) / std::max(height, 1);
    tan_x_ = tan_y_ * aspect;
    if (c.hfov_deg > 0) {
        // Both fields of view given: pixels stay square, as rpict keeps them, by narrowing the
        // one the image's aspect cannot hold (a 128x64 render of a 40x40 degree view shows 40
        // degrees across and 20.6 down, instead of squashing spheres into ellipses).
        double tx = std::tan(c.hfov_deg * kPi / 360.0);
        if (tx / tan_y_ > aspect) tan_x_ = tan_y_ * aspect;
        else tan_x_ = tx, tan_y_ = tx / aspect;
    }
}

void CameraRays::generate(double px, double py, Vec3& origin, Vec3& direction) const {
    double sx = (2 * px / width_ - 1) * tan_x_;
    double sy = (1 - 2 * py / height_) * tan_y_;
    origin = origin_;
    direction = normalize_or_zero(forward_ + right_ * sx + up_ * sy);
}

RenderScene::RenderScene(const Scene& s) : scene(s) {
    embree = std::make_unique<EmbreeScene>(s);
    lights = std::make_unique<LightSampler>(s, *embree);
    for (const Material& m : s.materials) bsdfs.push_back(Bsdf::of(m));
    medium = medium_of(s);
}

}  // namespace crex
