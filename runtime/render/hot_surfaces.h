// Surfaces a small lamp lights from up close, such as the inside of its shade: many times as
// bright as the room around them, and seen from a wall or an irradiance record's hemisphere
// through the shade's openings only. Rays that met them by chance made a record several times
// too bright or left it dark (blotches on the walls and ceiling), and glossy rays that met them
// made white specks everywhere. Their direct light is sampled as a light of its own instead, as
// RADIANCE's mkillum turns such surfaces into light sources by hand: by each record
// (record_hemispheres.cpp, add_hot_surfaces()) and by each hit's direct light (shade.cpp,
// hot_surface_sample()), both through reflected(); rays of diffuse and glossy lobes that meet
// them take no direct light there.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "runtime/base/sampling.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/shadow_pass.h"

namespace crex {

class HotSurfaces {
public:
    /// Surfaces within this share of the scene's extent of a spherical `light` whose radius is
    /// no larger: a lamp's shade, the top of its pole, a desk under a desk lamp.
    static constexpr double kReach = 0.05;
    /// Rays cast from each such lamp's centre to find them; fewer (down to kFewestProbeRays)
    /// where there are so many lamps that all of them would cast more than kProbeBudget.
    static constexpr uint32_t kProbeRays = 4096, kFewestProbeRays = 256, kProbeBudget = 1u << 20;
    /// A lamp counts when at least this share of its rays meet them: one its shade (a sconce, a
    /// lantern) mostly encloses, so that they, not the bulb, light the room. A bulb over a desk
    /// lights a desk top that records' rays see as a wide patch, and sampling it as a light
    /// measured worse (the furnished room: FLIP 0.0349 -> 0.0380 at 960x540).
    static constexpr double kEnclosed = 0.3;

    /// Finds them: the triangles of opaque reflecting surfaces (plastic, metal; no emitters)
    /// that rays from each small, enclosed lamp meet within reach, each weighted by the rays it
    /// took.
    /// None in a scene with a medium or without lights.
    explicit HotSurfaces(const RenderScene& scene);

    bool empty() const { return triangles_.empty(); }
    size_t size() const { return triangles_.size(); }
    /// The triangle's index among them, or -1 when it is not one of them.
    int index_of(uint32_t geometry, uint32_t primitive) const {
        return geometry < index_.size() && primitive < index_[geometry].size() ? static_cast<int>(index_[geometry][primitive]) - 1 : -1;
    }
    /// Whether the triangle is one of them.
    bool contains(uint32_t geometry, uint32_t primitive) const { return index_of(geometry, primitive) >= 0; }
    /// Whether a ray along `dir` that meets the hot triangle comes from the side its lamp
    /// lights (the inside of a shade).
    bool from_lit_side(uint32_t geometry, uint32_t primitive, const Vec3& dir) const {
        const int i = index_of(geometry, primitive);
        return i >= 0 && dot(dir, triangles_[static_cast<size_t>(i)].lit_normal) < 0;
    }
    /// Irradiance the hot surfaces give each other on their lit sides, over every bounce (a
    /// small radiosity solution made once, on up to 16 cells of each triangle: a shade's
    /// triangles span it from rim to rim, and a single value each made a path-traced floor
    /// under a lamp 1.3 % too bright), at
    /// barycentrics (b1, b2) of the triangle: what a shade's inside adds to the direct light
    /// of its bulb. Light from the rest of the scene onto them is left out (a few per cent of
    /// the bulb's there).
    const Vec3& interreflected(uint32_t triangle, double b1, double b2) const { return interreflected_[cell_of(triangle, b1, b2)]; }
    const Vec3& lit_normal(uint32_t triangle) const { return triangles_[triangle].lit_normal; }

