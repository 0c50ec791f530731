#include "runtime/scene/shapes.h"

#include "runtime/base/sampling.h"
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "runtime/base/name_table.h"

namespace crex {
namespace {

constexpr std::array<std::pair<ShapeType, std::string_view>, 7> kShapeNames = {{
    {ShapeType::kSphere, "sphere"},
    {ShapeType::kPolygon, "polygon"},
    {ShapeType::kMesh, "mesh"},
    {ShapeType::kBox, "box"},
    {ShapeType::kRing, "ring"},
    {ShapeType::kCone, "cone"},
    {ShapeType::kCylinder, "cylinder"},
}};


// Newell's method: a robust normal (times twice the area) for any planar polygon.
Vec3 newell_normal(const std::vector<Vec3>& v) {
    Vec3 n;
    for (size_t i = 0; i < v.size(); ++i) {
        const Vec3& a = v[i];
        const Vec3& b = v[(i + 1) % v.size()];
        n.x += (a.y - b.y) * (a.z + b.z);
        n.y += (a.z - b.z) * (a.x + b.x);
        n.z += (a.x - b.x) * (a.y + b.y);
    }
    return n;
}

// Two unit vectors spanning the plane perpendicular to unit `n`.
void basis(const Vec3& n, Vec3& u, Vec3& v) {
    Vec3 a = std::fabs(n.x) > 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
    u = normalize_or_zero(cross(n, a));
    v = cross(n, u);
}

bool finite_all(std::initializer_list<double> xs) {
    for (double x : xs)
        if (!std::isfinite(x)) return false;
    return true;
}

uint32_t push(TriangleMesh& m, const Vec3& p) {
    m.positions.push_back(p);
    return static_cast<uint32_t>(m.positions.size() - 1);
}

// A band between two circles (a ring when both centres coincide, a cone or cylinder otherwise).
// A cone's triangles face away from its axis, a ring's along its normal; `flip` turns them.
void tessellate_band(TriangleMesh& out, const Vec3& c0, const Vec3& c1, const Vec3& axis, double r0, double r1, bool flip) {
    Vec3 u, v;
    basis(normalize_or_zero(axis), u, v);
    uint32_t base = static_cast<uint32_t>(out.positions.size());
    for (int i = 0; i < kRoundSegments; ++i) {
        double t = 2 * kPi * i / kRoundSegments;
        Vec3 dir = u * std::cos(t) + v * std::sin(t);
        push(out, c0 + dir * r0);
        push(out, c1 + dir * r1);
    }
    // (a0, b0, a1) turns from the tangent to the axis: outward for a cone; for a ring, whose
    // axis is its normal, the same order turns from the tangent to the radius, facing -normal.
    if (c0 == c1) flip = !flip;
    for (uint32_t i = 0; i < kRoundSegments; ++i) {
        uint32_t j = (i + 1) % kRoundSegments;
        uint32_t a0 = base + 2 * i, a1 = base + 2 * i + 1, b0 = base + 2 * j, b1 = base + 2 * j + 1;
        if (r0 > 0) out.indices.push_back(flip ? std::array<uint32_t, 3>{a0, a1, b0} : std::array<uint32_t, 3>{a0, b0, a1});
        if (r1 > 0) out.indices.push_back(flip ? std::array<uint32_t, 3>{b0, a1, b1} : std::array<uint32_t, 3>{b0, b1, a1});
    }
}

}  // namespace

std::string_view shape_type_name(ShapeType t) { return name_in(kShapeNames, t); }

std::optional<ShapeType> shape_type_from_name(std::string_view name) { return value_in(kShapeNames, name); }

std::vector<std::array<uint32_t, 3>> triangulate_polygon(const std::vector<Vec3>& vertices) {
    // Ear clipping that also takes RADIANCE's polygons with holes: a hole is a loop of
    // vertices joined to the outline by a seam, an edge walked once each way, so the loop
    // touches itself where the seam's ends repeat. Such a "weakly simple" polygon clips like a
    // simple one once a vertex lying exactly on a corner of a candidate ear (the other end of a
    // seam) does not count as inside it; the ear theorem's argument holds unchanged. (Counting
    // it made every ear at a seam fail, and the old fallback, a fan, filled the hole: a wall
    // with a window lit 1,985 pixels where RADIANCE lit 1,452.)
    std::vector<std::array<uint32_t, 3>> tris;
    const size_t n = vertices.size();
    if (n < 3) return tris;
    const Vec3 normal = normalize_or_zero(newell_normal(vertices));
    if (normal == Vec3{}) return tris;
    Vec3 u, v;
    basis(normal, u, v);
    std::vector<std::array<double, 2>> p(n);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t i = 0; i < n; ++i) {
        p[i] = {dot(vertices[i], u), dot(vertices[i], v)};
        for (int k = 0; k < 2; ++k) lo[k] = std::fmin(lo[k], p[i][k]), hi[k] = std::fmax(hi[k], p[i][k]);
    }
    // Tolerances relative to the polygon's own size (never the scene's).
    const double size = std::fmax(hi[0] - lo[0], hi[1] - lo[1]);
    const double same = 1e-9 * size, flat = 1e-12 * size * size;
    auto area2 = [&](uint32_t a, uint32_t b, uint32_t c) {
        return (p[b][0] - p[a][0]) * (p[c][1] - p[a][1]) - (p[c][0] - p[a][0]) * (p[b][1] - p[a][1]);
    };
    auto coincide = [&](uint32_t a, uint32_t b) {
        return std::fabs(p[a][0] - p[b][0]) <= same && std::fabs(p[a][1] - p[b][1]) <= same;
    };
    // In (u, v) the polygon winds counter-clockwise, since u x v = normal from Newell.
    std::vector<uint32_t> ring;
    for (uint32_t i = 0; i < n; ++i)
        if (ring.empty() || !coincide(ring.back(), i)) ring.push_back(i);
    while (ring.size() > 1 && coincide(ring.front(), ring.back())) ring.pop_back();
    auto at = [&](size_t i) { return ring[i % ring.size()]; };
    auto is_ear = [&](size_t i) {
        const uint32_t a = at(i + ring.size() - 1), b = at(i), c = at(i + 1);
        if (area2(a, b, c) <= flat) return false;  // reflex or flat corner
        for (size_t k = 0; k < ring.size(); ++k) {
            const uint32_t q = ring[k];
            if (q == a || q == b || q == c || coincide(q, a) || coincide(q, b) || coincide(q, c)) continue;
            // Only a reflex vertex can lie inside an ear.
            if (area2(at(k + ring.size() - 1), q, at(k + 1)) > flat) continue;
            if (area2(a, b, q) >= -flat && area2(b, c, q) >= -flat && area2(c, a, q) >= -flat) return false;
        }
        return true;
    };
    size_t start = 0;
    while (ring.size() > 3) {
        bool clipped = false;
        for (size_t step = 0; step < ring.size(); ++step) {
            const size_t i = (start + step) % ring.size();
            if (!is_ear(i)) continue;
            tris.push_back({at(i + ring.size() - 1), at(i), at(i + 1)});
            ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
            start = i == 0 ? 0 : i - 1;
            clipped = true;
            break;
        }
        if (clipped) continue;
        // No ear: drop a vertex that encloses nothing (on a straight line, or the tip of a
        // spike left where a seam met itself), and a repeated neighbour with it.
        bool dropped = false;
        for (size_t i = 0; i < ring.size() && !dropped; ++i) {
            if (std::fabs(area2(at(i + ring.size() - 1), at(i), at(i + 1))) > flat) continue;
            ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
            dropped = true;
        }
        if (!dropped) break;  // not weakly simple: what is left is not triangulated
        for (size_t k = 0; ring.size() > 1 && k < ring.size();) {  // neighbours that now repeat
            if (coincide(at(k), at(k + 1))) ring.erase(ring.begin() + static_cast<std::ptrdiff_t>((k + 1) % ring.size()));
            else ++k;
        }
        start = 0;
    }
    if (ring.size() == 3 && area2(ring[0], ring[1], ring[2]) > flat) tris.push_back({ring[0], ring[1], ring[2]});
    return tris;
}

