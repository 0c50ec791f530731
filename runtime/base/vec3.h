/// \file vec3.h
/// A small double-precision 3-vector for the scene model (loading, validation, tessellation).
/// The renderer converts to float only where Embree needs it.
#pragma once

#include <cmath>

namespace crex {

struct Vec3 {
    double x = 0, y = 0, z = 0;

    constexpr Vec3() = default;
    constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}

    double operator[](int i) const { return i == 0 ? x : i == 1 ? y : z; }
    Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    Vec3 operator-() const { return {-x, -y, -z}; }
    Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
    Vec3 operator/(double s) const {
        double r = 1 / s;  // one division, not three
        return {x * r, y * r, z * r};
    }
    Vec3 operator*(const Vec3& o) const { return {x * o.x, y * o.y, z * o.z}; }
    Vec3& operator+=(const Vec3& o) { return *this = *this + o; }
    bool operator==(const Vec3& o) const { return x == o.x && y == o.y && z == o.z; }
    bool operator!=(const Vec3& o) const { return !(*this == o); }
};

inline Vec3 operator*(double s, const Vec3& v) { return v * s; }
inline double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const Vec3& v) { return std::sqrt(dot(v, v)); }
/// Rec. 709 luminance of a linear RGB value.
inline double luminance(const Vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }
inline bool is_finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
/// std::fmax and std::fmin (a NaN argument loses to a number), inline: without -ffast-math
/// GCC calls libm for them, and shading calls them at every hit.
inline double max_of(double a, double b) { return a >= b || b != b ? a : b; }
inline double min_of(double a, double b) { return a <= b || b != b ? a : b; }
inline double max_component(const Vec3& v) { return max_of(v.x, max_of(v.y, v.z)); }
/// Light per unit of throughput, channel by channel (a / b): 0 where b is not positive or the
/// ratio is not finite, never negative. What a ray brought back per unit weight.
inline Vec3 per_unit(const Vec3& a, const Vec3& b) {
    auto r = [](double x, double y) { return y > 0 && std::isfinite(x / y) ? max_of(0.0, x / y) : 0.0; };
    return {r(a.x, b.x), r(a.y, b.y), r(a.z, b.z)};
}
inline double min_component(const Vec3& v) { return min_of(v.x, min_of(v.y, v.z)); }
inline Vec3 vmin(const Vec3& a, const Vec3& b) { return {min_of(a.x, b.x), min_of(a.y, b.y), min_of(a.z, b.z)}; }
inline Vec3 vmax(const Vec3& a, const Vec3& b) { return {max_of(a.x, b.x), max_of(a.y, b.y), max_of(a.z, b.z)}; }
/// Unit vector, or the zero vector when `v` has no usable length.
inline Vec3 normalize_or_zero(const Vec3& v) {
    double l = length(v);
    return l > 0 && std::isfinite(l) ? v / l : Vec3{};
}

}  // namespace crex
