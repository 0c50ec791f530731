// libFuzzer target: any bytes as a Wavefront OBJ and its MTL (the input split at a line
// "#mtl"; the OBJ names "fuzz.mtl" itself or not). Invariants: no crash or sanitizer report,
// a scene only when there are no errors, and then only finite vertices.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "runtime/scene/load_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    static const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("crex_obj_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::string text(reinterpret_cast<const char*>(data), size);
    std::string obj = text, mtl;
    if (size_t at = text.find("\n#mtl\n"); at != std::string::npos) obj = text.substr(0, at + 1), mtl = text.substr(at + 6);
    std::ofstream(dir / "fuzz.obj", std::ios::binary) << obj;
    std::ofstream(dir / "fuzz.mtl", std::ios::binary) << mtl;
    SceneSources sources;
    DiagnosticSink sink;
    std::optional<Scene> s = import_obj((dir / "fuzz.obj").string(), sink, sources);
    if (s.has_value() && sink.has_errors()) std::abort();
    if (s)
        for (const auto& shape : s->shapes)
            for (const auto& v : shape.vertices)
                if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) std::abort();
    return 0;
}
