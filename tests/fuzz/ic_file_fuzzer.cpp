// libFuzzer target (run with tools/dev.sh fuzz): any bytes as an irradiance cache file (`crex run --ic-file F`).
// Invariants: no crash, sanitizer report or exception, and cache_invariants.h (a refused file
// loads nothing and names itself; an accepted one holds only records this scene can have).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "runtime/cache/irradiance_cache.h"
#include "runtime/render/render_scene.h"
#include "runtime/scene/load_scene.h"
#include "tests/fuzz/cache_invariants.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    static const Scene scene = *builtin_scene("cornell");
    static const RenderScene rs(scene);
    // The seeds' settings (tools/dev.sh: --ad 16 --ab 1 --caustic-photons 0), so they pass the
    // header check; no caustic map to build for every input.
    IcSettings settings;
    settings.divisions = 16, settings.bounces = 1, settings.caustic_photons = 0;
    IrradianceCache cache(rs, settings);
    std::string error = cache.load_bytes(std::string(reinterpret_cast<const char*>(data), size), "fuzz.ic");
    fuzz::check_cache_load(cache, error, "fuzz.ic", rs, settings.bounces);
    return 0;
}
