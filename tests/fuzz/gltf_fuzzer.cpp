// libFuzzer target: any bytes as a glTF 2.0 file (.glb when they start with "glTF", else
// .gltf). Invariants: no crash, hang or sanitizer report; a scene only when there are no
// errors, and then only finite vertices, per-vertex attributes that match, materials that
// exist, vertex colours finite and not negative, and texture references to images that exist. Its camera animation, read as a camera
// path, likewise never crashes.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "runtime/scene/camera_path_file.h"
#include "runtime/scene/gltf/gltf_camera_path.h"
#include "runtime/scene/load_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    static const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("crex_gltf_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    const std::filesystem::path file = dir / (binary ? "fuzz.glb" : "fuzz.gltf");
    std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    SceneSources sources;
    DiagnosticSink sink;
    // Its camera animation, read as a path: no crash, and a path text only without errors.
    DiagnosticSink path_sink;
    if (auto text = gltf_camera_path_json(file.string(), "", sources, path_sink)) {
        if (path_sink.has_errors()) std::abort();
        DiagnosticSink read_sink;
        (void)read_camera_path(SourceFile("path.json", *text), 30, read_sink);
    }
    std::optional<Scene> s = import_gltf(file.string(), sink, sources);
    if (s.has_value() && sink.has_errors()) std::abort();
    if (!s) return 0;
    for (const auto& shape : s->shapes) {
        if (!s->find_material(shape.material)) std::abort();
        for (const auto& v : shape.vertices)
            if (!is_finite(v)) std::abort();
        if (!shape.uvs.empty() && shape.uvs.size() != shape.vertices.size()) std::abort();
        if (!shape.normals.empty() && shape.normals.size() != shape.vertices.size()) std::abort();
        if (!shape.colors.empty() && shape.colors.size() != shape.vertices.size()) std::abort();
        for (const auto& c : shape.colors)
            if (!is_finite(c) || c.x < 0 || c.y < 0 || c.z < 0) std::abort();
        for (const auto& t : shape.triangles)
            for (uint32_t i : t)
                if (i >= shape.vertices.size()) std::abort();
    }
    for (const auto& m : s->materials)
        m.textures.for_each([&](const char*, const TextureRef& t) {
            if (t.file.empty()) {
                bool found = false;
                for (const auto& i : s->images) found = found || i.name == t.image;
                if (!found) std::abort();
            }
            if (!is_finite(t.scale) || !std::isfinite(t.power)) std::abort();
            for (double x : t.uv_transform)
                if (!std::isfinite(x)) std::abort();
        });
    return 0;
}
