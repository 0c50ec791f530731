// Camera path files (issue 36) refuse what they cannot animate with a located error that says
// what was expected: the JSON path's fields, and a view file's lines.
#include <gtest/gtest.h>

#include "runtime/scene/camera_path_file.h"
#include "tests/support/diagnostic_helpers.h"

namespace crex {
namespace {

using PathCase = testing::DiagnosticCase;

class CameraPathDiagnostic : public ::testing::TestWithParam<PathCase> {};

TEST_P(CameraPathDiagnostic, IsLocatedAndNamesItsCause) {
    const PathCase& c = GetParam();
    SourceFile file("walk.path", c.text);
    DiagnosticSink sink;
    auto path = read_camera_path(file, 30, sink);
    testing::Diagnosed r{sink.sorted(), sink.error_count()};
    if (c.code[0] == 'E') {
        EXPECT_FALSE(path) << c.name;
    } else {
        EXPECT_TRUE(path) << c.name;  // a warning: the path is still read
    }
    testing::expect_diagnostic(r, c.name, c.code, c.line, c.col, c.message_part);
}

#define K0 "{\"time\": 0, \"position\": [0, 1, 0], \"look_at\": [0, 1, -5]}"
#define K1 "{\"time\": 2, \"position\": [0, 1, -3], \"look_at\": [0, 1, -9]}"

INSTANTIATE_TEST_SUITE_P(
    Refusals, CameraPathDiagnostic,
    ::testing::Values(
        PathCase{"syntax", "{\"keys\": [\n" K0 ",\n]}", "E301", 3, 1, ""},
        PathCase{"not_an_object", "[1, 2]", "E302", 1, 1, "a camera path must be a JSON object"},
        PathCase{"no_keys", "{\"timing\": \"keys\"}", "E304", 1, 1, "missing required field 'keys'"},
        PathCase{"empty_keys", "{\"keys\": []}", "E303", 1, 10, "at least one key"},
        PathCase{"unknown_timing", "{\"timing\": \"ease\", \"keys\": [" K0 "]}", "E303", 1, 12, "\"constant_speed\" or \"keys\""},
        PathCase{"no_position", "{\"keys\": [\n" K0 ",\n {\"time\": 1, \"look_at\": [0, 0, 0]}]}", "E304", 3, 2,
                 "missing required field 'position'"},
        PathCase{"no_aim", "{\"keys\": [\n{\"time\": 0, \"position\": [0, 1, 0]}]}", "E304", 2, 1, "'look_at'"},
        PathCase{"position_not_a_point", "{\"keys\": [\n{\"position\": [0, 1], \"look_at\": [0, 0, 0]}]}", "E302", 2, 14,
                 "expected an array of 3 numbers"},
        PathCase{"times_not_increasing", "{\"timing\": \"keys\", \"keys\": [\n" K1 ",\n" K0 "]}", "E303", 3, 10,
                 "0 s is not after the key before's 2 s"},
        PathCase{"last_time_missing", "{\"keys\": [\n" K0 ",\n{\"position\": [0, 1, -3], \"look_at\": [0, 1, -9]}]}", "E304", 3, 1,
                 "missing required field 'time'"},
        PathCase{"negative_time", "{\"keys\": [{\"time\": -1, \"position\": [0, 1, 0], \"look_at\": [0, 1, -5]}]}", "E303", 1, 20,
                 "expected a number >= 0"},
        PathCase{"mixed_aims", "{\"keys\": [\n" K0 ",\n{\"time\": 2, \"position\": [0, 1, -3], \"direction\": [0, 0, -1]}]}", "E303",
                 3, 37, "this path aims by 'look_at' (keys[0])"},
        PathCase{"up_on_a_later_key_only", "{\"keys\": [\n" K0 ",\n{\"time\": 2, \"position\": [0, 1, -3], \"look_at\": [0, 1, -9], \"up\": [0, 1, 0]}]}",
                 "E304", 2, 1, "keys[0]: missing 'up', which keys[1] gives"},
        PathCase{"vfov_out_of_range", "{\"keys\": [{\"position\": [0, 1, 0], \"look_at\": [0, 1, -5], \"vfov\": 180}]}", "E303", 1, 66,
                 "expected a number in (0, 180)"},
        PathCase{"repeated_position_at_constant_speed",
                 "{\"keys\": [\n" K0 ",\n{\"position\": [0, 1, 0], \"look_at\": [5, 1, 0]},\n" K1 "]}", "E306", 3, 14,
                 "at constant speed the camera would turn there in no time"},
        PathCase{"camera_at_its_look_at", "{\"keys\": [\n" K0 ",\n{\"time\": 2, \"position\": [0, 1, -5], \"look_at\": [0, 1, -5]}]}",
                 "E306", 3, 1, "reaches its look-at point"},
        PathCase{"aim_along_up", "{\"keys\": [{\"position\": [0, 1, 0], \"direction\": [0, 2, 0], \"up\": [0, 1, 0]}]}", "E306", 1, 11,
                 "looks along its up"},
        PathCase{"unknown_field", "{\"keys\": [{\"position\": [0, 1, 0], \"look_at\": [0, 1, -5], \"fov\": 40}]}", "W301", 1, 58,
                 "unknown field 'fov'"},
        PathCase{"intermediate_time_ignored", "{\"keys\": [\n" K0 ",\n{\"time\": 1, \"position\": [0, 1, -1], \"look_at\": [0, 1, -9]},\n" K1 "]}",
                 "W301", 3, 2, "keys[1].time is ignored"},
        // A view per line.
        PathCase{"view_bad_number", "-vp 0 0 1 -vd 0 1 0\n-vp 0 x 1 -vd 0 1 0\n", "E302", 2, 7, "expected a finite number, got 'x'"},
        PathCase{"view_type_changes", "-vtv -vp 0 0 1 -vd 0 1 0\n-vta -vp 0 1 1 -vd 0 1 0 -vh 180 -vv 180\n", "E303", 2, 1,
                 "differs from line 1's"},
        PathCase{"view_degenerate", "-vp 0 0 1 -vd 0 0 1\n", "E306", 1, 1, "parallel to the up vector"},
        // Found by camera_path_fuzzer: a direction whose length overflows has none once normalised.
        PathCase{"view_direction_overflows", "-vp 0 0 1 -vd 0 1 0\n-vp 0 0 1 -vd 1e301 2 -2 -vu 0 1 0\n", "E306", 2, 1,
                 "too long to normalise"},
        PathCase{"view_file_empty", "# nothing but a comment\n", "E304", 1, 1, "at least one line of view options"}),
    [](const ::testing::TestParamInfo<PathCase>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace crex
