// libFuzzer target: an irradiance cache file of the right shape (version 2, this scene's
// settings) whose records are the fuzzer's floats (issue 37: records of E = 1e38 or -5 loaded
// and the image lost its indirect light). Random bytes rarely pass the header, so the header is
// built here and the fuzz input is the records' bytes, and a count that may disagree with them.
// Invariants: no crash, sanitizer report or exception, and cache_invariants.h.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "runtime/cache/irradiance_cache.h"
#include "runtime/render/render_scene.h"
#include "runtime/scene/load_scene.h"
#include "tests/fuzz/cache_invariants.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    static const Scene scene = *builtin_scene("cornell");
    static const RenderScene rs(scene);
    IcSettings settings;
    settings.divisions = 16, settings.bounces = 2, settings.caustic_photons = 0;
    IrradianceCache cache(rs, settings);
    constexpr size_t kRecordBytes = 30 * 4;
    if (size < 1) return 0;
    // The first byte: whether the count agrees with the records (mostly it does).
    const size_t records = (size - 1) / kRecordBytes;
    const size_t count = data[0] < 240 ? records : records + (data[0] - 239);
    nlohmann::json j;
    j["format"] = "crex-irradiance-cache";
    j["version"] = 2;
    j["settings"] = {{"divisions", 16}, {"bounces", 2}, {"caustic_photons", 0}, {"extent", rs.embree->extent()}};
    j["count"] = count;
    j["records"] = nlohmann::json::binary(std::vector<std::uint8_t>(data + 1, data + 1 + records * kRecordBytes));
    const std::vector<std::uint8_t> cbor = nlohmann::json::to_cbor(j);
    const std::string error = cache.load_bytes(std::string(cbor.begin(), cbor.end()), "fuzz.ic");
    fuzz::check_cache_load(cache, error, "fuzz.ic", rs, settings.bounces);
    return 0;
}