namespace {

// The diagonal of a polygon's bounds: the size its area is measured against.
double own_size(const std::vector<Vec3>& points) {
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    for (const auto& p : points) {
        lo = {std::fmin(lo.x, p.x), std::fmin(lo.y, p.y), std::fmin(lo.z, p.z)};
        hi = {std::fmax(hi.x, p.x), std::fmax(hi.y, p.y), std::fmax(hi.z, p.z)};
    }
    return length(hi - lo);
}

}  // namespace

double polygon_signed_area(const std::vector<Vec3>& vertices) {
    return 0.5 * length(newell_normal(vertices));
}

bool polygon_fully_triangulated(const Shape& s) {
    if (s.type != ShapeType::kPolygon || s.vertices.size() < 3) return true;
    // Areas as seen along the polygon's normal: a polygon a few millimetres out of its plane
    // (the published Cornell box's red wall) has triangles whose own areas add to a little
    // more than its outline's, though they cover it exactly.
    const Vec3 newell = newell_normal(s.vertices);
    const double area = 0.5 * length(newell);
    if (!(area > 0)) return true;
    const Vec3 n = newell / (2 * area);
    double covered = 0;
    for (const auto& t : triangulate_polygon(s.vertices))
        covered += 0.5 * std::fabs(dot(cross(s.vertices[t[1]] - s.vertices[t[0]], s.vertices[t[2]] - s.vertices[t[0]]), n));
    return std::fabs(covered - area) <= 1e-6 * std::fmax(area, 1e-300);
}

