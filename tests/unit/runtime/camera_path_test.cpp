// Camera paths (issue 36): the camera passes through every key exactly (position, aim, up,
// field of view), moves at constant speed along the spline where the timing says so, and a
// RADIANCE file of one view per line gives each line's view at its frame.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "runtime/scene/camera_path_file.h"

namespace crex {
namespace {

CameraPath read_path(const std::string& text, double fps = 30) {
    SourceFile file("path.json", text);
    DiagnosticSink sink;
    auto path = read_camera_path(file, fps, sink);
    EXPECT_TRUE(path.has_value());
    EXPECT_EQ(sink.error_count(), 0u);
    return *path;
}

// Uneven keys with a sharp turn: where a uniform parameter would speed up and slow down.
const char* kWalk = R"({
  "keys": [
    {"time": 1, "position": [0, 1.6, 9.5], "look_at": [0, 1.4, 0], "up": [0, 1, 0], "vfov": 50},
    {"position": [0.3, 1.6, 8.8], "look_at": [-1.2, 1.3, 3], "vfov": 40},
    {"position": [-1.0, 1.6, 2.5], "look_at": [0.6, 1.2, -4]},
    {"position": [1.0, 1.7, 2.0], "look_at": [2, 1.2, -4], "up": [0.1, 1, 0]},
    {"time": 5, "position": [0, 1.6, -7.5], "look_at": [0, 2.2, -10]}
  ]
})";

double arc_between(const CameraPath& path, double t0, double t1, int chords) {
    double s = 0;
    Vec3 prev = path.position_at(t0);
    for (int j = 1; j <= chords; ++j) {
        Vec3 p = path.position_at(t0 + (t1 - t0) * j / chords);
        s += length(p - prev);
        prev = p;
    }
    return s;
}

TEST(CameraPath, PassesThroughEveryKeyExactly) {
    const CameraPath path = read_path(kWalk);
    const Camera scene;  // up and fov of keys without them: the key before's
    const double scale = 10;
    const Vec3 look_at[] = {{0, 1.4, 0}, {-1.2, 1.3, 3}, {0.6, 1.2, -4}, {2, 1.2, -4}, {0, 2.2, -10}};
    const double vfov[] = {50, 40, 40, 40, 40};
    double previous = -1;
    for (size_t i = 0; i < path.keys().size(); ++i) {
        const double t = path.key_time(i);
        EXPECT_GT(t, previous) << "key " << i;  // keys are passed in order
        previous = t;
        const Camera c = path.camera_at(t, scene);
        const CameraKey& k = path.keys()[i];
        EXPECT_LT(length(c.position - k.position), 1e-9 * scale) << "key " << i;
        EXPECT_LT(length(normalize_or_zero(c.direction) - normalize_or_zero(look_at[i] - k.position)), 1e-9) << "key " << i;
        EXPECT_LT(length(c.up - normalize_or_zero(k.up)), 1e-12) << "key " << i;
        EXPECT_DOUBLE_EQ(c.vfov_deg, vfov[i]) << "key " << i;
    }
    EXPECT_DOUBLE_EQ(path.key_time(0), 1);
    EXPECT_DOUBLE_EQ(path.key_time(4), 5);
}

// Equal times, equal arc lengths: the 20 twentieths of the time each cover a twentieth of the
// path within 0.1 %. The path's own table has 128 chords a segment; the check measures with
// 400 chords per interval of the camera's actual positions, so the table's error shows.
TEST(CameraPath, MovesAtConstantSpeed) {
    const CameraPath path = read_path(kWalk);
    const int n = 20;
    const double whole = arc_between(path, 1, 5, 8000);
    EXPECT_NEAR(whole, path.length(), 1e-4 * whole);
    for (int k = 0; k < n; ++k) {
        const double t0 = 1 + 4.0 * k / n, t1 = 1 + 4.0 * (k + 1) / n;
        EXPECT_NEAR(arc_between(path, t0, t1, 400), whole / n, 1e-3 * whole / n) << "interval " << k;
    }
    // Without the re-parameterisation the spline's own parameter is far from even here:
    // key 1 is 0.76 m from key 0 but key 2 is 7 m further, each one segment.
    EXPECT_LT(path.key_time(1) - path.key_time(0), 0.2 * (path.key_time(2) - path.key_time(1)));
}

