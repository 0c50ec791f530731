#include "runtime/render/triangle_weights.h"

#include <cmath>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace crex {
namespace {

// Two doubles as one vector (GCC's and Clang's vector extension).
using D2 = double __attribute__((vector_size(16)));
constexpr size_t kLanes = 2;
D2 splat(double v) { return D2{v, v}; }
D2 load(const double* p) {
    D2 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
D2 sqrt2(D2 v) {
#if defined(__SSE2__)
    return _mm_sqrt_pd(v);
#else
    for (size_t k = 0; k < kLanes; ++k) v[k] = std::sqrt(v[k]);
    return v;
#endif
}

}  // namespace

TriangleWeights::TriangleWeights(const std::vector<WeighedTriangle>& triangles) : count_(triangles.size()) {
    stride_ = (count_ + kLanes - 1) / kLanes * kLanes;
    data_.assign(kFields * stride_, 0.0);
    for (size_t i = stride_; i-- > 0;) {
        // Padding lanes copy the last triangle: finite arithmetic, and never read.
        const WeighedTriangle& t = triangles[i < count_ ? i : count_ - 1];
        const double values[kFields] = {t.a.x,      t.a.y,      t.a.z,   t.b.x,   t.b.y,  t.b.z,   t.c.x,          t.c.y,     t.c.z,    t.d.x, t.d.y, t.d.z, t.normal.x,
                                        t.normal.y, t.normal.z, t.centre.x, t.centre.y, t.centre.z, t.power, t.area, t.reach, t.reach * t.reach};
        for (size_t f = 0; f < kFields; ++f) data_[f * stride_ + i] = values[f];
    }
}

void TriangleWeights::weigh(const Vec3& x, const Vec3* horizon, double* w) const {
    const D2 one = splat(1.0), zero = splat(0.0), floor = splat(1e-9);
    const D2 px = splat(x.x), py = splat(x.y), pz = splat(x.z);
    const D2 hx = splat(horizon ? horizon->x : 0), hy = splat(horizon ? horizon->y : 0), hz = splat(horizon ? horizon->z : 0);
    for (size_t i = 0; i < count_; i += kLanes) {
        const D2 ax = load(field(kAx) + i), ay = load(field(kAy) + i), az = load(field(kAz) + i);
        const D2 nx = load(field(kNx) + i), ny = load(field(kNy) + i), nz = load(field(kNz) + i);
        // Behind it: no light (LightSampler::local_weight).
        const auto in_front = (px - ax) * nx + (py - ay) * ny + (pz - az) * nz > zero;
        const D2 dx = px - load(field(kMx) + i), dy = py - load(field(kMy) + i), dz = pz - load(field(kMz) + i);
        const D2 d2 = dx * dx + dy * dy + dz * dz;
        const D2 area = load(field(kArea) + i);
        const D2 near_weight = load(field(kPower) + i) / (d2 >= area ? d2 : area);
        const D2 inv_d = one / sqrt2(d2), sin_b = load(field(kReach) + i) * inv_d;
        const auto min_one = [&](D2 v) { return (one <= v) | (v != v) ? one : v; };  // min_of(1, v)
        D2 cosines = min_one((dx * nx + dy * ny + dz * nz) * inv_d + sin_b);
        auto lit = in_front;
        if (horizon) {
            const D2 cos_h = min_one(-(dx * hx + dy * hy + dz * hz) * inv_d + sin_b);
            cosines = cosines * cos_h;
            // Wholly at or below the surface's plane: no corner above it (LightSampler::below_horizon).
            const auto below = [&](Field fx) {
                return (load(field(fx) + i) - px) * hx + (load(field(Field(fx + 1)) + i) - py) * hy + (load(field(Field(fx + 2)) + i) - pz) * hz <= zero;
            };
            lit = lit & ~(below(kAx) & below(kBx) & below(kCx) & below(kDx));
        }
        const D2 far_weight = near_weight * (cosines >= floor ? cosines : floor);
        const D2 value = d2 > load(field(kReach2) + i) ? far_weight : near_weight;
        const D2 weight = lit ? value : zero;
        for (size_t k = 0; k < kLanes && i + k < count_; ++k) w[i + k] = weight[k];
    }
}

}  // namespace crex
