// Scenes available without any file: `builtin:cornell` (the default scene of `crex run`) and
// `builtin:cornell_diffuse`. examples/scenes/cornell/ holds the same box as JSON and .rad.
#include "runtime/scene/load_scene.h"

namespace crex {
namespace {

Shape quad(const std::string& name, const std::string& material, Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
    Shape s;
    s.type = ShapeType::kPolygon;
    s.name = name;
    s.material = material;
    s.vertices = {a, b, c, d};
    return s;
}

Material diffuse(const std::string& name, Vec3 color) {
    Material m;
    m.name = name;
    m.type = MaterialType::kPlastic;
    m.color = color;
    return m;
}

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
    Material light;
    light.name = "ceiling_light";
    light.type = MaterialType::kLight;
    light.color = {17, 12, 4};
    s.materials.push_back(light);
    s.shapes.push_back(quad("floor", "white", {-1, -1, 1}, {1, -1, 1}, {1, -1, -1}, {-1, -1, -1}));
    s.shapes.push_back(quad("ceiling", "white", {-1, 1, -1}, {1, 1, -1}, {1, 1, 1}, {-1, 1, 1}));
    s.shapes.push_back(quad("back_wall", "white", {-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}));
    s.shapes.push_back(quad("left_wall", "red", {-1, -1, 1}, {-1, -1, -1}, {-1, 1, -1}, {-1, 1, 1}));
    s.shapes.push_back(quad("right_wall", "green", {1, -1, -1}, {1, -1, 1}, {1, 1, 1}, {1, 1, -1}));
    // Light slightly below the ceiling, facing down.
    s.shapes.push_back(quad("light", "ceiling_light", {-0.25, 0.998, -0.25}, {0.25, 0.998, -0.25},
                            {0.25, 0.998, 0.25}, {-0.25, 0.998, 0.25}));
    // Six outward-facing quads, as RADIANCE's genbox writes them (so the .rad twin matches).
    const Vec3 a{-0.7, -1, -0.7}, b{-0.1, 0.2, -0.1};
    s.shapes.push_back(quad("tall_box.xmin", "white", {a.x, a.y, a.z}, {a.x, a.y, b.z}, {a.x, b.y, b.z}, {a.x, b.y, a.z}));
    s.shapes.push_back(quad("tall_box.xmax", "white", {b.x, a.y, a.z}, {b.x, b.y, a.z}, {b.x, b.y, b.z}, {b.x, a.y, b.z}));
    s.shapes.push_back(quad("tall_box.ymin", "white", {a.x, a.y, a.z}, {b.x, a.y, a.z}, {b.x, a.y, b.z}, {a.x, a.y, b.z}));
    s.shapes.push_back(quad("tall_box.ymax", "white", {a.x, b.y, a.z}, {a.x, b.y, b.z}, {b.x, b.y, b.z}, {b.x, b.y, a.z}));
    s.shapes.push_back(quad("tall_box.zmin", "white", {a.x, a.y, a.z}, {a.x, b.y, a.z}, {b.x, b.y, a.z}, {b.x, a.y, a.z}));
    s.shapes.push_back(quad("tall_box.zmax", "white", {a.x, a.y, b.z}, {b.x, a.y, b.z}, {b.x, b.y, b.z}, {a.x, b.y, b.z}));
    if (with_specular_objects) {
        Material glass;
        glass.name = "glass";
        glass.type = MaterialType::kGlass;
        glass.color = {0.96, 0.96, 0.96};
        glass.ior = 1.5;
        s.materials.push_back(glass);
        Material mirror;
        mirror.name = "mirror";
        mirror.type = MaterialType::kMirror;
        mirror.color = {0.95, 0.95, 0.95};
        s.materials.push_back(mirror);
        Shape ball;
        ball.type = ShapeType::kSphere;
        ball.name = "glass_ball";
        ball.material = "glass";
        ball.center = {0.45, -0.65, 0.3};
        ball.radius = 0.35;
        s.shapes.push_back(ball);
        ball.name = "mirror_ball";
        ball.material = "mirror";
        ball.center = {-0.4, 0.5, -0.4};
        ball.radius = 0.3;
        s.shapes.push_back(ball);
    } else {
        Shape ball;
        ball.type = ShapeType::kSphere;
        ball.name = "white_ball";
        ball.material = "white";
        ball.center = {0.45, -0.65, 0.3};
        ball.radius = 0.35;
        s.shapes.push_back(ball);
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