// Timed keys: each key at its own time, constant speed within each segment, and a turn on the
// spot (a key repeating the position before) that takes its time.
TEST(CameraPath, KeysTimingReachesEachKeyAtItsTime) {
    const CameraPath path = read_path(R"({"timing": "keys", "keys": [
        {"time": 0, "position": [0, 0, 0], "direction": [0, 0, -1]},
        {"time": 1, "position": [0, 0, -2], "direction": [0, 0, -1]},
        {"time": 3, "position": [0, 0, -2], "direction": [1, 0, 0]},
        {"time": 4, "position": [3, 0, -2], "direction": [1, 0, 0]}]})");
    const Camera scene;
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_DOUBLE_EQ(path.key_time(i), path.keys()[i].time);
        EXPECT_LT(length(path.position_at(path.keys()[i].time) - path.keys()[i].position), 1e-12) << "key " << i;
    }
    // The turn: standing at (0, 0, -2) from 1 s to 3 s, the direction swinging from -z to +x.
    double last_x = -1;
    for (int j = 0; j <= 10; ++j) {
        const Camera c = path.camera_at(1 + 0.2 * j, scene);
        EXPECT_LT(length(c.position - Vec3{0, 0, -2}), 1e-12) << j;
        EXPECT_NEAR(length(c.direction), 1, 1e-12);
        EXPECT_GE(c.direction.x, last_x - 1e-12) << "the turn goes one way";
        last_x = c.direction.x;
    }
    // Within the first segment (a straight line of 2 m in 1 s): 2 m/s throughout.
    for (int j = 0; j < 10; ++j) EXPECT_NEAR(length(path.position_at(0.1 * (j + 1)) - path.position_at(0.1 * j)), 0.2, 2e-4);
    // Up and fov: the scene camera's, since no key gives them.
    const Camera scene_camera{{0, 0, 5}, {0, 0, -1}, {0, 0, 1}, 33};
    const Camera c = path.camera_at(0.5, scene_camera);
    EXPECT_EQ(c.up, (Vec3{0, 0, 1}));
    EXPECT_EQ(c.vfov_deg, 33);
}

// A RADIANCE walkthrough: line k is frame k's view, at any fps; between lines the camera
// moves on (unit direction, fov between the lines').
TEST(CameraPath, ViewFileGivesEachLinesView) {
    const std::string text =
        "# a walkthrough, as ranimate reads one\n"
        "rview -vtv -vp 0 0 1.5 -vd 0 1 0 -vu 0 0 1 -vh 60 -vv 45\n"
        "\n"
        "-vp 0 1 1.5 -vd 1 1 0 -vh 50 -vv 40  # a comment\n"
        "-vtv -vp 0.5 2 1.6 -vd 1 0 0 -vu 0 0 1 -vh 40 -vv 30\n";
    for (double fps : {30.0, 24.0}) {
        const CameraPath path = read_path(text, fps);
        ASSERT_EQ(path.keys().size(), 3u);
        const Camera scene;  // y up, 45 degrees: a view file's own (RADIANCE's) defaults win
        const Vec3 vp[] = {{0, 0, 1.5}, {0, 1, 1.5}, {0.5, 2, 1.6}};
        const Vec3 vd[] = {{0, 1, 0}, normalize_or_zero(Vec3{1, 1, 0}), {1, 0, 0}};
        const double vh[] = {60, 50, 40}, vv[] = {45, 40, 30};
        for (int k = 0; k < 3; ++k) {
            const Camera c = path.camera_at(k / fps, scene);
            EXPECT_LT(length(c.position - vp[k]), 1e-12) << k;
            EXPECT_LT(length(c.direction - vd[k]), 1e-12) << k;
            EXPECT_EQ(c.up, (Vec3{0, 0, 1})) << k;
            EXPECT_DOUBLE_EQ(c.hfov_deg, vh[k]) << k;
            EXPECT_DOUBLE_EQ(c.vfov_deg, vv[k]) << k;
            EXPECT_EQ(c.projection, Projection::kPerspective);
        }
        const Camera mid = path.camera_at(0.5 / fps, scene);
        EXPECT_NEAR(length(mid.direction), 1, 1e-12);
        EXPECT_GT(mid.hfov_deg, 50);
        EXPECT_LT(mid.hfov_deg, 60);
        EXPECT_DOUBLE_EQ(path.end_time(), 2 / fps);
    }
}

}  // namespace
}  // namespace crex
