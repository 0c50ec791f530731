// Scenes available without any file: `builtin:cornell` (the default scene of `crex run`) and
// `builtin:cornell_diffuse`. examples/scenes/cornell/ holds the same box as JSON and .rad.
#include "runtime/scene/load_scene.h"
#include "runtime/scene/scene_builders.h"

namespace crex {
namespace {

using build::quad;
using build::sphere;

Material diffuse(const std::string& name, Vec3 color) { return build::material(name, MaterialType::kPlastic, color); }

// The box spans [-1, 1]^3, open towards +z where the camera looks in from.
Scene cornell(bool with_specular_objects) {
    Scene s;
    s.source = with_specular_objects ? "builtin:cornell" : "builtin:cornell_diffuse";
    s.camera.position = {0, 0, 3.4};
    s.camera.direction = {0, 0, -1};
    s.camera.up = {0, 1, 0};
    s.camera.vfov_deg = 40;
    s.camera.hfov_deg = 40;
    s.materials.push_back(diffuse("white", {0.73, 0.73, 0.73}));
    s.materials.push_back(diffuse("red", {0.63, 0.065, 0.05}));
    s.materials.push_back(diffuse("green", {0.14, 0.45, 0.091}));
    s.materials.push_back(build::material("ceiling_light", MaterialType::kLight, {17, 12, 4}));
    s.shapes.push_back(quad("white", {-1, -1, 1}, {1, -1, 1}, {1, -1, -1}, {-1, -1, -1}, "floor"));
    s.shapes.push_back(quad("white", {-1, 1, -1}, {1, 1, -1}, {1, 1, 1}, {-1, 1, 1}, "ceiling"));
    s.shapes.push_back(quad("white", {-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, "back_wall"));
    s.shapes.push_back(quad("red", {-1, -1, 1}, {-1, -1, -1}, {-1, 1, -1}, {-1, 1, 1}, "left_wall"));
    s.shapes.push_back(quad("green", {1, -1, -1}, {1, -1, 1}, {1, 1, 1}, {1, 1, -1}, "right_wall"));
    // Light slightly below the ceiling, facing down.
    s.shapes.push_back(quad("ceiling_light", {-0.25, 0.998, -0.25}, {0.25, 0.998, -0.25}, {0.25, 0.998, 0.25}, {-0.25, 0.998, 0.25}, "light"));
    // Six outward-facing quads, as RADIANCE's genbox writes them (so the .rad twin matches).
    const Vec3 a{-0.7, -1, -0.7}, b{-0.1, 0.2, -0.1};
    s.shapes.push_back(quad("white", {a.x, a.y, a.z}, {a.x, a.y, b.z}, {a.x, b.y, b.z}, {a.x, b.y, a.z}, "tall_box.xmin"));
    s.shapes.push_back(quad("white", {b.x, a.y, a.z}, {b.x, b.y, a.z}, {b.x, b.y, b.z}, {b.x, a.y, b.z}, "tall_box.xmax"));
    s.shapes.push_back(quad("white", {a.x, a.y, a.z}, {b.x, a.y, a.z}, {b.x, a.y, b.z}, {a.x, a.y, b.z}, "tall_box.ymin"));
    s.shapes.push_back(quad("white", {a.x, b.y, a.z}, {a.x, b.y, b.z}, {b.x, b.y, b.z}, {b.x, b.y, a.z}, "tall_box.ymax"));
    s.shapes.push_back(quad("white", {a.x, a.y, a.z}, {a.x, b.y, a.z}, {b.x, b.y, a.z}, {b.x, a.y, a.z}, "tall_box.zmin"));
    s.shapes.push_back(quad("white", {a.x, a.y, b.z}, {b.x, a.y, b.z}, {b.x, b.y, b.z}, {a.x, b.y, b.z}, "tall_box.zmax"));
    if (with_specular_objects) {
        Material glass = build::material("glass", MaterialType::kGlass, {0.96, 0.96, 0.96});
        glass.ior = 1.5;
        s.materials.push_back(glass);
        s.materials.push_back(build::material("mirror", MaterialType::kMirror, {0.95, 0.95, 0.95}));
        s.shapes.push_back(sphere("glass", {0.45, -0.65, 0.3}, 0.35, "glass_ball"));
        s.shapes.push_back(sphere("mirror", {-0.4, 0.5, -0.4}, 0.3, "mirror_ball"));
    } else {
        s.shapes.push_back(sphere("white", {0.45, -0.65, 0.3}, 0.35, "white_ball"));
    }
    return s;
}

}  // namespace

std::vector<std::string> builtin_scene_names() { return {"cornell", "cornell_diffuse"}; }

std::optional<Scene> builtin_scene(const std::string& name) {
    if (name == "cornell") return cornell(true);
    if (name == "cornell_diffuse") return cornell(false);
    return std::nullopt;
}

}  // namespace crex
