// libFuzzer target: any bytes as a RADIANCE view file (crex run --view, a .vf beside a .rad).
// Invariants: no crash or sanitizer report, spans inside the input, a finite camera frame
// when there are no errors.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "runtime/scene/radiance_view.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    SourceFile f("fuzz.vf", std::string(reinterpret_cast<const char*>(data), size));
    DiagnosticSink sink;
    Camera cam;
    apply_radiance_view(f, view_file_words(f), cam, true, sink);
    for (const auto& d : sink.diagnostics())
        if (d.span.file == &f && (d.span.end > size || d.span.begin > d.span.end)) std::abort();
    if (!sink.has_errors()) {
        for (double v : {cam.position.x, cam.position.y, cam.position.z, cam.direction.x, cam.direction.y, cam.direction.z,
                         cam.vfov_deg, cam.hfov_deg})
            if (!std::isfinite(v)) std::abort();
        if (!(length(cross(cam.direction, cam.up)) > 0)) std::abort();
    }
    return 0;
}