bool degenerate_polygon(const Shape& s) {
    if (s.type != ShapeType::kPolygon || s.vertices.size() < 3) return false;
    double size = own_size(s.vertices);
    double area = 0.5 * length(newell_normal(s.vertices));
    return !(area > 1e-12 * size * size);
}

Vec3 imported_vertex_color(double r, double g, double b) {
    auto channel = [](double x) { return std::isfinite(x) ? std::clamp(x, 0.0, 1.0) : 1.0; };
    return {channel(r), channel(g), channel(b)};
}

std::optional<std::string> shape_problem(const Shape& s) {
    switch (s.type) {
    case ShapeType::kSphere:
        if (!is_finite(s.center) || !std::isfinite(s.radius)) return "non-finite centre or radius";
        if (!(s.radius > 0)) return fmt::format("radius must be > 0, got {}", s.radius);
        return std::nullopt;
    case ShapeType::kPolygon: {
        if (s.vertices.size() < 3) return fmt::format("a polygon needs at least 3 vertices, got {}", s.vertices.size());
        for (const auto& v : s.vertices)
            if (!is_finite(v)) return "non-finite vertex coordinate";
        return std::nullopt;
    }
    case ShapeType::kMesh:
        for (const auto& v : s.vertices)
            if (!is_finite(v)) return "non-finite vertex coordinate";
        for (const auto& t : s.triangles)
            for (uint32_t i : t)
                if (i >= s.vertices.size())
                    return fmt::format("triangle index {} out of range ({} vertices)", i, s.vertices.size());
        if (s.triangles.empty()) return "mesh has no triangles";
        if (!s.uvs.empty() && s.uvs.size() != s.vertices.size())
            return fmt::format("{} texture coordinates for {} vertices", s.uvs.size(), s.vertices.size());
        if (!s.normals.empty() && s.normals.size() != s.vertices.size())
            return fmt::format("{} normals for {} vertices", s.normals.size(), s.vertices.size());
        if (!s.colors.empty() && s.colors.size() != s.vertices.size())
            return fmt::format("{} vertex colours for {} vertices", s.colors.size(), s.vertices.size());
        for (const auto& c : s.colors)
            if (!is_finite(c) || c.x < 0 || c.y < 0 || c.z < 0) return "a vertex colour that is negative or not finite";
        for (const auto& uv : s.uvs)
            if (!std::isfinite(uv[0]) || !std::isfinite(uv[1])) return "non-finite texture coordinate";
        for (const auto& n : s.normals)
            if (!is_finite(n)) return "non-finite normal";
        return std::nullopt;
    case ShapeType::kBox:
        if (!is_finite(s.min) || !is_finite(s.max)) return "non-finite box corner";
        if (!(s.min.x < s.max.x && s.min.y < s.max.y && s.min.z < s.max.z))
            return "box 'min' must be below 'max' on every axis";
        return std::nullopt;
    case ShapeType::kRing:
        if (!is_finite(s.center) || !is_finite(s.normal) || !finite_all({s.r0, s.r1})) return "non-finite ring";
        if (!(length(s.normal) > 0)) return "degenerate normal (zero length)";
        if (!(s.r0 >= 0 && s.r1 > s.r0)) return fmt::format("ring radii must satisfy 0 <= inner < outer, got {} and {}", s.r0, s.r1);
        return std::nullopt;
    case ShapeType::kCone:
    case ShapeType::kCylinder: {
        double r0 = s.type == ShapeType::kCylinder ? s.radius : s.r0;
        double r1 = s.type == ShapeType::kCylinder ? s.radius : s.r1;
        if (!is_finite(s.p0) || !is_finite(s.p1) || !finite_all({r0, r1})) return "non-finite end point or radius";
        // Relative to the shape's own numbers: its coordinates and radii.
        double own = std::fmax(std::fmax(length(s.p0), length(s.p1)), std::fmax(r0, r1));
        if (!(length(s.p1 - s.p0) > 1e-12 * own)) return "end points coincide: the axis is degenerate";
        if (!(r0 >= 0 && r1 >= 0 && r0 + r1 > 0)) return fmt::format("radii must be >= 0 and not both 0, got {} and {}", r0, r1);
        return std::nullopt;
    }
    }
    return std::nullopt;
}

