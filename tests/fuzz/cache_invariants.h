/// \file cache_invariants.h
/// What every irradiance-cache fuzzer asserts of a load (ic_file_fuzzer, ic_records_fuzzer):
/// a refused file loads nothing and its message names the file; every record of an accepted
/// one is finite, inside the scene, with an irradiance from 0 to what the scene can give, a
/// positive radius, an accuracy in (0, 1] and a bounce within the cache's. Aborts otherwise.
#pragma once

#include <cmath>
#include <cstdlib>
#include <string>

#include "runtime/cache/irradiance_cache.h"
#include "runtime/render/render_scene.h"

namespace crex::fuzz {

inline void check_cache_load(const IrradianceCache& cache, const std::string& error, const std::string& name,
                             const RenderScene& scene, uint32_t bounces) {
    if (!error.empty()) {
        if (!cache.records().empty() || error.find("'" + name + "'") == std::string::npos) std::abort();
        return;
    }
    const double extent = scene.embree->extent();
    for (const auto& r : cache.records()) {
        const Vec3& e = r.irradiance;
        if (!is_finite(r.position) || std::fabs(r.position.x) > extent || std::fabs(r.position.y) > extent ||
            std::fabs(r.position.z) > extent)
            std::abort();
        if (!is_finite(e) || e.x < 0 || e.y < 0 || e.z < 0 || max_component(e) > 1e12) std::abort();  // cornell: 17 pi 1e6 at most
        if (!(r.harmonic_distance > 0) || !std::isfinite(r.harmonic_distance) || !(r.quality > 0 && r.quality <= 1)) std::abort();
        for (size_t c = 0; c < 3; ++c)
            if (!is_finite(r.rotation[c]) || !is_finite(r.translation[c])) std::abort();
        if (r.level > bounces) std::abort();
    }
}

}  // namespace crex::fuzz
