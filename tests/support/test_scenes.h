/// \file test_scenes.h
/// Small scenes with known answers, built in code for the renderer's tests.
#pragma once

#include <cmath>
#include <string>

#include "compiler/crex/compile.h"
#include "runtime/driver/run_plan.h"
#include "runtime/scene/scene.h"
#include "runtime/scene/scene_builders.h"

namespace crex::testing {

using build::quad;

inline Material make_material(const std::string& name, MaterialType type, Vec3 color) {
    return build::material(name, type, color);
}

/// White furnace: a closed box [-1, 1]^3 of inward-facing diffuse walls of albedo `a` that all
/// emit `le` (an unsampled `emission`); the camera inside. Radiance everywhere: le / (1 - a).
inline Scene furnace_box(double a, double le) {
    Scene s;
    Material wall = make_material("wall", MaterialType::kPlastic, {a, a, a});
    wall.emission = Vec3{le, le, le};
    s.materials.push_back(wall);
    const double k = 1;
    s.shapes.push_back(quad("wall", {-k, -k, k}, {k, -k, k}, {k, -k, -k}, {-k, -k, -k}));   // floor, +y
    s.shapes.push_back(quad("wall", {-k, k, -k}, {k, k, -k}, {k, k, k}, {-k, k, k}));       // ceiling, -y
    s.shapes.push_back(quad("wall", {-k, -k, -k}, {k, -k, -k}, {k, k, -k}, {-k, k, -k}));   // back, +z
    s.shapes.push_back(quad("wall", {-k, -k, k}, {-k, k, k}, {k, k, k}, {k, -k, k}));       // front, -z
    s.shapes.push_back(quad("wall", {-k, -k, k}, {-k, -k, -k}, {-k, k, -k}, {-k, k, k}));   // left, +x
    s.shapes.push_back(quad("wall", {k, -k, -k}, {k, -k, k}, {k, k, k}, {k, k, -k}));       // right, -x
    s.camera.position = {0, 0, 0};
    s.camera.direction = {0, 0, -1};
    s.camera.vfov_deg = 90;
    return s;
}

/// A diffuse floor (albedo rho, y = 0, facing up) under a square `light` of radiance L, half
/// side `half`, at height h, facing down. The camera looks straight down at the point under
/// the light's centre through a narrow field of view.
inline Scene square_light_over_plane(double rho, double L, double half, double h) {
    Scene s;
    s.materials.push_back(make_material("floor", MaterialType::kPlastic, {rho, rho, rho}));
    s.materials.push_back(make_material("lamp", MaterialType::kLight, {L, L, L}));
    const double w = 50;
    s.shapes.push_back(quad("floor", {-w, 0, w}, {w, 0, w}, {w, 0, -w}, {-w, 0, -w}));
    s.shapes.push_back(quad("lamp", {-half, h, -half}, {half, h, -half}, {half, h, half}, {-half, h, half}));
    s.camera.position = {0, h / 2, 0};
    s.camera.direction = {0, -1, 0};
    s.camera.up = {0, 0, -1};
    s.camera.vfov_deg = 1;
    return s;
}

/// Irradiance at the point under the centre of a square emitter (half side `half`, height h,
/// radiance L), from the form factor of a rectangle to a parallel differential area:
/// E = 4 L (A / sqrt(1 + A^2)) atan(A / sqrt(1 + A^2)), A = half / h.
inline double irradiance_under_square(double L, double half, double h) {
    double a = half / h;
    double q = a / std::sqrt(1 + a * a);
    return 4 * L * q * std::atan(q);
}

/// The same scene moved by `shift` (shapes and camera), for far-from-the-origin tests.
inline Scene shifted(Scene s, const Vec3& shift) {
    for (auto& sh : s.shapes) {
        sh.center = sh.center + shift;
        for (auto& v : sh.vertices) v = v + shift;
    }
    s.camera.position = s.camera.position + shift;
    return s;
}

/// The scene with every length times k (shapes, the camera's place and fore clip; a perspective
/// camera's angles stay): the same image at any scale.
inline Scene scaled(Scene s, double k) {
    for (auto& sh : s.shapes) {
        sh.center = sh.center * k, sh.min = sh.min * k, sh.max = sh.max * k, sh.p0 = sh.p0 * k, sh.p1 = sh.p1 * k;
        sh.radius *= k, sh.r0 *= k, sh.r1 *= k;
        for (auto& v : sh.vertices) v = v * k;
    }
    s.camera.position = s.camera.position * k;
    s.camera.fore_clip *= k;
    return s;
}

inline sched::Program lower_or_die(const std::string& crex) {
    SourceFile f("<test>", crex);
    DiagnosticSink sink;
    CompiledCrex c = compile_crex(f, sink);
    if (!c.program) throw std::runtime_error("test crex does not compile: " + crex);
    return *c.program;
}

inline RunResult render_crex(const Scene& s, const std::string& crex, int size, uint32_t spp, uint64_t seed = 0,
                                uint32_t shadow_rays = 1) {
    RunSettings o;
    o.width = o.height = size;
    o.spp = spp;
    o.seed = seed;
    o.executor.shade.shadow_rays = shadow_rays;
    return render(s, lower_or_die(crex), o);
}

inline double mean_luminance(const std::vector<float>& rgb) {
    double sum = 0;
    size_t n = rgb.size() / 3;
    for (size_t i = 0; i < n; ++i) sum += 0.2126 * rgb[3 * i] + 0.7152 * rgb[3 * i + 1] + 0.0722 * rgb[3 * i + 2];
    return sum / static_cast<double>(n);
}

/// Mean over every channel of every pixel of the squared difference of two images.
inline double mean_squared_difference(const std::vector<float>& a, const std::vector<float>& b) {
    double sum = 0;
    for (size_t i = 0; i < a.size(); ++i) sum += (static_cast<double>(a[i]) - b[i]) * (static_cast<double>(a[i]) - b[i]);
    return sum / static_cast<double>(a.size());
}

/// A 4 x 4 diffuse floor (reflectance 0.6) under a square `emitter` material of half-width
/// `half` at height 1, facing down; seen from 0.6 above it, looking down, 90 degrees.
inline Scene floor_under(const Material& emitter, double half) {
    Scene s;
    s.materials.push_back(make_material("floor", MaterialType::kPlastic, {0.6, 0.6, 0.6}));
    s.materials.push_back(emitter);
    s.shapes.push_back(quad("floor", {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, {-2, 0, -2}));
    s.shapes.push_back(quad(emitter.name, {-half, 1, -half}, {half, 1, -half}, {half, 1, half}, {-half, 1, half}));
    s.camera.position = {0, 0.6, 0};
    s.camera.direction = {0, -1, 0};
    s.camera.up = {0, 0, -1};
    s.camera.vfov_deg = 90;
    return s;
}

/// A lamp in its shade over a floor: a bulb (a `light` of radius 2 cm) in an open cylinder
/// (radius 15 cm, 20 cm tall, reflectance 0.9) 1.5 above a diffuse floor, 4 x 4.
inline Scene lamp_in_a_shade() {
    Scene s = floor_under(make_material("unused", MaterialType::kPlastic, {0, 0, 0}), 0.01);
    s.shapes.pop_back();
    s.materials.push_back(make_material("bulb", MaterialType::kLight, {3000, 3000, 3000}));
    s.materials.push_back(make_material("shade", MaterialType::kPlastic, {0.9, 0.9, 0.9}));
    s.shapes.push_back(build::sphere("bulb", {0, 1.5, 0}, 0.02));
    Shape shade;
    shade.type = ShapeType::kCylinder, shade.material = "shade", shade.p0 = {0, 1.4, 0}, shade.p1 = {0, 1.6, 0}, shade.radius = 0.15;
    s.shapes.push_back(shade);
    return s;
}

/// What 16 samples a pixel do against a 1024-sample render of `crex` (24x24): `ratio` is their
/// error over what 16 independent samples would leave (a 1-sample render's error over 16: the
/// per-sample variance, the reference's own negligible), 1 for independent samples; `mean` the
/// 16-sample image's mean luminance over the reference's.
struct SixteenSamples {
    double ratio = 0, mean = 0;
};
inline SixteenSamples sixteen_samples_against_independent(const Scene& s, const std::string& crex) {
    const std::vector<float> ref = render_crex(s, crex, 24, 1024, 5).image();
    const std::vector<float> one = render_crex(s, crex, 24, 1, 1).image();
    const std::vector<float> sixteen = render_crex(s, crex, 24, 16, 1).image();
    const double v = mean_squared_difference(one, ref);
    return {v > 0 ? mean_squared_difference(sixteen, ref) / (v / 16) : NAN, mean_luminance(sixteen) / mean_luminance(ref)};
}

inline bool all_finite(const std::vector<float>& rgb) {
    for (float v : rgb)
        if (!std::isfinite(v)) return false;
    return true;
}

}  // namespace crex::testing

