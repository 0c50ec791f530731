/// \file scene.h
/// The scene model: what every loader produces and the census, planner and renderer read.
/// Plain data (names instead of pointers), so a scene can be serialised, hashed and shipped.
/// Units are the scene's own (metres by convention); angles in degrees; colours linear RGB.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "runtime/base/vec3.h"

namespace crex {

/// RADIANCE's common material set (spec/crex.md §1 gives each one's component split).
enum class MaterialType {
    kVoid,        ///< absorbs everything, spawns nothing
    kPlastic,     ///< diffuse + uncoloured specular (G if rough, S if ideal)
    kMetal,       ///< diffuse + specular coloured by the material
    kTrans,       ///< plastic-like reflection + diffuse and specular transmission
    kGlass,       ///< thin or solid glass: T (1-F) and R (F)
    kDielectric,  ///< dielectric interface with index n: T and R
    kMirror,      ///< ideal mirror: M
    kLight,       ///< emitter sampled for direct lighting
    kGlow,        ///< emitter not sampled (adds emission on every ray)
};

struct Material {
    std::string name;
    MaterialType type = MaterialType::kPlastic;
    Vec3 color{0.5, 0.5, 0.5};  ///< reflectance (plastic/metal/trans/mirror), transmission (glass,
                                ///< dielectric), radiance (light/glow)
    double specularity = 0;     ///< plastic, metal, trans: fraction reflected specularly
    double roughness = 0;       ///< plastic, metal, trans: 0 = ideal specular (S), > 0 glossy (G)
    double transmissivity = 0;  ///< trans: fraction of non-specular light transmitted
    double transmitted_specular = 0;  ///< trans: fraction of transmitted light that is specular
    double ior = 1.52;          ///< glass, dielectric: index of refraction
    double glow_radius = 0;     ///< glow: maximum radius of influence (0 = everywhere)
    std::optional<Vec3> emission;  ///< any non-emitter may glow too (not sampled)
};

enum class ShapeType { kSphere, kPolygon, kMesh, kBox, kRing, kCone, kCylinder };

/// What a task map and the on-screen distractor map know about an object.
struct Tag {
    std::string name;
    int task = 0;             ///< task value 0..3
    bool distractor = false;  ///< on-screen distractor (OSDM)
};

struct Shape {
    ShapeType type = ShapeType::kSphere;
    std::string name;       ///< optional identifier (RADIANCE identifiers land here)
    std::string material;   ///< material name
    std::optional<Tag> tag;
    // sphere, ring
    Vec3 center;
    double radius = 0;  ///< sphere, cylinder
    // polygon (planar, >= 3 vertices) and mesh
    std::vector<Vec3> vertices;
    std::vector<std::array<uint32_t, 3>> triangles;  ///< mesh
    std::string file;                                  ///< mesh: the OBJ it came from, if any
    // box
    Vec3 min, max;
    // ring: center, normal, inner and outer radius; cone: p0, p1, r0, r1; cylinder: p0, p1, radius
    Vec3 normal;
    Vec3 p0, p1;
    double r0 = 0, r1 = 0;
};

struct Camera {
    Vec3 position{0, 0, 5};
    Vec3 direction{0, 0, -1};  ///< need not be unit length
    Vec3 up{0, 1, 0};
    double vfov_deg = 45;      ///< full vertical field of view
    double hfov_deg = 0;       ///< full horizontal field of view; 0 = from vfov and image aspect
    double view_distance = 1;  ///< viewer's distance to the display, in display widths (foveal angles)
};

/// Homogeneous single-scattering medium filling the scene (RADIANCE "mist").
struct Medium {
    Vec3 extinction{0, 0, 0};  ///< per scene unit
    Vec3 albedo{0, 0, 0};
    double eccentricity = 0;   ///< Henyey-Greenstein g in (-1, 1)
};

struct Scene {
    std::string source;  ///< where it came from (a path or "builtin:cornell")
    Camera camera;
    Vec3 background{0, 0, 0};
    std::vector<Material> materials;
    std::vector<Shape> shapes;
    std::optional<Medium> medium;

    const Material* find_material(const std::string& name) const;
};

}  // namespace crex
