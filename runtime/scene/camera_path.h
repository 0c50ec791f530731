/// \file camera_path.h
/// A camera moving through a scene (issue 36): keys of position, aim (a point looked at, or a
/// direction), up and field of view, and the camera between them at any time.
///
/// Positions follow a centripetal Catmull-Rom spline (alpha = 1/2, Barry-Goldman form) through
/// the key positions: unlike the uniform one it makes no cusps or loops where keys are unevenly
/// spaced. The ends are continued by reflecting the second key about the first (and the last
/// but one about the last). The spline is re-parameterised by arc length from a table of 128
/// chords per segment, so the camera's speed is what the timing says:
///  - constant speed (the default): the camera leaves the first key at its time and reaches the
///    last key at its time at one speed all along; the keys between are passed where the arc
///    length puts them (key_time()).
///  - keys: each key is reached at its own time, at constant speed within each segment.
/// The aim, up and field of view are interpolated consistently with the position: by a uniform
/// Catmull-Rom spline in the same segment parameter, so that the camera at a key looks exactly
/// as that key says (directions and up renormalised; fields of view kept between their keys'
/// values, with no overshoot).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "runtime/base/vec3.h"
#include "runtime/scene/scene.h"

namespace crex {

enum class PathTiming { kConstantSpeed, kKeys };
enum class PathAim { kLookAt, kDirection };

struct CameraKey {
    double time = 0;  ///< seconds from the animation's start (frame f is at f / fps)
    Vec3 position;
    Vec3 aim;         ///< a point looked at, or a direction (PathAim)
    Vec3 up{0, 1, 0};
    double vfov = 45, hfov = 0;  ///< degrees; hfov 0: from vfov and the image's aspect
};

/// What a path sets of the camera besides position and aim; the rest is the scene's camera's.
struct PathFields {
    bool up = false;   ///< the keys' up (else the scene camera's)
    bool fov = false;  ///< the keys' vfov and hfov (else the scene camera's)
    /// The camera the path's cameras are made from (projection, fore clip, view distance):
    /// a RADIANCE view file's first view; unset: the scene's camera.
    std::optional<Camera> base;
};

class CameraPath {
public:
    /// `keys` non-empty, with finite values, ordered by time (strictly increasing where the
    /// timing uses them); under constant speed, consecutive keys at distinct positions. The
    /// file readers (camera_path_file.h) check this and say where; here it is assumed.
    CameraPath(std::vector<CameraKey> keys, PathAim aim, PathTiming timing, PathFields fields);

    double start_time() const { return keys_.front().time; }
    double end_time() const { return keys_.back().time; }
    double length() const { return total_length_; }  ///< arc length of the whole path
    const std::vector<CameraKey>& keys() const { return keys_; }
    PathAim aim() const { return aim_; }
    PathTiming timing() const { return timing_; }
    const PathFields& fields() const { return fields_; }

    /// When the camera passes key `i` (its own time under keys timing).
    double key_time(size_t i) const;
    /// The camera at time `t` (clamped to the path's span): `scene_camera` with the path's fields.
    Camera camera_at(double t, const Camera& scene_camera) const;
    Vec3 position_at(double t) const;

    /// A point on the path: segment `segment` (from key `segment` to the next) at spline
    /// parameter u in [0, 1]. Exposed so readers can check the aim along every segment.
    struct Where {
        size_t segment = 0;
        double u = 0;
    };
    Where locate(double t) const;
    Vec3 position(Where w) const;
    /// Direction, up, vfov, hfov at `w` (direction and up unit length, or zero where the
    /// interpolated aim degenerates: the camera at its look-at point).
    void orientation(Where w, Vec3& direction, Vec3& up, double& vfov, double& hfov) const;
    size_t segments() const { return keys_.size() > 1 ? keys_.size() - 1 : 0; }

private:
    double u_at_length(size_t segment, double s) const;  // s from the segment's start

    std::vector<CameraKey> keys_;
    PathAim aim_;
    PathTiming timing_;
    PathFields fields_;
    std::vector<double> segment_start_;            // arc length at each key
    std::vector<std::vector<double>> chord_sums_;  // per segment: arc length at u = j / kChords
    double total_length_ = 0;
};

}  // namespace crex
