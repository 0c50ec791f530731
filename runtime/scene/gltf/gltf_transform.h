/// \file gltf_transform.h
/// glTF's node transforms: a column-major 4x4 matrix, and a node's matrix or TRS as one (the
/// importer's node tree and the camera animation both compose them).
#pragma once

#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <vector>

#include "runtime/base/vec3.h"

namespace crex::gltf {

/// Column-major 4x4 (glTF's order): m[column * 4 + row].
struct Mat4 {
    std::array<double, 16> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    Mat4 operator*(const Mat4& o) const {
        Mat4 r;
        for (int c = 0; c < 4; ++c)
            for (int row = 0; row < 4; ++row) {
                double s = 0;
                for (int k = 0; k < 4; ++k) s += m[size_t(k * 4 + row)] * o.m[size_t(c * 4 + k)];
                r.m[size_t(c * 4 + row)] = s;
            }
        return r;
    }
    Vec3 point(const Vec3& p) const {
        return {m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12], m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13],
                m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14]};
    }
    Vec3 vector(const Vec3& v) const {
        return {m[0] * v.x + m[4] * v.y + m[8] * v.z, m[1] * v.x + m[5] * v.y + m[9] * v.z, m[2] * v.x + m[6] * v.y + m[10] * v.z};
    }
    double det3() const {
        return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) + m[8] * (m[1] * m[6] - m[5] * m[2]);
    }
    /// Normals: the inverse transpose of the upper 3x3 (its cofactor matrix, up to the
    /// determinant's scale, which normalising removes; its sign is kept).
    Vec3 normal(const Vec3& n) const {
        const Vec3 c0{m[0], m[1], m[2]}, c1{m[4], m[5], m[6]}, c2{m[8], m[9], m[10]};
        const Vec3 r0 = cross(c1, c2), r1 = cross(c2, c0), r2 = cross(c0, c1);
        Vec3 out = r0 * n.x + r1 * n.y + r2 * n.z;
        return normalize_or_zero(det3() < 0 ? -out : out);
    }
};

/// Translation, rotation (a quaternion x, y, z, w; normalised here, identity if it cannot be)
/// and scale, applied scale first: a node's TRS.
inline Mat4 trs_transform(const std::vector<double>& translation, const std::vector<double>& rotation, const std::vector<double>& scale_xyz) {
    Mat4 translate, rotate, scale;
    if (translation.size() == 3) translate.m[12] = translation[0], translate.m[13] = translation[1], translate.m[14] = translation[2];
    if (rotation.size() == 4) {
        double x = rotation[0], y = rotation[1], z = rotation[2], w = rotation[3];
        const double len = std::sqrt(x * x + y * y + z * z + w * w);
        if (len > 0 && std::isfinite(len)) x /= len, y /= len, z /= len, w /= len;
        else x = y = z = 0, w = 1;
        rotate.m = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),     0,
                    2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),     0,
                    2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y), 0,
                    0,                       0,                       0,                       1};
    }
    if (scale_xyz.size() == 3) scale.m[0] = scale_xyz[0], scale.m[5] = scale_xyz[1], scale.m[10] = scale_xyz[2];
    return translate * rotate * scale;
}

/// A node's own transform: its matrix, or its TRS.
inline Mat4 local_transform(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) {
        Mat4 t;
        for (size_t i = 0; i < 16; ++i) t.m[i] = n.matrix[i];
        return t;
    }
    return trs_transform(n.translation, n.rotation, n.scale);
}

}  // namespace crex::gltf
