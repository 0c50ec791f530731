// libFuzzer target: any bytes as a camera path file (crex run --camera-path: a JSON path of
// keys, or a RADIANCE file of one view per line). Invariants: no crash, hang or sanitizer
// report; spans inside the input; and a path read without errors gives, at any time (before,
// along and after it; a view file's at its lines), a camera with a finite position, a finite
// non-zero direction, finite fields of view and, where the path gives the up, an up not
// parallel to the direction: the frame every camera ray is made from.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "runtime/scene/camera_path_file.h"

namespace {

bool finite(const crex::Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    SourceFile f("fuzz.path", std::string(reinterpret_cast<const char*>(data), size));
    DiagnosticSink sink;
    const std::optional<CameraPath> path = read_camera_path(f, 30, sink);
    for (const auto& d : sink.diagnostics())
        if (d.span.file == &f && (d.span.end > size || d.span.begin > d.span.end)) std::abort();
    if (!path) return 0;
    if (sink.has_errors()) std::abort();  // a path comes back only without errors
    const Camera scene_camera;
    const double t0 = path->start_time(), t1 = path->end_time();
    if (!std::isfinite(t0) || !std::isfinite(t1) || t1 < t0 || !std::isfinite(path->length())) std::abort();
    // A view file's frames are its lines (frame k at any fps is line k): its cameras are
    // checked there; between them (a cut can turn the camera round) none is rendered.
    const bool view_lines = path->fields().base.has_value();
    constexpr int kSteps = 512;
    const int steps = view_lines ? static_cast<int>(path->keys().size()) - 1 : kSteps;
    for (int i = view_lines ? 0 : -2; i <= steps + (view_lines ? 0 : 2); ++i) {
        const double t = view_lines ? path->keys()[static_cast<size_t>(i)].time : t0 + (t1 - t0) * i / kSteps;
        const Camera c = path->camera_at(t, scene_camera);
        if (!finite(c.position) || !finite(c.direction) || !finite(c.up) || !std::isfinite(c.vfov_deg) || !std::isfinite(c.hfov_deg))
            std::abort();
        if (!(length(c.direction) > 0)) std::abort();
        // The reader can hold a path to an up it gives; the scene camera's up, where it gives
        // none, is checked frame by frame when the run knows it (check_path_cameras).
        if (path->fields().up && !(length(cross(c.direction, c.up)) > 0)) std::abort();
    }
    return 0;
}