namespace {

void append_triangles(const Shape& s, TriangleMesh& out, size_t* dropped) {
    switch (s.type) {
    case ShapeType::kSphere: return;
    case ShapeType::kPolygon: {
        uint32_t base = static_cast<uint32_t>(out.positions.size());
        for (const auto& v : s.vertices) out.positions.push_back(v);
        for (auto t : triangulate_polygon(s.vertices)) out.indices.push_back({base + t[0], base + t[1], base + t[2]});
        return;
    }
    case ShapeType::kMesh: {
        uint32_t base = static_cast<uint32_t>(out.positions.size());
        // Per-vertex attributes stay aligned with the positions only while every mesh
        // appended has them.
        const bool aligned_uvs = out.uvs.size() == base, aligned_normals = out.normals.size() == base,
                   aligned_colors = out.colors.size() == base;
        for (const auto& v : s.vertices) out.positions.push_back(v);
        if (aligned_uvs && s.uvs.size() == s.vertices.size()) out.uvs.insert(out.uvs.end(), s.uvs.begin(), s.uvs.end());
        else out.uvs.clear();
        if (aligned_normals && s.normals.size() == s.vertices.size()) out.normals.insert(out.normals.end(), s.normals.begin(), s.normals.end());
        else out.normals.clear();
        if (aligned_colors && s.colors.size() == s.vertices.size()) out.colors.insert(out.colors.end(), s.colors.begin(), s.colors.end());
        else out.colors.clear();
        for (const auto& t : s.triangles) {
            Vec3 n = cross(s.vertices[t[1]] - s.vertices[t[0]], s.vertices[t[2]] - s.vertices[t[0]]);
            if (!(length(n) > 0)) {  // zero-area triangles have no normal: never hand them to the tracer
                if (dropped) ++*dropped;
                continue;
            }
            out.indices.push_back({base + t[0], base + t[1], base + t[2]});
        }
        return;
    }
    case ShapeType::kBox: {
        const Vec3& a = s.min;
        const Vec3& b = s.max;
        uint32_t base = static_cast<uint32_t>(out.positions.size());
        for (int i = 0; i < 8; ++i) push(out, {i & 1 ? b.x : a.x, i & 2 ? b.y : a.y, i & 4 ? b.z : a.z});
        // Outward-facing faces, two triangles each.
        // Corner i has x from bit 0, y from bit 1, z from bit 2; faces -x +x -y +y -z +z.
        static const uint32_t faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
        for (const auto& f : faces) {
            out.indices.push_back({base + f[0], base + f[1], base + f[2]});
            out.indices.push_back({base + f[0], base + f[2], base + f[3]});
        }
        return;
    }
    case ShapeType::kRing: tessellate_band(out, s.center, s.center, s.normal, s.r0, s.r1, false); return;
    case ShapeType::kCone: tessellate_band(out, s.p0, s.p1, s.p1 - s.p0, s.r0, s.r1, s.inward); return;
    case ShapeType::kCylinder: tessellate_band(out, s.p0, s.p1, s.p1 - s.p0, s.radius, s.radius, s.inward); return;
    }
}

}  // namespace

