// libFuzzer target: any bytes as a native JSON scene, a RADIANCE scene and a RADIANCE project
// (.rif). Invariants: no crash or sanitizer report, spans inside the input, a scene only when
// there are no errors. The files are named in a directory that does not exist, so the `!xform`
// and `-vf` files an input names are never read from the machine (each is a located E308).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "runtime/scene/load_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    std::string text(reinterpret_cast<const char*>(data), size);
    for (int format = 0; format < 3; ++format) {
        SceneSources sources;
        DiagnosticSink sink;
        const char* names[] = {"/nonexistent/fuzz.json", "/nonexistent/fuzz.rad", "/nonexistent/fuzz.rif"};
        const SourceFile& f = sources.add(names[format], text);
        std::optional<Scene> s = format == 0   ? load_scene_json(f, "/nonexistent", sources, sink)
                                 : format == 1 ? import_radiance(f, sources, sink)
                                               : import_radiance_project(f, sources, {}, sink);
        if (s.has_value() == sink.has_errors()) std::abort();
        for (const auto& d : sink.diagnostics())
            if (d.span.file == &f && (d.span.end > size || d.span.begin > d.span.end)) std::abort();
    }
    return 0;
}
