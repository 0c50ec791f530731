// libFuzzer target: any bytes as a native JSON scene and as a RADIANCE scene. Invariants: no
// crash or sanitizer report, spans inside the input, a scene only when there are no errors.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "runtime/scene/load_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    std::string text(reinterpret_cast<const char*>(data), size);
    for (int format = 0; format < 2; ++format) {
        SceneSources sources;
        DiagnosticSink sink;
        const SourceFile& f = sources.add(format ? "fuzz.rad" : "fuzz.json", text);
        std::optional<Scene> s = format ? import_radiance(f, sink) : load_scene_json(f, "/nonexistent", sources, sink);
        if (s.has_value() == sink.has_errors()) std::abort();
        for (const auto& d : sink.diagnostics())
            if (d.span.file == &f && (d.span.end > size || d.span.begin > d.span.end)) std::abort();
    }
    return 0;
}