void tessellate(const Shape& s, TriangleMesh& out, size_t* dropped) {
    append_triangles(s, out, dropped);
    // Per-vertex attributes are all or nothing.
    if (out.uvs.size() != out.positions.size()) out.uvs.clear();
    if (out.normals.size() != out.positions.size()) out.normals.clear();
    if (out.colors.size() != out.positions.size()) out.colors.clear();
}

size_t triangle_count(const Shape& s) {
    TriangleMesh m;
    tessellate(s, m);
    return m.indices.size();
}

void expand_bounds(const Shape& s, Vec3& lo, Vec3& hi) {
    auto add = [&](const Vec3& p, double r) {
        lo = vmin(lo, p - Vec3{r, r, r});
        hi = vmax(hi, p + Vec3{r, r, r});
    };
    switch (s.type) {
    case ShapeType::kSphere: add(s.center, s.radius); return;
    case ShapeType::kRing: add(s.center, s.r1); return;
    case ShapeType::kCone: add(s.p0, s.r0); add(s.p1, s.r1); return;
    case ShapeType::kCylinder: add(s.p0, s.radius); add(s.p1, s.radius); return;
    case ShapeType::kBox: add(s.min, 0); add(s.max, 0); return;
    case ShapeType::kPolygon:
    case ShapeType::kMesh:
        for (const auto& v : s.vertices) add(v, 0);
        return;
    }
}

