// Surfaces a small lamp lights from up close, such as the inside of its shade: many times as
// bright as the room around them, and seen by an irradiance record's hemisphere in a cell or
// two. Rays that meet them by chance made a record several times too bright or left it dark:
// blotches on the walls and ceiling where the records were used, and a grain of small records
// beside the lamp. IrradianceCache samples their direct light as a light of its own instead
// (RADIANCE's mkillum does this by hand; record_hemispheres.cpp, add_hot_surfaces()).
#pragma once

#include <cstdint>
#include <vector>

#include "runtime/render/render_scene.h"

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
    /// None either when not `wanted`.
    HotSurfaces(const RenderScene& scene, bool wanted);

    bool empty() const { return triangles_.empty(); }
    size_t size() const { return triangles_.size(); }
    /// Whether the triangle is one of them.
    bool contains(uint32_t geometry, uint32_t primitive) const {
        return geometry < flags_.size() && primitive < flags_[geometry].size() && flags_[geometry][primitive];
    }

    struct Point {
        uint32_t geometry = 0, primitive = 0;
        double b1 = 0, b2 = 0;  ///< barycentrics of vertices 1 and 2 (Embree's u, v)
        Vec3 position;          ///< local coordinates
        double pdf_area = 0;    ///< density of choosing it, per unit area
    };
    /// A point on them from three uniforms: a triangle by the probe rays it took, then a point
    /// uniform in the solid angle it fills seen from its lamp (Arvo's spherical triangle), so
    /// points fall as densely as the lamp's light: uniform over a desk top under a desk lamp,
    /// most fell where the lamp's light is faint. pdf_area 0: none could be made.
    Point sample(double u0, double u1, double u2) const;

private:
    struct Triangle {
        uint32_t geometry, primitive;
        Vec3 lamp;           ///< the centre of the lamp that lights it
        double solid_angle;  ///< it fills seen from there
    };
    const EmbreeScene& embree_;
    std::vector<Triangle> triangles_;
    std::vector<double> cdf_;  ///< cumulative weights, the last 1
    std::vector<double> probability_;
    std::vector<std::vector<uint8_t>> flags_;  ///< per geometry, per triangle (empty where none)
};

}  // namespace crex
