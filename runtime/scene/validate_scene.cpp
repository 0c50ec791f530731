// Checks every loader's result gets, whatever the format.
#include <fmt/format.h>

#include <cmath>
#include <set>

#include "runtime/scene/load_scene.h"
#include "runtime/scene/material.h"
#include "runtime/scene/shapes.h"

namespace crex {

const Material* Scene::find_material(const std::string& name) const {
    for (const auto& m : materials)
        if (m.name == name) return &m;
    return nullptr;
}

SceneBox scene_box(const Scene& scene) {
    SceneBox box;
    for (const auto& s : scene.shapes) expand_bounds(s, box.lo, box.hi);
    return box;
}

std::string camera_problem(const Camera& c, const SceneBox& box) {
    if (!is_finite(c.position) || !is_finite(c.direction) || !is_finite(c.up)) return "non-finite position, direction or up vector";
    // Camera rays span the plane across the direction and up: without it every ray is the same.
    if (!(length(cross(normalize_or_zero(c.direction), normalize_or_zero(c.up))) > 1e-6))
        return "looking along its up vector (or nowhere): it has no image plane";
    if (is_finite(box.hi - box.lo) && length(box.hi - box.lo) <= kMaxReach) {
        const double d = length(c.position - (box.lo + box.hi) * 0.5);
        if (!(d <= kMaxReach))
            return std::isfinite(d) ? fmt::format("{:.3g} units from the scene, more than float rays can represent ({:g})", d, kMaxReach)
                                    : fmt::format("farther from the scene than float rays can represent ({:g} units)", kMaxReach);
    }
    return "";
}

size_t sampled_light_count(const Scene& scene, bool textured_emission) {
    size_t lights = 0;
    for (const Shape& s : scene.shapes)
        if (const Material* m = scene.find_material(s.material);
            m && (textured_emission ? is_sampled_shape(*m, s) : is_sampled_emitter(*m)) && is_emissive(*m))
            ++lights;
    for (const DistantLight& l : scene.distant_lights)
        if (const Material* m = scene.find_material(l.material);
            m && (m->type == MaterialType::kLight || m->type == MaterialType::kGlow || m->type == MaterialType::kIllum) && is_emissive(*m) &&
            !(m->type == MaterialType::kGlow && m->glow_radius < 0))
            ++lights;
    return lights;
}

void validate_scene(const Scene& scene, DiagnosticSink& sink, const std::function<SourceSpan(size_t)>& locate) {
    const SceneBox box = scene_box(scene);
    const Vec3 lo = box.lo, hi = box.hi;
    std::set<std::string> over_bright;  // said once a material
    for (size_t i = 0; i < scene.shapes.size(); ++i) {
        const Shape& s = scene.shapes[i];
        const Material* m = scene.find_material(s.material);
        if (!m) {
            sink.report("E305", locate(i), fmt::format("shape uses material '{}', which is not defined", s.material));
            continue;
        }
        const auto problem = shape_problem(s);
        if (problem)
            sink.report("E306", locate(i), fmt::format("{}{}: {}", shape_type_name(s.type),
                                                       s.name.empty() ? "" : " '" + s.name + "'", *problem));
        else if (degenerate_polygon(s))
            sink.report("W304", locate(i), fmt::format("polygon{}: zero area for its size, so no normal: dropped",
                                                       s.name.empty() ? "" : " '" + s.name + "'"));
        else if (!polygon_fully_triangulated(s))
            sink.report("W308", locate(i), fmt::format("polygon{} crosses itself (or a hole winds the same way as its outline): "
                                                       "crex renders only part of it", s.name.empty() ? "" : " '" + s.name + "'"))
                .help = "a hole is a loop of vertices running the other way round, joined to the outline by a seam";
        if (s.type == ShapeType::kMesh) {
            size_t dropped = 0;
            TriangleMesh tm;
            if (!problem) tessellate(s, tm, &dropped);
            if (dropped > 0)
                sink.report("W303", locate(i), fmt::format("mesh{}: {} of {} triangles have zero area and are dropped",
                                                           s.name.empty() ? "" : " '" + s.name + "'", dropped, s.triangles.size()));
        }
        // Every format's emitters (a JSON scene's were refused where they are written).
        if (const double e = max_component(emitted_radiance(*m)); !(e <= kMaxRadiance) && !over_bright.count(m->name)) {
            over_bright.insert(m->name);
            sink.report("E303", locate(i), fmt::format("material '{}': radiance {:g} is beyond the {:g} crex can render (weighted "
                                                       "by a path, it would overflow the image's floats and come out black)",
                                                       m->name, e, kMaxRadiance));
        }
    }
    for (size_t i = 0; i < scene.distant_lights.size(); ++i) {
        const DistantLight& l = scene.distant_lights[i];
        const Material* m = scene.find_material(l.material);
        const std::string what = fmt::format("distant light{}", l.name.empty() ? "" : " '" + l.name + "'");
        if (!m) {
            sink.report("E305", locate(SIZE_MAX), fmt::format("{} uses material '{}', which is not defined", what, l.material));
            continue;
        }
        if (m->type != MaterialType::kLight && m->type != MaterialType::kGlow && m->type != MaterialType::kIllum)
            sink.report("E303", locate(SIZE_MAX), fmt::format("{}: its material '{}' must be a light or a glow, not {}", what, m->name,
                                                              material_type_name(m->type)));
        if (!is_finite(l.direction) || !(length(l.direction) > 0) || !(l.angle_deg > 0 && l.angle_deg <= 360))
            sink.report("E306", locate(SIZE_MAX), fmt::format("{}: the direction must be non-zero and the angle in (0, 360]", what));
        if (const double e = max_component(emitted_radiance(*m)) * (l.sky ? std::fmax(l.sky->zenith, l.sky->ground) : 1.0); !(e <= kMaxRadiance))
            sink.report("E303", locate(SIZE_MAX), fmt::format("{}: radiance {:g} is beyond the {:g} crex can render", what, e, kMaxRadiance));
    }
    if (!(max_component(scene.background) <= kMaxRadiance))
        sink.report("E303", locate(SIZE_MAX), fmt::format("background: radiance {:g} is beyond the {:g} crex can render",
                                                          max_component(scene.background), kMaxRadiance));
    if (is_finite(hi - lo) && length(hi - lo) > kMaxReach)
        sink.report("E303", locate(SIZE_MAX), fmt::format("the scene spans {:.3g} units: more than float rays can represent ({:g})",
                                                          length(hi - lo), kMaxReach));
    if (length(hi - lo) > 0 && length(hi - lo) < kMinSpan)  // 0: one point, which the shapes' own checks judge
        sink.report("E303", locate(SIZE_MAX), fmt::format("the scene spans {:.3g} units: less than float rays can resolve ({:g})",
                                                          length(hi - lo), kMinSpan))
            .help = "give its lengths in a smaller unit (micrometres instead of metres, say)";
    if (const std::string problem = camera_problem(scene.camera, box); !problem.empty()) {
        Diagnostic& d = sink.report("E303", locate(SIZE_MAX), "camera: " + problem);
        if (problem.find("from the scene") != std::string::npos) d.help = "move the camera closer, or scale the scene down";
    }
    if (scene.shapes.empty())
        sink.report("W302", locate(SIZE_MAX), "the scene has no shapes: the image will show the background only")
            .help = "give the scene shapes and a 'light' material (a 0-byte file is an empty scene)";
    else if (sampled_light_count(scene) == 0)
        sink.report("W302", locate(SIZE_MAX), "no shape or distant source is sampled by direct lighting (a light, an illum, "
                                              "a glow with a radius): direct lighting will be black")
            .help = "give an emitter the material type 'light' so it is sampled";
}

}  // namespace crex
