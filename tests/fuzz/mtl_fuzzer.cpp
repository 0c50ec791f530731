// libFuzzer target: any bytes as the MTL of a fixed OBJ (with texture coordinates and normals,
// and faces of four materials), textures included: map_Kd, map_Ks, map_Ns, map_d, bump, norm,
// map_Ke and their options. Invariants: no crash or sanitizer report; a scene only when there
// are no errors, and then every texture reference an absolute path with finite numbers.
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
    static const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("crex_mtl_fuzz_" + std::to_string(::getpid()));
    static const bool ready = [] {
        std::filesystem::create_directories(dir / "tex");
        std::ofstream(dir / "tex" / "wood.png") << "texels";
        std::ofstream(dir / "fuzz.obj") << "mtllib fuzz.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nvn 0 0 1\n"
                                           "usemtl a\nf 1/1/1 2/2/1 3/3/1\nusemtl b\nf 2/2 4/4 3/3\nusemtl c\nf 1 2 4\nusemtl d\nf 1/1/1 4/4/1 3/3/1\n";
        return true;
    }();
    (void)ready;
    std::ofstream(dir / "fuzz.mtl", std::ios::binary).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    SceneSources sources;
    DiagnosticSink sink;
    std::optional<Scene> s = import_obj((dir / "fuzz.obj").string(), sink, sources);
    if (s.has_value() && sink.has_errors()) std::abort();
    if (!s) return 0;
    for (const auto& m : s->materials) {
        if (!is_finite(m.color) || !std::isfinite(m.specularity) || !std::isfinite(m.roughness)) std::abort();
        m.textures.for_each([&](const char*, const TextureRef& t) {
            if (!std::filesystem::path(t.file).is_absolute()) std::abort();
            if (!is_finite(t.scale) || !std::isfinite(t.power) || t.channel < 0 || t.channel > 3) std::abort();
            for (double x : t.uv_transform)
                if (!std::isfinite(x)) std::abort();
        });
    }
    for (const auto& shape : s->shapes) {
        if (!shape.uvs.empty() && shape.uvs.size() != shape.vertices.size()) std::abort();
        if (!shape.normals.empty() && shape.normals.size() != shape.vertices.size()) std::abort();
    }
    return 0;
}
