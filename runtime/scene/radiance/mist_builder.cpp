// RADIANCE's mist (m_mist.c): the surfaces of a closed volume whose inside holds a participating
// medium. The surfaces themselves are never seen. crex's medium is homogeneous and fills either
// the scene or one axis-aligned box, so a mist with coefficients becomes the scene's medium when
// its surfaces make such a box (genbox, moved by xform -t); a mist without them only names the
// light sources RADIANCE scatters inside it, where crex scatters every source's light.
#include <fmt/format.h>

#include <cmath>

#include "runtime/scene/radiance/scene_builder.h"

namespace crex::radiance {
namespace {

// Twice the area of a planar polygon (Newell's normal's length).
double polygon_area(const std::vector<Vec3>& v) {
    Vec3 n;
    for (size_t i = 0; i < v.size(); ++i) n = n + cross(v[i], v[(i + 1) % v.size()]);
    return 0.5 * length(n);
}

double axis(const Vec3& v, int k) { return k == 0 ? v.x : k == 1 ? v.y : v.z; }

// Whether `polygons` are the six faces of the box [lo, hi] (each lying in one face's plane,
// their areas adding up to the box's).
bool make_a_box(const std::vector<std::vector<Vec3>>& polygons, const Vec3& lo, const Vec3& hi) {
    const double size = length(hi - lo), eps = 1e-6 * size;
    const Vec3 e = hi - lo;
    if (!(e.x > eps && e.y > eps && e.z > eps)) return false;
    double area = 0;
    for (const auto& poly : polygons) {
        bool on_a_face = false;
        for (int k = 0; k < 3 && !on_a_face; ++k)
            for (double plane : {axis(lo, k), axis(hi, k)}) {
                bool all = true;
                for (const Vec3& v : poly) all = all && std::fabs(axis(v, k) - plane) <= eps;
                on_a_face = on_a_face || all;
            }
        if (!on_a_face) return false;
        area += polygon_area(poly);
    }
    const double box_area = 2 * (e.x * e.y + e.y * e.z + e.z * e.x);
    return std::fabs(area - box_area) <= 1e-6 * box_area;
}

}  // namespace

void SceneBuilder::mist_surface(const DefPtr& d, const Primitive& p) {
    MistBoundary* b = nullptr;
    for (MistBoundary& m : mists_)
        if (m.def == d) b = &m;
    if (!b) {
        mists_.push_back({d, p, {}, false});
        b = &mists_.back();
    }
    if (p.type.text != "polygon") {
        b->other = true;
        return;
    }
    std::vector<Vec3> v;
    for (size_t i = 0; i + 2 < p.reals.size(); i += 3) v.push_back({p.reals[i], p.reals[i + 1], p.reals[i + 2]});
    b->polygons.push_back(std::move(v));
}

void SceneBuilder::finish_mists() {
    for (const MistBoundary& b : mists_) {
        const Primitive& m = b.def->p;
        const SourceSpan where = m.type.span.merge(m.id.span);
        const std::vector<double>& r = m.reals;
        if (r.size() != 0 && r.size() != 3 && r.size() != 6 && r.size() != 7) {
            report("E303", where, fmt::format("mist '{}' takes 0, 3, 6 or 7 real arguments (extinction, albedo, eccentricity), got {}",
                                              m.id.text, r.size()), &b.first);
            continue;
        }
        if (r.empty()) {  // names the sources scattered inside; no medium of its own
            if (!m.strings.empty())
                report("W306", where, fmt::format("mist '{}': crex scatters every light source's light wherever its medium is, not only the "
                                                  "sources a mist names", m.id.text), &b.first);
            continue;
        }
        Medium medium;
        medium.extinction = {r[0], r[1], r[2]};
        if (r.size() >= 6) medium.albedo = {r[3], r[4], r[5]};
        if (r.size() == 7) medium.eccentricity = r[6];
        const bool valid = r[0] >= 0 && r[1] >= 0 && r[2] >= 0 && (r.size() < 6 || (r[3] >= 0 && r[3] <= 1 && r[4] >= 0 && r[4] <= 1 && r[5] >= 0 && r[5] <= 1)) &&
                           (r.size() < 7 || std::fabs(r[6]) < 1);
        if (!valid) {
            report("E302", where, fmt::format("mist '{}': extinction must be >= 0, albedo in [0, 1] and eccentricity in (-1, 1)", m.id.text),
                   &b.first);
            continue;
        }
        if (scene_.medium) {
            report("E307", where, fmt::format("mist '{}': crex renders one medium, and the scene has one already", m.id.text), &b.first).help =
                "give the scene a single mist with coefficients";
            continue;
        }
        Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
        for (const auto& poly : b.polygons)
            for (const Vec3& v : poly) {
                lo = {std::fmin(lo.x, v.x), std::fmin(lo.y, v.y), std::fmin(lo.z, v.z)};
                hi = {std::fmax(hi.x, v.x), std::fmax(hi.y, v.y), std::fmax(hi.z, v.z)};
            }
        if (b.other || b.polygons.empty() || !make_a_box(b.polygons, lo, hi)) {
            report("E307", b.first.type.span.merge(b.first.id.span),
                   fmt::format("mist '{}': crex's medium fills the whole scene or one axis-aligned box, and the surfaces of this mist do not "
                               "make one", m.id.text), &b.first)
                .help = "bound the mist by a genbox moved with xform -t (no rotation), or give a JSON scene a \"medium\"";
            continue;
        }
        medium.bounded = true;
        medium.box_min = lo;
        medium.box_max = hi;
        scene_.medium = medium;
    }
}

}  // namespace crex::radiance
