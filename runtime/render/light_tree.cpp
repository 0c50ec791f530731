#include "runtime/render/light_tree.h"

#include <algorithm>
#include <cmath>

#include "runtime/base/sampling.h"

namespace crex {
namespace {

double safe_sqrt(double v) { return std::sqrt(std::fmax(0.0, v)); }
double safe_acos(double c) { return std::acos(std::clamp(c, -1.0, 1.0)); }

// cos(max(0, a - b)) and sin(max(0, a - b)) from the angles' sines and cosines.
double cos_minus(double sin_a, double cos_a, double sin_b, double cos_b) { return cos_a > cos_b ? 1.0 : cos_a * cos_b + sin_a * sin_b; }

// The smallest cone holding two cones of directions (pbrt-v4's DirectionCone Union).
void merge_cones(Vec3& axis, double& cos_spread, const Vec3& other_axis, double other_cos) {
    const double ta = safe_acos(cos_spread), tb = safe_acos(other_cos);
    const double td = safe_acos(dot(axis, other_axis));
    if (std::fmin(td + tb, kPi) <= ta) return;
    if (std::fmin(td + ta, kPi) <= tb) {
        axis = other_axis, cos_spread = other_cos;
        return;
    }
    const double to = (ta + td + tb) / 2;
    const Vec3 about = cross(axis, other_axis);
    const double about_len = length(about);
    if (to >= kPi || !(about_len > 1e-12)) {
        cos_spread = -1;  // the whole sphere
        return;
    }
    // Turn `axis` towards the other by to - ta about their common normal (Rodrigues).
    const Vec3 k = about / about_len;
    const double turn = to - ta, c = std::cos(turn), s = std::sin(turn);
    axis = normalize_or_zero(axis * c + cross(k, axis) * s + k * (dot(k, axis) * (1 - c)));
    cos_spread = std::cos(to);
    if (axis == Vec3{}) cos_spread = -1;
}

}  // namespace

LightTree::LightTree(const std::vector<LightBound>& lights) {
    if (lights.empty()) return;
    order_.resize(lights.size());
    for (uint32_t i = 0; i < order_.size(); ++i) order_[i] = i;
    trails_.assign(lights.size(), 0);
    nodes_.reserve(2 * (lights.size() / kLeafMax + 1));
    nodes_.emplace_back();
    build(0, 0, order_.size(), lights, 0, 0);
}

// Node `at` over order_[begin, end): a leaf of up to kLeafMax emitters, or split at the median
// of the centres along their widest extent, the two children side by side (the trails hold
// 64 levels: 2^67 emitters).
void LightTree::build(uint32_t at, size_t begin, size_t end, const std::vector<LightBound>& lights, uint64_t trail, int depth) {
    if (end - begin <= kLeafMax) {
        Node& n = nodes_[at];
        const LightBound& l = lights[order_[begin]];
        n.lo = l.lo, n.hi = l.hi, n.axis = l.axis, n.cos_spread = l.cos_spread, n.power = 0;
        for (size_t i = begin; i < end; ++i) {
            const LightBound& m = lights[order_[i]];
            n.lo = vmin(n.lo, m.lo), n.hi = vmax(n.hi, m.hi);
            n.power += m.power;
            if (i > begin) merge_cones(n.axis, n.cos_spread, m.axis, m.cos_spread);
            trails_[order_[i]] = trail;
        }
        n.first = static_cast<uint32_t>(begin);
        n.count = static_cast<uint32_t>(end - begin);
        finish(n);
        return;
    }
    Vec3 clo = (lights[order_[begin]].lo + lights[order_[begin]].hi) / 2, chi = clo;
    for (size_t i = begin; i < end; ++i) {
        const Vec3 c = (lights[order_[i]].lo + lights[order_[i]].hi) / 2;
        clo = vmin(clo, c), chi = vmax(chi, c);
    }
    const Vec3 extent = chi - clo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    const size_t mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + static_cast<std::ptrdiff_t>(begin), order_.begin() + static_cast<std::ptrdiff_t>(mid),
                     order_.begin() + static_cast<std::ptrdiff_t>(end), [&](uint32_t a, uint32_t b) {
                         return lights[a].lo[axis] + lights[a].hi[axis] < lights[b].lo[axis] + lights[b].hi[axis];
                     });
    const uint32_t first = static_cast<uint32_t>(nodes_.size());
    nodes_.emplace_back();
    nodes_.emplace_back();
    nodes_[at].first = first;
    build(first, begin, mid, lights, trail, depth + 1);
    build(first + 1, mid, end, lights, trail | (uint64_t{1} << std::min(depth, 63)), depth + 1);
    const Node a = nodes_[first], b = nodes_[first + 1];
    Node& n = nodes_[at];
    n.lo = vmin(a.lo, b.lo), n.hi = vmax(a.hi, b.hi);
    n.power = a.power + b.power;
    n.axis = a.axis, n.cos_spread = a.cos_spread;
    merge_cones(n.axis, n.cos_spread, b.axis, b.cos_spread);
    finish(n);
}

