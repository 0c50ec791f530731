/// \file scene_builders.h
/// Building scenes in code (the built-in scenes, tests): one line per material or shape.
#pragma once

#include <string>

#include "runtime/scene/scene.h"

namespace crex::build {

inline Material material(const std::string& name, MaterialType type, Vec3 color) {
    Material m;
    m.name = name;
    m.type = type;
    m.color = color;
    return m;
}

/// A planar quad a-b-c-d; it faces the side from which a, b, c run counter-clockwise.
inline Shape quad(const std::string& material, Vec3 a, Vec3 b, Vec3 c, Vec3 d, const std::string& name = "") {
    Shape s;
    s.type = ShapeType::kPolygon;
    s.material = material;
    s.name = name;
    s.vertices = {a, b, c, d};
    return s;
}

inline Shape sphere(const std::string& material, Vec3 center, double radius, const std::string& name = "") {
    Shape s;
    s.type = ShapeType::kSphere;
    s.material = material;
    s.name = name;
    s.center = center;
    s.radius = radius;
    return s;
}

}  // namespace crex::build
