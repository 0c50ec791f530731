#include "runtime/render/light_tree.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include "runtime/base/sampling.h"

namespace crex {
namespace {

double safe_sqrt(double v) { return std::sqrt(std::fmax(0.0, v)); }
double safe_acos(double c) { return std::acos(std::clamp(c, -1.0, 1.0)); }

// Four floats as one vector (GCC's and Clang's vector extension): the four children of a node.
using F4 = float __attribute__((vector_size(16)));
F4 splat(float v) { return F4{v, v, v, v}; }
F4 load(const float* p) {
    F4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
F4 max4(F4 a, F4 b) { return a > b ? a : b; }
F4 sqrt4(F4 v) {
#if defined(__SSE__)
    return _mm_sqrt_ps(v);
#else
    for (int k = 0; k < 4; ++k) v[k] = std::sqrt(v[k]);
    return v;
#endif
}

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

void LightTree::Bound::add(const Bound& other) {
    lo = vmin(lo, other.lo), hi = vmax(hi, other.hi);
    power += other.power;
    merge_cones(axis, cos_spread, other.axis, other.cos_spread);
}

LightTree::LightTree(const std::vector<LightBound>& lights) {
    if (lights.empty()) return;
    order_.resize(lights.size());
    for (uint32_t i = 0; i < order_.size(); ++i) order_[i] = i;
    trails_.assign(lights.size(), 0);
    // Lanes hold powers over the whole tree's, so that single precision keeps their ratios
    // whatever the scene's units.
    double total = 0;
    for (const LightBound& l : lights) total += l.power;
    power_scale_ = total > 0 && std::isfinite(total) ? total : 1;
    nodes_.reserve(lights.size() / kLeafMax + 2);
    nodes_.emplace_back();
    const Bound all = build(0, 0, order_.size(), lights, 0, 0);
    set_lane(top_, 0, all);
}

// The emitters order_[begin, end) split at the median of their centres along the centres'
// widest extent; returns the median's place.
size_t LightTree::split(size_t begin, size_t end, const std::vector<LightBound>& lights) {
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
    return mid;
}

LightTree::Bound LightTree::leaf_bound(size_t begin, size_t end, const std::vector<LightBound>& lights, uint64_t trail) {
    const auto bound_of = [](const LightBound& l) { return Bound{l.lo, l.hi, l.axis, l.cos_spread, l.power}; };
    Bound b = bound_of(lights[order_[begin]]);
    for (size_t i = begin; i < end; ++i) {
        if (i > begin) b.add(bound_of(lights[order_[i]]));
        trails_[order_[i]] = trail;
    }
    return b;
}

// Node `at` over order_[begin, end): two median splits make up to four children (a half of at
// most kLeafMax emitters is not split again), each a leaf of up to kLeafMax emitters or a
// node of its own. `trail` holds the choices down to `at`, 2 bits a level (32 levels:
// 8 x 4^32 emitters). Returns the bound of them all.
LightTree::Bound LightTree::build(uint32_t at, size_t begin, size_t end, const std::vector<LightBound>& lights, uint64_t trail, int depth) {
    size_t cut[kWidth + 1];
    int parts = 0;
    cut[0] = begin;
    if (end - begin <= kLeafMax) {
        cut[++parts] = end;
    } else {
        const size_t mid = split(begin, end, lights);
        for (const auto& [lo, hi] : {std::pair{begin, mid}, std::pair{mid, end}}) {
            if (hi - lo > kLeafMax) cut[++parts] = split(lo, hi, lights);
            cut[++parts] = hi;
        }
    }
    Bound all;
    for (int k = 0; k < parts; ++k) {
        const uint64_t lane_trail = trail | (static_cast<uint64_t>(k) << (2 * std::min(depth, 31)));
        Bound b;
        if (cut[k + 1] - cut[k] <= kLeafMax) {
            b = leaf_bound(cut[k], cut[k + 1], lights, lane_trail);
            nodes_[at].child[k] = static_cast<uint32_t>(cut[k]);
            nodes_[at].count[k] = static_cast<uint32_t>(cut[k + 1] - cut[k]);
        } else {
            const uint32_t child = static_cast<uint32_t>(nodes_.size());
            nodes_.emplace_back();
            b = build(child, cut[k], cut[k + 1], lights, lane_trail, depth + 1);
            nodes_[at].child[k] = child;
            nodes_[at].count[k] = 0;
        }
        set_lane(nodes_[at], k, b);
        if (k == 0) {
            all = b;
        } else {
            all.add(b);
        }
    }
    return all;
}

// Lane k of n from a bound, rounded so that it stays one: the sphere a little larger, the
// power never 0 for a group that has some.
void LightTree::set_lane(Node& n, int k, const Bound& b) const {
    const Vec3 centre = (b.lo + b.hi) / 2;
    n.cx[k] = static_cast<float>(centre.x), n.cy[k] = static_cast<float>(centre.y), n.cz[k] = static_cast<float>(centre.z);
    n.radius[k] = static_cast<float>(length(b.hi - b.lo) / 2 * (1 + 1e-5) + 1e-6 * (std::fabs(centre.x) + std::fabs(centre.y) + std::fabs(centre.z)));
    n.ax[k] = static_cast<float>(b.axis.x), n.ay[k] = static_cast<float>(b.axis.y), n.az[k] = static_cast<float>(b.axis.z);
    n.cos_spread[k] = static_cast<float>(b.cos_spread);
    n.sin_spread[k] = static_cast<float>(safe_sqrt(1 - b.cos_spread * b.cos_spread));
    n.power[k] = b.power > 0 ? std::max(static_cast<float>(b.power / power_scale_), 1e-30f) : 0.0f;
}

// pbrt-v4's LightBounds::Importance for emitters that emit over the hemisphere about each of
// their normals, for the four children at once: power x the cosine at the emitters bounded from
// above / distance^2 (at least the bounding sphere's radius squared), times the bound of the
// cosine at a surface that only reflects (signed: nothing below its horizon). Angles as sines
// and cosines: no acos at a hit; every lane the same arithmetic, no branches, written in GCC's
// vector extension (four floats; SSE where the target has it). Both cosine bounds are raised
// by kSlack: in single precision a group just able to light x must not round to 0 (a group
// that cannot costs a sample that finds nothing, which the exact weights of its leaf then say).
void LightTree::importances(const Node& n, const Vec3& x, const Vec3* normal, double w[kWidth]) {
    static_assert(kWidth == 4, "one vector of four floats a node");
    const F4 slack = splat(1e-5f), zero = splat(0.f), one = splat(1.f), tiny = splat(1e-30f);
    const F4 tx = splat(static_cast<float>(x.x)) - load(n.cx), ty = splat(static_cast<float>(x.y)) - load(n.cy),
             tz = splat(static_cast<float>(x.z)) - load(n.cz);
    const F4 radius = load(n.radius), spread_cos = load(n.cos_spread), spread_sin = load(n.sin_spread);
    const F4 d2 = tx * tx + ty * ty + tz * tz, r2 = radius * radius;
    const auto outside = d2 > r2;
    const F4 inv_d = one / sqrt4(max4(d2, tiny));
    const F4 wx = tx * inv_d, wy = ty * inv_d, wz = tz * inv_d;
    // The cone of directions from x that holds the bounding sphere (all of them from inside it).
    const F4 sin_b = outside ? radius * inv_d : zero;
    const F4 cos_b = outside ? sqrt4(max4(zero, one - sin_b * sin_b)) : splat(-1.f);
    // The smallest angle between an emitter's normal and a direction from it to x, less the
    // normals' cone: no emitter faces x when even that is past 90 degrees.
    const F4 cos_w = load(n.ax) * wx + load(n.ay) * wy + load(n.az) * wz;
    const F4 sin_w = sqrt4(max4(zero, one - cos_w * cos_w));
    const auto within = (spread_cos <= splat(-1.f)) | (cos_w > spread_cos);
    const F4 cos_x = within ? one : cos_w * spread_cos + sin_w * spread_sin;
    const F4 sin_x = within ? zero : sin_w * spread_cos - cos_w * spread_sin;
    const F4 cos_emit = (cos_x > cos_b ? one : cos_x * cos_b + sin_x * sin_b) + slack;
    const F4 falloff = outside ? inv_d * inv_d : one / max4(r2, tiny);
    F4 value = load(n.power) * max4(cos_emit, zero) * falloff;
    if (normal) {  // the horizon: the smallest angle between the normal and a direction into the sphere
        const F4 cos_i = -(wx * splat(static_cast<float>(normal->x)) + wy * splat(static_cast<float>(normal->y)) +
                           wz * splat(static_cast<float>(normal->z)));
        const F4 sin_i = sqrt4(max4(zero, one - cos_i * cos_i));
        value = value * (cos_i < cos_b ? max4(zero, cos_i * cos_b + sin_i * sin_b + slack) : one);
    }
    value = value < splat(3e38f) ? max4(value, zero) : zero;  // not NaN nor infinite
    for (int k = 0; k < kWidth; ++k) w[k] = value[k];
}

}  // namespace crex