void LightTree::finish(Node& n) {
    n.centre = (n.lo + n.hi) / 2;
    n.radius = length(n.hi - n.lo) / 2;
    n.sin_spread = safe_sqrt(1 - n.cos_spread * n.cos_spread);
}

// pbrt-v4's LightBounds::Importance for emitters that emit over the hemisphere about each of
// their normals: power x the cosine at the emitters bounded from above / distance^2 (at least
// the bounding sphere's radius squared), times the bound of the cosine at a surface that only
// reflects (signed: nothing below its horizon). Angles as sines and cosines: no acos at a hit.
double LightTree::importance(const Node& n, const Vec3& x, const Vec3* normal) {
    const Vec3 to_x = x - n.centre;
    const double dist2 = dot(to_x, to_x), r2 = n.radius * n.radius;
    if (!(dist2 > 0)) return n.power / max_of(r2, 1e-300);  // x at the centre: every bound is 1
    const double inv_d = 1 / std::sqrt(dist2);  // one square root and one division: this runs ~12 times a shadow ray
    const Vec3 w = to_x * inv_d;
    // The cone of directions from x that holds the bounding sphere (all of them from inside it).
    double cos_b = -1, sin_b = 0;
    if (dist2 > r2) sin_b = n.radius * inv_d, cos_b = std::sqrt(1 - sin_b * sin_b);
    // The smallest angle between an emitter's normal and a direction from it to x, less the
    // cone's: no emitter faces x when even that is past 90 degrees.
    double cos_x = 1, sin_x = 0;
    if (n.cos_spread > -1) {
        const double cos_w = dot(n.axis, w);
        if (cos_w <= n.cos_spread) {
            const double sin_w = std::sqrt(max_of(0.0, 1 - cos_w * cos_w));
            cos_x = cos_w * n.cos_spread + sin_w * n.sin_spread;
            sin_x = sin_w * n.cos_spread - cos_w * n.sin_spread;
        }
    }
    const double cos_emit = cos_minus(sin_x, cos_x, sin_b, cos_b);
    if (cos_emit <= 0) return 0;
    double importance = n.power * cos_emit * (dist2 > r2 ? inv_d * inv_d : 1 / max_of(r2, 1e-300));
    if (normal) {
        const double cos_i = -dot(w, *normal);
        if (cos_i < cos_b) {  // else the sphere's cone holds the normal: the bound is 1
            const double sin_i = std::sqrt(max_of(0.0, 1 - cos_i * cos_i));
            importance *= max_of(0.0, cos_i * cos_b + sin_i * sin_b);
        }
    }
    return std::isfinite(importance) ? max_of(importance, 0.0) : 0.0;
}

}  // namespace crex
