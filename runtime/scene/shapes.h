/// \file shapes.h
/// Shape names, validation and tessellation. Spheres stay analytic; every other shape becomes
/// triangles (rings, cones and cylinders with kRoundSegments segments, as RADIANCE's own
/// converters do for rasterisers).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/scene/scene.h"

namespace crex {

inline constexpr int kRoundSegments = 48;

std::string_view shape_type_name(ShapeType t);
std::optional<ShapeType> shape_type_from_name(std::string_view name);

struct TriangleMesh {
    std::vector<Vec3> positions;
    std::vector<std::array<uint32_t, 3>> indices;
    /// Per position, for meshes that have them (empty otherwise, or when the meshes appended
    /// to one TriangleMesh do not all have them).
    std::vector<std::array<double, 2>> uvs;
    std::vector<Vec3> normals;
    std::vector<Vec3> colors;  ///< per position, multiplying the material's colour (Shape::colors)
};

/// Why `shape` cannot be rendered (non-finite numbers, zero radius, degenerate normal or axis,
/// index out of range, ...), or nullopt when it is fine. "Degenerate" is relative to the
/// shape's own size, never the scene's: one huge ground plane must not make a 2 m floor
/// "zero-area". A zero-area polygon is not a problem here but degenerate_polygon().
std::optional<std::string> shape_problem(const Shape& shape);

/// A vertex colour read from a file (glTF COLOR_0, OBJ `v x y z r g b`): each channel clamped to
/// [0, 1], one that is not finite white. It multiplies an albedo, and must not make a surface give
/// back more light than it receives.
Vec3 imported_vertex_color(double r, double g, double b);

/// A polygon whose area is zero relative to its own size: it has no normal, and is dropped
/// with a warning (RADIANCE warns too) rather than failing the scene.
bool degenerate_polygon(const Shape& shape);

/// Appends the triangles of `shape` (nothing for spheres). Degenerate mesh triangles are
/// dropped and counted in `dropped` when given.
void tessellate(const Shape& shape, TriangleMesh& out, size_t* dropped = nullptr);

/// Number of triangles `shape` tessellates to.
size_t triangle_count(const Shape& shape);

/// Axis-aligned bounds of a shape (spheres and round shapes included).
void expand_bounds(const Shape& shape, Vec3& lo, Vec3& hi);

struct SurfaceDistance {
    double distance = INFINITY;  ///< to the nearest point of the surface; infinite without one
    /// `p` is inside: behind the front of every face at that distance and, for a mesh, every
    /// ray from `p` meets its faces from behind first (inside a closed mesh whose faces look
    /// out, not beside the back of an open sheet), or inside a sphere that is not a bubble.
    bool behind = false;
};
/// From `p` to the nearest point of `shape`'s surface (its triangles, or the analytic sphere).
SurfaceDistance distance_to_surface(const Shape& shape, const Vec3& p);

/// Triangulates a planar polygon by ear clipping (convex or not, with holes joined to the
/// outline by seams as RADIANCE writes them); returns index triples into `vertices`, empty if
/// it cannot (degenerate).
std::vector<std::array<uint32_t, 3>> triangulate_polygon(const std::vector<Vec3>& vertices);

/// The polygon's area: its outline's less its holes' (seams cancel), by Newell's formula.
double polygon_signed_area(const std::vector<Vec3>& vertices);
/// False when the triangles do not cover the polygon's area (it crosses itself, or a hole
/// winds the same way as its outline): crex then renders only part of it.
bool polygon_fully_triangulated(const Shape& shape);

}  // namespace crex