namespace {

// Squared distance from p to triangle abc: the closest point by Voronoi regions (Ericson,
// Real-Time Collision Detection, 5.1.5), which stays exact for slivers.
double squared_distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    auto d2_to = [&](const Vec3& q) { const Vec3 e = p - q; return dot(e, e); };
    if (d1 <= 0 && d2 <= 0) return d2_to(a);
    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return d2_to(b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return d2_to(a + ab * (d1 / (d1 - d3)));
    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return d2_to(c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return d2_to(a + ac * (d2 / (d2 - d6)));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return d2_to(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
    const double sum = va + vb + vc;
    if (!(sum > 0)) return std::min({d2_to(a), d2_to(b), d2_to(c)});  // degenerate: its corners
    return d2_to(a + ab * (vb / sum) + ac * (vc / sum));
}

/// Distance along `d` from `o` to the triangle (a, b, c), or infinity; `back` says whether the
/// ray meets its back (the side its winding faces away from). Moeller-Trumbore, both sides.
double ray_triangle(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c, bool& back) {
    const Vec3 e1 = b - a, e2 = c - a, q = cross(d, e2);
    const double det = dot(e1, q);
    if (!(std::abs(det) > 1e-300)) return INFINITY;
    const double inv = 1 / det;
    const Vec3 s = o - a;
    const double u = dot(s, q) * inv;
    if (u < 0 || u > 1) return INFINITY;
    const Vec3 r = cross(s, e1);
    const double v = dot(d, r) * inv;
    if (v < 0 || u + v > 1) return INFINITY;
    const double t = dot(e2, r) * inv;
    back = det < 0;  // dot(d, cross(e1, e2)) = -det: the ray runs along the face's normal
    return t > 0 ? t : INFINITY;
}

/// Whether every ray from `p` (fourteen directions, turned off the axes so none grazes a
/// mesh's edges by construction) first meets one of the triangles from behind: `p` is
/// enclosed by them, not beside the back of an open sheet such as a leaf or a wall's panel.
bool enclosed(const Vec3& p, const std::vector<Vec3>& v, const std::vector<std::array<uint32_t, 3>>& tris) {
    static const std::array<Vec3, 14> kDirections = [] {
        std::array<Vec3, 14> out{};
        const Vec3 raw[14] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {1, 1, 1}, {1, 1, -1},
                              {1, -1, 1}, {1, -1, -1}, {-1, 1, 1}, {-1, 1, -1}, {-1, -1, 1}, {-1, -1, -1}};
        for (size_t i = 0; i < 14; ++i) out[i] = normalize_or_zero(raw[i] + Vec3{0.0127, 0.0311, 0.0233});
        return out;
    }();
    for (const Vec3& d : kDirections) {
        double nearest = INFINITY;
        bool nearest_back = false;
        for (const auto& t : tris) {
            if (t[0] >= v.size() || t[1] >= v.size() || t[2] >= v.size()) continue;
            bool back = false;
            const double hit = ray_triangle(p, d, v[t[0]], v[t[1]], v[t[2]], back);
            if (hit < nearest) nearest = hit, nearest_back = back;
        }
        if (!(nearest < INFINITY) || !nearest_back) return false;
    }
    return true;
}

}  // namespace

SurfaceDistance distance_to_surface(const Shape& s, const Vec3& p) {
    SurfaceDistance out;
    if (s.type == ShapeType::kSphere) {
        const double r = length(p - s.center);
        out.distance = std::abs(r - s.radius);
        out.behind = (r < s.radius) != s.inward;
        return out;
    }
    double best = INFINITY;
    // Faces at the nearest distance (within rounding) all vote: behind only if behind every one,
    // so a point by an edge of a convex solid is in front of it.
    auto over = [&](const std::vector<Vec3>& v, const std::vector<std::array<uint32_t, 3>>& tris) {
        for (const auto& t : tris) {
            if (t[0] >= v.size() || t[1] >= v.size() || t[2] >= v.size()) continue;
            const double d2 = squared_distance_to_triangle(p, v[t[0]], v[t[1]], v[t[2]]);
            if (d2 > best * (1 + 1e-9)) continue;
            const bool behind = dot(cross(v[t[1]] - v[t[0]], v[t[2]] - v[t[0]]), p - v[t[0]]) < 0;
            out.behind = d2 < best * (1 - 1e-9) ? behind : out.behind && behind;
            best = std::min(best, d2);
        }
        // Behind the nearest face of an open sheet is only its other side.
        if (out.behind) out.behind = enclosed(p, v, tris);
    };
    if (s.type == ShapeType::kMesh) {
        over(s.vertices, s.triangles);
    } else {
        TriangleMesh m;
        tessellate(s, m);
        over(m.positions, m.indices);
    }
    out.distance = std::sqrt(best);
    return out;
}

}  // namespace crex
