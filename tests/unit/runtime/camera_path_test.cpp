// Camera paths (issue 36): the camera passes through every key exactly (position, aim, up,
// field of view), moves at constant speed along the spline where the timing says so, and a
// RADIANCE file of one view per line gives each line's view at its frame.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "runtime/api/frame_sequence.h"
#include "runtime/scene/camera_path_file.h"
#include "runtime/scene/gltf/gltf_camera_path.h"

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

// The frames a path holds at an fps, what a sequence renders without --frames: whole
// frames within its span, and never a frame number past kMaxFrame, however long the path (a
// path ending at 1e308 s rendered "0 frames" with exit 0: its last frame overflowed).
TEST(CameraPath, ItsFramesAreWholeFramesUpToTheLargestFrameNumber) {
    const CameraPath walk = read_path(kWalk);  // 1 s to 5 s
    const FrameRange frames = path_frames(walk, 30);
    EXPECT_EQ(frames.first, 30);
    EXPECT_EQ(frames.last, 150);
    EXPECT_EQ(check_path_frames(walk, 30), "");
    auto two_keys = [](const char* t0, const char* t1) {
        return read_path(std::string(R"({"keys": [{"time": )") + t0 + R"(, "position": [0, 1, 3], "look_at": [0, 1, 0]},
                                                  {"time": )" + t1 + R"(, "position": [0, 1, 2], "look_at": [0, 1, 0]}]})");
    };
    for (const char* end : {"1e308", "1e6"}) {
        const CameraPath endless = two_keys("0", end);
        EXPECT_EQ(path_frames(endless, 30).last, kMaxFrame + 1) << end;
        EXPECT_NE(check_path_frames(endless, 30).find("past frame 9999999"), std::string::npos) << check_path_frames(endless, 30);
    }
    const CameraPath between = two_keys("0.01", "0.02");  // frame 0 at 0 s, frame 1 at 0.033 s
    EXPECT_LT(path_frames(between, 30).last, path_frames(between, 30).first);
    EXPECT_NE(check_path_frames(between, 30).find("holds no whole frame at 30 fps"), std::string::npos);
    EXPECT_EQ(check_path_frames(between, 1000), "");  // frames 10..20
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

// A glTF camera on a rig: the rig turns 90 degrees about y (rotation, LINEAR: slerped) while
// the camera on it moves from 5 to 4 m in front of the rig's centre (translation, LINEAR), over
// one second, with a triangle to look at. The camera's world transform composes both.
const char* kRiggedCamera = R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0, 2]}],
  "nodes": [
    {"name": "rig", "children": [1]},
    {"name": "eye", "camera": 0, "translation": [0, 0, 5]},
    {"name": "tri", "mesh": 0}
  ],
  "cameras": [{"name": "dolly", "type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 3}}]}],
  "animations": [{
    "samplers": [{"input": 0, "output": 1, "interpolation": "LINEAR"}, {"input": 0, "output": 2}],
    "channels": [{"sampler": 0, "target": {"node": 0, "path": "rotation"}},
                 {"sampler": 1, "target": {"node": 1, "path": "translation"}}]
  }],
  "buffers": [{"byteLength": 100, "uri": "data:application/octet-stream;base64,AAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAPMENT8AAAAA8wQ1PwAAAAAAAAAAAACgQAAAAAAAAAAAAACAQAAAgL8AAIC/AAAAwAAAgD8AAIC/AAAAwAAAAAAAAIA/AAAAwA=="}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 8}, {"buffer": 0, "byteOffset": 8, "byteLength": 32},
                  {"buffer": 0, "byteOffset": 40, "byteLength": 24}, {"buffer": 0, "byteOffset": 64, "byteLength": 36}],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1]},
    {"bufferView": 1, "componentType": 5126, "count": 2, "type": "VEC4"},
    {"bufferView": 2, "componentType": 5126, "count": 2, "type": "VEC3"},
    {"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC3", "min": [-1, -1, -2], "max": [1, 1, -2]}
  ]
})";

TEST(CameraPath, GltfAnimationMovesTheCameraAsGltfSays) {
    const auto dir = std::filesystem::temp_directory_path() / ("crex_gltf_path_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string file = (dir / "rig.gltf").string();
    std::ofstream(file) << kRiggedCamera;
    SceneSources sources;
    DiagnosticSink sink;
    const auto text = gltf_camera_path_json(file, "", sources, sink);
    ASSERT_TRUE(text.has_value()) << (sink.diagnostics().empty() ? "" : sink.diagnostics()[0].message);
    const CameraPath path = read_path(*text);
    EXPECT_DOUBLE_EQ(path.start_time(), 0);
    EXPECT_DOUBLE_EQ(path.end_time(), 1);
    const double kPi = 3.14159265358979323846;
    for (double t : {0.0, 0.25, 0.5, 0.53, 0.9, 1.0}) {
        // The rig at angle 90 t degrees (slerp between two rotations about y is linear in angle),
        // the eye at 5 - t on the rig's +z.
        const double angle = kPi / 2 * t, d = 5 - t;
        const Vec3 want_position{d * std::sin(angle), 0, d * std::cos(angle)}, want_direction{-std::sin(angle), 0, -std::cos(angle)};
        const Camera c = path.camera_at(t, Camera{});
        // Keys every 1/8 s: exact there, and within a sample's chord of the arc between them.
        const double tolerance = std::fmod(t * 8, 1.0) == 0 ? 1e-6 : 2e-3;
        EXPECT_NEAR(c.position.x, want_position.x, tolerance * 5) << "t = " << t;
        EXPECT_NEAR(c.position.y, want_position.y, 1e-9) << "t = " << t;
        EXPECT_NEAR(c.position.z, want_position.z, tolerance * 5) << "t = " << t;
        const Vec3 looking = normalize_or_zero(c.direction);
        EXPECT_NEAR(looking.x, want_direction.x, tolerance) << "t = " << t;
        EXPECT_NEAR(looking.z, want_direction.z, tolerance) << "t = " << t;
        EXPECT_NEAR(c.vfov_deg, 0.8 * 180 / kPi, 1e-9);
    }
    // By name and by index as --camera takes them; a name that is not there is located.
    EXPECT_TRUE(gltf_camera_path_json(file, "dolly", sources, sink).has_value());
    EXPECT_TRUE(gltf_camera_path_json(file, "0", sources, sink).has_value());
    DiagnosticSink missing;
    EXPECT_FALSE(gltf_camera_path_json(file, "crane", sources, missing).has_value());
    ASSERT_EQ(missing.error_count(), 1u);
    EXPECT_NE(missing.diagnostics()[0].message.find("its cameras are 0 'dolly'"), std::string::npos) << missing.diagnostics()[0].message;
    // A camera no animation moves is refused, located at its node.
    std::string still = kRiggedCamera;
    still.replace(still.find("\"node\": 0"), 9, "\"node\": 2");
    still.replace(still.find("\"node\": 1"), 9, "\"node\": 2");
    std::ofstream(file) << still;
    DiagnosticSink not_moving;
    EXPECT_FALSE(gltf_camera_path_json(file, "", sources, not_moving).has_value());
    ASSERT_EQ(not_moving.error_count(), 1u);
    EXPECT_NE(not_moving.diagnostics()[0].message.find("is not animated"), std::string::npos) << not_moving.diagnostics()[0].message;
    EXPECT_TRUE(SourceLocation::of(not_moving.diagnostics()[0].span).known());
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace crex
