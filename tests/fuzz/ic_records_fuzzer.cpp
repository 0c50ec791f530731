// libFuzzer target: an irradiance cache file of the right shape (version 2, this scene's
// settings) whose records are the fuzzer's floats (issue 37: records of E = 1e38 or -5 loaded
// and the image lost its indirect light). Random bytes rarely pass the header, so the header is
// built here and the fuzz input is the records' bytes, and a count that may disagree with them.
// Invariants: no crash, sanitizer report or exception; a refused file loads nothing and its
// message names the file; every record of an accepted one is finite, inside the scene, with an
// irradiance from 0 to what the scene's emitters can give, R > 0, accuracy in (0, 1].
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
    if (!error.empty()) {
        if (!cache.records().empty() || error.find("'fuzz.ic'") == std::string::npos) std::abort();
        return 0;
    }
    const double extent = rs.embree->extent();
    for (const auto& r : cache.records()) {
        const Vec3& e = r.irradiance;
        if (!is_finite(r.position) || std::fabs(r.position.x) > extent || std::fabs(r.position.y) > extent ||
            std::fabs(r.position.z) > extent)
            std::abort();
        if (!is_finite(e) || e.x < 0 || e.y < 0 || e.z < 0 || max_component(e) > 1e12) std::abort();  // cornell: radiance 17 * pi * 1e6
        if (!(r.harmonic_distance > 0) || !std::isfinite(r.harmonic_distance) || !(r.quality > 0 && r.quality <= 1)) std::abort();
        for (size_t c = 0; c < 3; ++c)
            if (!is_finite(r.rotation[c]) || !is_finite(r.translation[c])) std::abort();
        if (r.level > settings.bounces) std::abort();
    }
    return 0;
}
