#include "runtime/scene/radiance/transform.h"

#include "runtime/base/sampling.h"
#include <fmt/format.h>

#include <cmath>
#include <cstdlib>

#include "runtime/scene/radiance/scene_text.h"

namespace crex::radiance {
namespace {


// The largest -i count we repeat: a transform applied more often than this is a typo (and
// would take as long as its count).
constexpr long kMaxIterations = 1000000;

}  // namespace

Transform::Transform() {
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m_[r][c] = r == c ? 1.0 : 0.0;
}

Vec3 Transform::point(const Vec3& p) const {
    return {p.x * m_[0][0] + p.y * m_[1][0] + p.z * m_[2][0] + m_[3][0], p.x * m_[0][1] + p.y * m_[1][1] + p.z * m_[2][1] + m_[3][1],
            p.x * m_[0][2] + p.y * m_[1][2] + p.z * m_[2][2] + m_[3][2]};
}

Vec3 Transform::vector(const Vec3& v) const {
    return {v.x * m_[0][0] + v.y * m_[1][0] + v.z * m_[2][0], v.x * m_[0][1] + v.y * m_[1][1] + v.z * m_[2][1],
            v.x * m_[0][2] + v.y * m_[1][2] + v.z * m_[2][2]};
}

Transform Transform::then(const Transform& next) const {
    if (next.identity_) return *this;
    if (identity_) return next;
    Transform r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double s = 0;
            for (int k = 0; k < 4; ++k) s += m_[i][k] * next.m_[k][j];
            r.m_[i][j] = s;
        }
    r.scale_ = scale_ * next.scale_;
    r.identity_ = false;
    return r;
}

Transform Transform::translate(const Vec3& t) {
    Transform r;
    r.m_[3][0] = t.x, r.m_[3][1] = t.y, r.m_[3][2] = t.z;
    r.identity_ = t == Vec3{};
    return r;
}

Transform Transform::rotate(int axis, double degrees) {
    Transform r;
    const double a = degrees * kPi / 180.0, c = std::cos(a), s = std::sin(a);
    // Counter-clockwise looking down the axis (towards the origin), as xform rotates.
    const int i = (axis + 1) % 3, j = (axis + 2) % 3;
    r.m_[i][i] = c, r.m_[j][j] = c;
    r.m_[i][j] = s, r.m_[j][i] = -s;
    r.identity_ = degrees == 0;
    return r;
}

Transform Transform::scaling(double s) {
    Transform r;
    r.m_[0][0] = r.m_[1][1] = r.m_[2][2] = s;
    r.scale_ = s;
    r.identity_ = s == 1;
    return r;
}

Transform Transform::mirror(int axis) {
    Transform r;
    r.m_[axis][axis] = -1;
    r.scale_ = -1;
    r.identity_ = false;
    return r;
}

bool is_transform_option(const std::string& w) {
    return w == "-t" || w == "-rx" || w == "-ry" || w == "-rz" || w == "-s" || w == "-mx" || w == "-my" || w == "-mz" || w == "-i";
}

bool parse_transform(const std::vector<std::string>& words, size_t first, Transform& out, size_t& consumed, std::string& error,
                     size_t& bad_word) {
    Transform total, group;
    long repeat = 1;  // how often `group` applies: once, until the first -i says otherwise
    size_t i = first;
    auto number = [&](size_t k, double& x) {
        if (k >= words.size()) {
            error = fmt::format("'{}' needs more numbers", words[i]);
            bad_word = i;
            return false;
        }
        if (!parse_real(words[k], x)) {
            error = fmt::format("'{}': expected a number, got '{}'", words[i], words[k]);
            bad_word = k;
            return false;
        }
        return true;
    };
    auto flush = [&] {  // total then group^repeat, by squaring (an array of 10^5 copies stays cheap)
        Transform power, base = group;
        for (long k = repeat; k > 0; k >>= 1, base = base.then(base))
            if (k & 1) power = power.then(base);
        total = total.then(power);
        group = Transform();
    };
    for (; i < words.size() && is_transform_option(words[i]); ++i) {
        const std::string& o = words[i];
        if (o == "-t") {
            double x, y, z;
            if (!number(i + 1, x) || !number(i + 2, y) || !number(i + 3, z)) return false;
            group = group.then(Transform::translate({x, y, z}));
            i += 3;
        } else if (o[1] == 'r') {
            double a;
            if (!number(i + 1, a)) return false;
            group = group.then(Transform::rotate(o[2] - 'x', a));
            ++i;
        } else if (o == "-s") {
            double s;
            if (!number(i + 1, s)) return false;
            if (s == 0) {
                error = "'-s 0' scales the scene to a point";
                bad_word = i + 1;
                return false;
            }
            group = group.then(Transform::scaling(s));
            ++i;
        } else if (o[1] == 'm') {
            group = group.then(Transform::mirror(o[2] - 'x'));
        } else {  // -i count
            double n;
            if (!number(i + 1, n)) return false;
            if (n < 0 || n != std::floor(n) || n > kMaxIterations) {
                error = fmt::format("'-i': expected a count in 0 .. {}, got '{}'", kMaxIterations, words[i + 1]);
                bad_word = i + 1;
                return false;
            }
            flush();
            repeat = static_cast<long>(n);
            ++i;
        }
    }
    flush();
    out = total;
    consumed = i - first;
    return true;
}

}  // namespace crex::radiance