    struct Point {
        uint32_t geometry = 0, primitive = 0;
        uint32_t triangle = 0;  ///< its index among them
        double b1 = 0, b2 = 0;  ///< barycentrics of vertices 1 and 2 (Embree's u, v)
        Vec3 position;          ///< local coordinates
        double pdf_area = 0;    ///< density of choosing it, per unit area
    };
    /// Embree's record of a hit at `y`, for hit_frame() and surface_at().
    RTCHit hit_at(const Point& y) const {
        RTCHit hit{};
        const Vec3& n = embree_.geometries()[y.geometry].normals[y.primitive];
        hit.Ng_x = static_cast<float>(n.x), hit.Ng_y = static_cast<float>(n.y), hit.Ng_z = static_cast<float>(n.z);
        hit.u = static_cast<float>(y.b1), hit.v = static_cast<float>(y.b2);
        hit.primID = y.primitive, hit.geomID = y.geometry, hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        return hit;
    }
    /// A point on them from three uniforms: a triangle by the probe rays it took, then a point
    /// uniform in the solid angle it fills seen from its lamp (Arvo's spherical triangle), so
    /// points fall as densely as the lamp's light: uniform over a desk top under a desk lamp,
    /// most fell where the lamp's light is faint. pdf_area 0: none could be made.
    Point sample(double u0, double u1, double u2) const;

    /// What point y sends back towards a viewer `t` away along unit `dir` (from the viewer to
    /// y), the one rule for a hit's hot-surface samples (shade.cpp) and a record's
    /// (record_hemispheres.cpp). Nothing where the viewer sees its back (unless back faces are
    /// visible) or it does not reflect direct light.
    struct Reflected {
        bool seen = false;
        double cos_y = 0;        ///< at y, towards the viewer
        double epsilon = 0;      ///< y's own ray epsilon
        bool lit = false;        ///< `to_light` is y's direct light: one light sample, its shadow ray still to trace
        ShadowSample to_light;   ///< with throughput 1: radiance reflected towards the viewer
        Vec3 each_other;         ///< on the lit side, the radiance of the hot surfaces' light on each other
    };
    /// `random`: the numbers of y's light sample.
    Reflected reflected(const RenderScene& scene, const Point& y, const Vec3& dir, double t, const HitRandom& random) const;

private:
    struct Triangle {
        uint32_t geometry, primitive;
        Vec3 lamp;           ///< the centre of the lamp that lights it
        double solid_angle;  ///< it fills seen from there
        Vec3 lit_normal;     ///< its normal on the lamp's side
    };
    /// The cell of the triangle's grid (cells_ a side in barycentrics, two cells a square, the
    /// upper one of each square on the diagonal unused) that (b1, b2) falls in.
    size_t cell_of(uint32_t triangle, double b1, double b2) const {
        const double n = cells_;
        const int i = std::clamp(static_cast<int>(b1 * n), 0, static_cast<int>(cells_) - 1);
        const int j = std::clamp(static_cast<int>(b2 * n), 0, static_cast<int>(cells_) - 1 - i);
        const bool upper = b1 * n - i + (b2 * n - j) > 1 && i + j < static_cast<int>(cells_) - 1;
        return (static_cast<size_t>(triangle) * cells_ * cells_ + static_cast<size_t>(i) * cells_ + static_cast<size_t>(j)) * 2 + (upper ? 1 : 0);
    }
    uint32_t cells_ = 1;                ///< a side of each triangle's grid of cells
    std::vector<Vec3> interreflected_;  ///< per cell (cell_of())
    /// Fills `interreflected_`.
    void solve_interreflection(const RenderScene& scene);

    const EmbreeScene& embree_;
    std::vector<Triangle> triangles_;
    std::vector<double> cdf_;  ///< cumulative weights, the last 1
    std::vector<double> probability_;
    std::vector<std::vector<uint32_t>> index_;  ///< per geometry, per triangle: its index + 1, 0 if not hot (empty where none)
    /// Rays that solve_interreflection() casts in all (each of those that meets a lit side, a
    /// shadow ray more); each cell casts between kFewestLinks and kMostLinks.
    static constexpr uint32_t kInterreflectionSamples = 1u << 19, kFewestLinks = 4, kMostLinks = 256;
};

}  // namespace crex
