/// \file triangle_weights.h
/// What each of a few flat emitter triangles (or parallelograms) brings to a shading point (LightSampler's local
/// weights), two triangles at a time in vector code: a weight costs a square root and two
/// divisions, and weighing them one by one was 8 % of a render of the Cornell box.
#pragma once

#include <cstddef>
#include <vector>

#include "runtime/base/vec3.h"

namespace crex {

/// One flat emitter as the weights need it.
struct WeighedTriangle {
    Vec3 a, b, c;      ///< corners
    Vec3 d;            ///< a parallelogram's fourth corner; a triangle repeats one of a, b, c
    Vec3 normal;       ///< unit normal: the side it lights
    Vec3 centre;       ///< centroid
    double power = 0;  ///< area x luminance
    double area = 0;
    double reach = 0;  ///< distance from the centre to its farthest corner
};

/// The triangles' fields side by side (structure of arrays), padded to whole vectors.
class TriangleWeights {
public:
    TriangleWeights() = default;
    explicit TriangleWeights(const std::vector<WeighedTriangle>& triangles);
    bool empty() const { return count_ == 0; }
    size_t size() const { return count_; }
    /// w[i] for each triangle: 0 where x is behind it or (with `horizon`, the unit normal of a
    /// surface that only reflects) it lies wholly at or below the surface's plane; else its
    /// power / max(distance^2, area), times the cosines of its light at the triangle and at
    /// the surface, each widened by the sine of the angle its sphere fills from x, at most 1
    /// and at least 1e-9. The same arithmetic, in the same order, as LightSampler's scalar
    /// weights: the same values bit for bit.
    void weigh(const Vec3& x, const Vec3* horizon, double* w) const;

private:
    enum Field { kAx, kAy, kAz, kBx, kBy, kBz, kCx, kCy, kCz, kDx, kDy, kDz, kNx, kNy, kNz, kMx, kMy, kMz, kPower, kArea, kReach, kReach2, kFields };
    const double* field(Field f) const { return data_.data() + static_cast<size_t>(f) * stride_; }
    std::vector<double> data_;  ///< kFields rows of stride_ values
    size_t count_ = 0, stride_ = 0;
};

}  // namespace crex
