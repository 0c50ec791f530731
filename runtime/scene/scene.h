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
#include "runtime/scene/texture_ref.h"

namespace crex {

/// RADIANCE's common material set (spec/crex.md §1 gives each one's component split).
enum class MaterialType {
    kVoid,        ///< absorbs everything, spawns nothing
    kPlastic,     ///< diffuse + uncoloured specular (G if rough, S if ideal)
    kMetal,       ///< diffuse + specular coloured by the material
    kTrans,       ///< plastic-like reflection + diffuse and specular transmission
    kGlass,       ///< glass: refracting T (1-F) and R (F); RADIANCE's thin pane (Material::thin_glass)
    kDielectric,  ///< dielectric interface with index n: T and R
    kMirror,      ///< ideal mirror: M
    kLight,       ///< emitter sampled for direct lighting
    kGlow,        ///< emitter sampled only within `glow_radius` (see Material::glow_radius)
    kIllum,       ///< emitter sampled for direct lighting; every other ray sees `alternate`
};

/// Anisotropic roughness (RADIANCE plastic2, metal2, trans2): the Ward lobe is `roughness`
/// wide along `orientation` projected onto the surface and `roughness_v` wide across it.
struct Anisotropy {
    Vec3 orientation{0, 0, 1};  ///< world direction; need not be unit length
    double roughness_v = 0;
};

/// A spotlight's cone (RADIANCE spotlight): light leaves only within `angle_deg` (full angle)
/// of `direction`, whose length is the distance of the focus behind the emitter.
struct Spot {
    double angle_deg = 180;
    Vec3 direction{0, 0, -1};
};

/// The medium outside a dielectric (RADIANCE interface); without it, the outside is vacuum.
struct OutsideMedium {
    Vec3 color{1, 1, 1};  ///< transmission per unit length of the outside medium (the inside's is `color`)
    double ior = 1;
};

/// A table of numbers over a grid (RADIANCE's data files): `axes` gives each dimension's
/// grid points, evenly spaced from `origin` to `origin + size` in `count` steps, or listed in
/// `points` (then origin and size are the first point and the span). `values` holds every
/// grid point's number, the last dimension varying fastest. Its meaning (interpolation and
/// what lies beyond the grid) is runtime/scene/data_table.h's.
struct DataTable {
    struct Axis {
        double origin = 0, size = 1;
        int count = 2;
        std::vector<double> points;  ///< uneven grids only
        bool operator==(const Axis&) const = default;
    };
    std::vector<Axis> axes;
    std::vector<double> values;
    bool operator==(const DataTable&) const = default;
};

/// A RADIANCE pattern on an emitter (`brightfunc`, `colorfunc`, `brightdata`, `colordata`,
/// `colorpict`): a factor per ray that multiplies the emitter's radiance, computed at render
/// time from the ray's direction, the hit point, the normal and the distance, in the
/// pattern's own coordinates, by expressions in RADIANCE's function language (its `.cal`
/// files). What luminaire distributions (ies2rad's `brightdata`) and photographed skies
/// (`colorpict` on a distant `glow`) are made of. Plain data: the function file's text, not
/// its name, so the scene is complete without the files.
struct FunctionPattern {
    enum class Kind { kBrightFunc, kColorFunc, kBrightData, kColorData, kColorPict, kBrightText, kColorText };
    Kind kind = Kind::kBrightFunc;
    std::string name;         ///< as the scene file names it (messages)
    std::string definitions;  ///< the function file's definitions ("" without one)
    /// func: 1 or 3 expressions, the factor (grey or RGB); data and pict: 1 or 3 names of
    /// functions applied to the values looked up (RADIANCE's `flatcorr`, `red`, ...).
    std::vector<std::string> functions;
    std::vector<std::string> coordinates;  ///< data, pict: one expression per dimension
    std::vector<DataTable> tables;         ///< brightdata: 1; colordata: 3
    std::string picture;                   ///< colorpict: the image file (absolute)
    /// text (RADIANCE's brighttext, colortext; runtime/scene/text_pattern.h): the font file's
    /// text and the lines; args then are the origin, right and down vectors, the colour inside
    /// letters and outside (1 or 3 numbers each) and the optional spacing.
    std::string font;
    std::vector<std::string> text;
    std::vector<double> args;              ///< A1..An of the expressions
    /// World to pattern coordinates (the inverse of the pattern's transform): rows of a 3x4
    /// matrix; directions and normals are also divided by `scale`, distances multiplied.
    std::array<double, 12> to_pattern{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    double scale = 1;
    bool operator==(const FunctionPattern&) const = default;
};

/// RADIANCE's BRTDfunc without its directional-diffuse functions: a trans-like surface whose
/// mirror reflection and straight-through transmission are colour functions of the ray
/// (RADIANCE's `Rdot`, `RdotP`, the hit point, ...), with constant diffuse reflectances for
/// its front and back and a constant diffuse transmittance.
struct SurfaceFunctions {
    FunctionPattern reflection;    ///< kColorFunc: the specular reflectance
    FunctionPattern transmission;  ///< kColorFunc: the specular transmittance
    Vec3 front_diffuse, back_diffuse, diffuse_transmit;
    bool operator==(const SurfaceFunctions&) const = default;
};

/// RADIANCE's plasfunc, metfunc and transfunc: a plastic, metal or trans whose specular part
/// answers direct light only, by a function of the light's direction (a BRDF shape, the
/// function file's own); every other ray sees a diffuse surface (`color` reflected, or with
/// the trans's transmissivity transmitted), as RADIANCE renders these types.
struct DirectionalFunction {
    /// kBrightFunc: the function called with the light's direction in its coordinates
    /// (RADIANCE's refl(x, y, z, solid angle)), RADIANCE's local frame (Ldx, Idx, ...) defined.
    FunctionPattern shape;
    Vec3 diffuse_reflect, diffuse_transmit;  ///< direct light's diffuse parts (RADIANCE's rdiff, tdiff)
    Vec3 reflect, transmit;                  ///< the function's weights in front and behind
    bool operator==(const DirectionalFunction&) const = default;
};

/// RADIANCE's prism1 and prism2: a surface that sends every ray meeting it on in one direction
/// (prism1) or two (prism2), each with a coefficient, functions of the ray in the function
/// file's coordinates; it stops shadow rays (RADIANCE lights through it only by virtual
/// sources, which crex does not make).
struct Redirection {
    FunctionPattern coefficient;  ///< kBrightFunc: the ray's weight
    FunctionPattern direction;    ///< kColorFunc: dx dy dz, its direction (taken unclamped)
    bool operator==(const Redirection&) const = default;
};

/// RADIANCE's mixfunc: at each point, the material is its foreground (the Material holding
/// this, a copy of it) with the probability `coefficient` gives there (clamped to [0, 1]),
/// else `background`.
struct Mixture {
    std::string background;        ///< a material defined before
    FunctionPattern coefficient;   ///< kBrightFunc: the foreground's share
    bool operator==(const Mixture&) const = default;
};

struct Material {
    std::string name;
    MaterialType type = MaterialType::kPlastic;
    Vec3 color{0.5, 0.5, 0.5};  ///< reflectance (plastic/metal/trans/mirror), transmission (glass; a
                                ///< dielectric's per unit length inside), radiance (light/glow/illum)
    double specularity = 0;     ///< plastic, metal, trans: fraction reflected specularly
    double roughness = 0;       ///< plastic, metal, trans: 0 = ideal specular (S), > 0 glossy (G)
    double transmissivity = 0;  ///< trans: fraction of non-specular light transmitted
    double transmitted_specular = 0;  ///< trans: fraction of transmitted light that is specular
    double ior = 1.52;          ///< glass, dielectric: index of refraction
    /// glass: RADIANCE's glass, a thin pane (rays pass through unbent; `color` is its
    /// transmissivity, and R and T hold the pane's inner reflections, as glass.c computes them).
    bool thin_glass = false;
    /// glow: > 0: sampled by direct lighting from points within this distance of it, seen by
    /// every other ray from farther away; 0: never sampled, seen by every ray; < 0: never
    /// lights the scene, seen only by camera rays and rays from ideal specular lobes.
    double glow_radius = 0;
    std::optional<Vec3> emission;  ///< any non-emitter may glow too (not sampled)
    /// An emission texture on a mesh is sampled by direct lighting (samples_textured_emission).
    /// False for surfaces that only show an image (glTF's unlit: a backdrop, baked lighting),
    /// whose light, often from large surfaces, rays find with less noise than samples do.
    bool emission_sampled = true;
    std::optional<Anisotropy> anisotropy;   ///< plastic, metal, trans
    std::optional<Spot> spot;               ///< light, illum
    std::optional<OutsideMedium> outside;   ///< dielectric
    /// illum: the material every ray but a shadow ray sees ("" = the surface is invisible).
    std::string alternate;
    /// plastic, metal, trans: blends the material towards a conductor of its colour (glTF's
    /// metallic): D scaled by (1 - metallic), the specular lobe (1 - metallic) s + metallic c.
    double metallic = 0;
    /// Fraction of light the surface stops (1 = opaque); below 1 a hit is a hole with the
    /// rest's probability for every ray (kBlend), or below `alpha_cutoff` always (kMask).
    double opacity = 1;
    AlphaMode alpha_mode = AlphaMode::kMask;
    double alpha_cutoff = 0.5;
    MaterialTextures textures;  ///< parameters taken from images instead of the constants above
    /// Factors multiplied in order (RADIANCE's patterns modifying the material, the nearest
    /// first): of the emitted radiance for light, glow and illum; of the colour at each hit
    /// for plastic, metal, trans and mirror.
    std::vector<FunctionPattern> patterns;
    /// trans: its lobes' weights at each hit from functions (RADIANCE's BRTDfunc); the
    /// constants above then only say which lobes there are.
    std::optional<SurfaceFunctions> surface_functions;
    /// plastic, trans: direct light's response from a function (RADIANCE's plasfunc, metfunc,
    /// transfunc); the constants above are what every other ray sees.
    std::optional<DirectionalFunction> directional;
    /// trans (all specular transmission): where the ray goes on instead (prism1, prism2).
    std::vector<Redirection> redirections;
    /// void: RADIANCE's antimatter. The shapes of this material bound a solid inside which the
    /// surfaces of these materials do not exist for any ray (a hole cut through a wall); the
    /// shapes themselves are never seen (as RADIANCE 5.4a renders them).
    std::vector<std::string> clips;
    /// A mixture: this material where the coefficient says so, `background` elsewhere.
    std::optional<Mixture> mixture;
};

enum class ShapeType { kSphere, kPolygon, kMesh, kBox, kRing, kCone, kCylinder };

/// What a task map and the on-screen distractor map know about an object.
struct Tag {
    std::string name;
    int task = 0;             ///< task value 0..3
    bool distractor = false;  ///< on-screen distractor (OSDM)
    bool operator==(const Tag&) const = default;
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
    /// mesh, optional: per-vertex texture coordinates and shading normals (each empty or one
    /// per vertex). Without normals a mesh is shaded flat.
    std::vector<std::array<double, 2>> uvs;
    std::vector<Vec3> normals;
    /// mesh, optional: per-vertex linear RGB that multiplies the material's colour (glTF's
    /// COLOR_0; its texture's colour too), one per vertex or none.
    std::vector<Vec3> colors;
    std::string file;                                  ///< mesh: the OBJ it came from, if any
    // box
    Vec3 min, max;
    // ring: center, normal, inner and outer radius; cone: p0, p1, r0, r1; cylinder: p0, p1, radius
    Vec3 normal;
    Vec3 p0, p1;
    double r0 = 0, r1 = 0;
    /// sphere, cone, cylinder: the front faces inward (RADIANCE bubble, cup, tube).
    bool inward = false;
};

/// RADIANCE's standard sky brightness (gensky's skybright.cal): a CIE sky above the horizon,
/// blending into the ground's brightness below it.
struct SkyModel {
    enum class Type { kClear = 1, kOvercast = 2, kUniform = 3, kIntermediate = 4 };
    Type type = Type::kClear;
    double zenith = 1;         ///< zenith brightness
    double ground = 0;         ///< ground plane brightness
    double normalization = 1;  ///< divides the clear and intermediate skies (depends on the sun)
    Vec3 sun{0, 0, 1};         ///< unit direction to the sun
};

/// A light source infinitely far away (RADIANCE `source`): the disk of directions within
/// half of `angle_deg` of `direction`. A `light` material makes it a sampled disk (the sun);
/// a `glow` makes it an environment that every escaping ray sees (a sky, the ground), sampled
/// by direct lighting too unless its glow radius is negative.
struct DistantLight {
    std::string name;
    std::string material;
    Vec3 direction{0, 0, 1};  ///< towards the source; need not be unit length
    double angle_deg = 0.5;   ///< full angle, in (0, 360]
    std::optional<SkyModel> sky;  ///< the brightness pattern multiplying the material's colour
    /// The studio's key light of a model without lights (model_defaults.h): placed from the
    /// camera, so a camera chosen or given after loading (--camera, --view) moves it too.
    bool studio_key = false;
};

/// How directions map to the image (RADIANCE's view types -vtv -vtl -vta -vth -vts -vtc).
enum class Projection {
    kPerspective,    ///< pinhole (-vtv)
    kParallel,       ///< orthographic: the fields of view are widths in scene units (-vtl)
    kAngular,        ///< fisheye, distance from the centre proportional to the angle (-vta)
    kHemispherical,  ///< fisheye, distance proportional to the angle's sine (-vth)
    kStereographic,  ///< fisheye, distance proportional to the tangent of half the angle (-vts)
    kCylindrical,    ///< panorama: angle across, perspective up and down (-vtc)
};

struct Camera {
    Vec3 position{0, 0, 5};
    Vec3 direction{0, 0, -1};  ///< need not be unit length
    Vec3 up{0, 1, 0};
    double vfov_deg = 45;      ///< full vertical field of view (parallel: height in scene units)
    double hfov_deg = 0;       ///< full horizontal field of view; 0 = from vfov and image aspect
    double view_distance = 1;  ///< viewer's distance to the display, in display widths (foveal angles)
    Projection projection = Projection::kPerspective;
    double fore_clip = 0;      ///< rays start this far along their direction (RADIANCE -vo)
};

/// Homogeneous single-scattering medium (RADIANCE "mist"): the whole scene, or an
/// axis-aligned box of it (a mist on a genbox).
struct Medium {
    Vec3 extinction{0, 0, 0};  ///< per scene unit
    Vec3 albedo{0, 0, 0};
    double eccentricity = 0;   ///< Henyey-Greenstein g in (-1, 1)
    bool bounded = false;      ///< only inside [box_min, box_max]
    Vec3 box_min, box_max;
};

/// A camera the scene file names (glTF cameras); `crex --camera NAME|INDEX` chooses one.
struct NamedCamera {
    std::string name;
    Camera camera;
};

/// What the scene's numbers mean, where the format says (glTF: metres, +y up); unknown
/// otherwise. Rendering needs neither; reports and people do.
struct SceneUnits {
    double metres_per_unit = 0;  ///< 0: not stated
    Vec3 up;                     ///< zero: not stated
};

struct Scene {
    std::string source;  ///< where it came from (a path or "builtin:cornell")
    Camera camera;
    std::vector<NamedCamera> cameras;  ///< the file's cameras, when it has several to choose from
    SceneUnits units;
    std::vector<EmbeddedImage> images;  ///< images carried in the scene file (texture references name them)
    Vec3 background{0, 0, 0};
    std::vector<Material> materials;
    std::vector<Shape> shapes;
    std::vector<DistantLight> distant_lights;
    std::optional<Medium> medium;
    /// False (RADIANCE's `-bv-`): a ray meeting the back of a surface goes on through it,
    /// unless the surface is a dielectric, an emitter, a BRTDfunc or a prism (as RADIANCE's);
    /// shadow rays are still blocked. A view from outside a closed room then looks in through
    /// its wall.
    bool back_faces_visible = true;

    const Material* find_material(const std::string& name) const;
};

}  // namespace crex
