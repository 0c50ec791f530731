#include "runtime/scene/camera_path.h"

#include <algorithm>
#include <cmath>

namespace crex {
namespace {

// Chords per segment of the arc-length table: the chord sum then differs from the arc length
// by about (turn per chord)^2 / 24, below 1e-5 for a segment turning 90 degrees.
constexpr int kChords = 128;

// A key's neighbour, continued past the ends by reflection (P[-1] = 2 P[0] - P[1]).
template <class Get>
Vec3 extended(const Get& get, size_t n, long i) {
    if (i < 0) return n > 1 ? get(0) * 2 - get(1) : get(0);
    if (i >= static_cast<long>(n)) return n > 1 ? get(n - 1) * 2 - get(n - 2) : get(n - 1);
    return get(static_cast<size_t>(i));
}

// Centripetal Catmull-Rom between p1 and p2 (Barry and Goldman's pyramid): knots spaced by the
// square root of the distance between control points. A zero distance (a key repeated) gets
// a tiny knot interval, whose division then multiplies a zero difference.
Vec3 centripetal(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3, double u) {
    const double d12 = std::sqrt(length(p2 - p1));
    const double tiny = 1e-6 * d12 + 1e-300;
    const double t0 = 0;
    const double t1 = t0 + std::max(std::sqrt(length(p1 - p0)), tiny);
    const double t2 = t1 + std::max(d12, tiny);
    const double t3 = t2 + std::max(std::sqrt(length(p3 - p2)), tiny);
    const double t = t1 + u * (t2 - t1);
    const Vec3 a1 = p0 * ((t1 - t) / (t1 - t0)) + p1 * ((t - t0) / (t1 - t0));
    const Vec3 a2 = p1 * ((t2 - t) / (t2 - t1)) + p2 * ((t - t1) / (t2 - t1));
    const Vec3 a3 = p2 * ((t3 - t) / (t3 - t2)) + p3 * ((t - t2) / (t3 - t2));
    const Vec3 b1 = a1 * ((t2 - t) / (t2 - t0)) + a2 * ((t - t0) / (t2 - t0));
    const Vec3 b2 = a2 * ((t3 - t) / (t3 - t1)) + a3 * ((t - t1) / (t3 - t1));
    return b1 * ((t2 - t) / (t2 - t1)) + b2 * ((t - t1) / (t2 - t1));
}

// Uniform Catmull-Rom (cubic Hermite with tangents (p2 - p0) / 2 and (p3 - p1) / 2).
Vec3 uniform(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3, double u) {
    const double u2 = u * u, u3 = u2 * u;
    return p1 * (2 * u3 - 3 * u2 + 1) + (p2 - p0) * (0.5 * (u3 - 2 * u2 + u)) + p2 * (-2 * u3 + 3 * u2) +
           (p3 - p1) * (0.5 * (u3 - u2));
}

// A unit vector between two keys' unit vectors: the spline's, renormalised; where it passes
// through zero (opposite keys), the nearer key's.
Vec3 unit_between(const Vec3& spline, const Vec3& a, const Vec3& b, double u) {
    Vec3 v = normalize_or_zero(spline);
    return v != Vec3{} ? v : (u < 0.5 ? a : b);
}

}  // namespace

CameraPath::CameraPath(std::vector<CameraKey> keys, PathAim aim, PathTiming timing, PathFields fields)
    : keys_(std::move(keys)), aim_(aim), timing_(timing), fields_(std::move(fields)) {
    for (CameraKey& k : keys_) {
        if (aim_ == PathAim::kDirection) k.aim = normalize_or_zero(k.aim);
        k.up = normalize_or_zero(k.up);
    }
    segment_start_.assign(keys_.size(), 0);
    chord_sums_.resize(segments());
    for (size_t i = 0; i < segments(); ++i) {
        std::vector<double>& sums = chord_sums_[i];
        sums.assign(kChords + 1, 0);
        Vec3 prev = keys_[i].position;
        for (int j = 1; j <= kChords; ++j) {
            const Vec3 p = position({i, double(j) / kChords});
            sums[static_cast<size_t>(j)] = sums[static_cast<size_t>(j - 1)] + crex::length(p - prev);
            prev = p;
        }
        segment_start_[i + 1] = segment_start_[i] + sums.back();
    }
    total_length_ = segment_start_.back();
}

double CameraPath::key_time(size_t i) const {
    if (timing_ == PathTiming::kKeys || !(total_length_ > 0)) return keys_[i].time;
    if (i + 1 == keys_.size()) return end_time();  // exactly, not by rounding
    return start_time() + (end_time() - start_time()) * (segment_start_[i] / total_length_);
}

double CameraPath::u_at_length(size_t segment, double s) const {
    const std::vector<double>& sums = chord_sums_[segment];
    if (!(sums.back() > 0)) return 0;
    if (s <= 0) return 0;
    if (s >= sums.back()) return 1;
    const size_t j = static_cast<size_t>(std::upper_bound(sums.begin(), sums.end(), s) - sums.begin());  // sums[j-1] <= s < sums[j]
    const double span = sums[j] - sums[j - 1];
    const double f = span > 0 ? (s - sums[j - 1]) / span : 0;
    return (double(j - 1) + f) / kChords;
}

CameraPath::Where CameraPath::locate(double t) const {
    if (segments() == 0) return {0, 0};
    t = std::clamp(t, start_time(), end_time());
    if (t >= end_time()) return {segments() - 1, 1};
    if (timing_ == PathTiming::kKeys) {
        // The segment whose keys' times hold t; within it, constant speed (or, where the camera
        // stands still and turns, the parameter in proportion to time).
        const size_t next = static_cast<size_t>(
            std::upper_bound(keys_.begin(), keys_.end(), t, [](double v, const CameraKey& k) { return v < k.time; }) - keys_.begin());
        const size_t i = std::min(next == 0 ? 0 : next - 1, segments() - 1);
        const double dt = keys_[i + 1].time - keys_[i].time;
        const double f = dt > 0 ? std::clamp((t - keys_[i].time) / dt, 0.0, 1.0) : 1.0;
        const double len = chord_sums_[i].back();
        return {i, len > 0 ? u_at_length(i, f * len) : f};
    }
    const double span = end_time() - start_time();
    const double s = span > 0 ? total_length_ * (t - start_time()) / span : 0;
    const size_t next = static_cast<size_t>(std::upper_bound(segment_start_.begin(), segment_start_.end(), s) - segment_start_.begin());
    const size_t i = std::min(next == 0 ? 0 : next - 1, segments() - 1);
    return {i, u_at_length(i, s - segment_start_[i])};
}

Vec3 CameraPath::position(Where w) const {
    const size_t n = keys_.size();
    if (n == 1 || w.u <= 0) return keys_[w.segment].position;
    if (w.u >= 1) return keys_[w.segment + 1].position;
    auto get = [&](size_t k) { return keys_[k].position; };
    const long i = static_cast<long>(w.segment);
    if (keys_[w.segment].position == keys_[w.segment + 1].position) return keys_[w.segment].position;  // standing still
    return centripetal(extended(get, n, i - 1), get(w.segment), get(w.segment + 1), extended(get, n, i + 2), w.u);
}

void CameraPath::orientation(Where w, Vec3& direction, Vec3& up, double& vfov, double& hfov) const {
    const size_t n = keys_.size();
    const size_t a = w.segment, b = std::min(w.segment + 1, n - 1);
    const long i = static_cast<long>(w.segment);
    const double u = n == 1 ? 0 : std::clamp(w.u, 0.0, 1.0);
    auto spline = [&](auto get) { return uniform(extended(get, n, i - 1), get(a), get(b), extended(get, n, i + 2), u); };
    // At a key exactly, the key itself (no rounding through the spline).
    const bool at_a = u <= 0, at_b = u >= 1;
    const CameraKey& ka = keys_[a];
    const CameraKey& kb = keys_[b];
    auto aim_of = [&](size_t k) { return keys_[k].aim; };
    Vec3 aim = at_a ? ka.aim : at_b ? kb.aim : spline(aim_of);
    if (aim_ == PathAim::kLookAt) {
        direction = normalize_or_zero(aim - position(w));
    } else {
        direction = at_a || at_b ? aim : unit_between(aim, ka.aim, kb.aim, u);
    }
    auto up_of = [&](size_t k) { return keys_[k].up; };
    up = at_a ? ka.up : at_b ? kb.up : unit_between(spline(up_of), ka.up, kb.up, u);
    auto scalar = [&](double CameraKey::*field) {
        if (at_a) return ka.*field;
        if (at_b) return kb.*field;
        auto get = [&](size_t k) { return Vec3{keys_[k].*field, 0, 0}; };
        const double lo = std::min(ka.*field, kb.*field), hi = std::max(ka.*field, kb.*field);
        return std::clamp(spline(get).x, lo, hi);  // no overshoot past either key's value
    };
    vfov = scalar(&CameraKey::vfov);
    hfov = scalar(&CameraKey::hfov);
}

Vec3 CameraPath::position_at(double t) const { return position(locate(t)); }

Camera CameraPath::camera_at(double t, const Camera& scene_camera) const {
    Camera cam = fields_.base ? *fields_.base : scene_camera;
    const Where w = locate(t);
    Vec3 direction, up;
    double vfov = 0, hfov = 0;
    orientation(w, direction, up, vfov, hfov);
    cam.position = position(w);
    if (direction != Vec3{}) cam.direction = direction;
    if (fields_.up && up != Vec3{}) cam.up = up;
    if (fields_.fov) cam.vfov_deg = vfov, cam.hfov_deg = hfov;
    return cam;
}

}  // namespace crex
