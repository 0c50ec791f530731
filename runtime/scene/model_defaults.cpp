// What a model file (OBJ, glTF) gets that it does not say: a camera, and light.
#include "runtime/scene/model_defaults.h"

#include <cmath>

#include "runtime/base/sampling.h"
#include "runtime/scene/load_scene.h"
#include "runtime/scene/material.h"

namespace crex {
namespace {

// The studio (model_defaults.h): the environment's radiance, the key light's added radiance on
// a white surface facing it, and its width.
constexpr double kStudioAmbient = 0.5, kStudioKey = 0.9, kStudioKeyAngleDeg = 5;

Vec3 studio_key_direction(const Camera& c) {
    const Vec3 forward = normalize_or_zero(c.direction), right = normalize_or_zero(cross(forward, c.up)), up = cross(right, forward);
    return normalize_or_zero(right * 0.4 + up * 0.8 - forward * 0.6);
}

}  // namespace

std::optional<Scene> light_unlit_model(std::optional<Scene> scene, DiagnosticSink& sink) {
    // A glowing screen or a lit dial (a textured emission) does not light a model as a studio
    // does: the studio is added unless the model has lamps of its own.
    if (!scene || scene->shapes.empty() || sampled_light_count(*scene, false) > 0 || max_component(scene->background) > 0) return scene;
    SourceSpan at;
    for (const Diagnostic& d : sink.diagnostics())
        if (d.code == "W302") at = d.span;
    sink.withdraw("W302");
    scene->background = Vec3{1, 1, 1} * kStudioAmbient;
    std::string name = "crex studio key";
    while (scene->find_material(name)) name += "'";
    // Its radiance over its solid angle makes an irradiance of pi x kStudioKey at normal incidence.
    const double solid_angle = 2 * kPi * (1 - std::cos(kStudioKeyAngleDeg * kPi / 360));
    Material key;
    key.name = name;
    key.type = MaterialType::kLight;
    key.color = Vec3{1, 1, 1} * (kPi * kStudioKey / solid_angle);
    scene->materials.push_back(key);
    DistantLight sun;
    sun.name = sun.material = name;
    sun.direction = studio_key_direction(scene->camera);
    sun.angle_deg = kStudioKeyAngleDeg;
    sun.studio_key = true;
    scene->distant_lights.push_back(sun);
    sink.report("W313", at, "nothing in the model lights it: it is lit as a model viewer lights it, by a uniform grey environment "
                            "(radiance 0.5, seen behind it) and a key light above, right of and behind the camera")
        .help = "to light it otherwise, give the file lights (glTF: KHR_lights_punctual or an emissive material; OBJ: a material "
                "with Ke) or name the OBJ from a JSON scene that has them (docs/scene-format.md)";
    return scene;
}

void aim_studio_key(Scene& scene) {
    for (DistantLight& l : scene.distant_lights)
        if (l.studio_key) l.direction = studio_key_direction(scene.camera);
}

void frame_model(Scene& scene) {
    const SceneBox box = scene_box(scene);
    const Vec3 centre = (box.lo + box.hi) * 0.5, size = box.hi - box.lo;
    const double radius = 0.5 * length(size);
    // Flat and facing z (a picture, a glTF test card): straight from +z; anything else from the
    // front, right and above, which sees three faces of a box and no flat thing edge-on.
    const bool faces_z = size.z <= 0.25 * std::fmax(size.x, size.y);
    const Vec3 towards_camera = faces_z ? Vec3{0, 0, 1} : normalize_or_zero(Vec3{0.5, 0.4, 1});
    scene.camera = Camera{};
    scene.camera.direction = -towards_camera;
    scene.camera.up = {0, 1, 0};
    // The bounding sphere within the 45-degree vertical field of view: radius / sin(22.5 deg).
    scene.camera.position = centre + towards_camera * (radius / std::sin(22.5 * kPi / 180) + 1e-9);
}

}  // namespace crex
