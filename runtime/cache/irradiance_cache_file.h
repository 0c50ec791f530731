/// \file irradiance_cache_file.h
/// The irradiance cache's file, apart from the cache (reuse across frames and runs, and the
/// bytes ranks exchange). Version 2: CBOR (nlohmann-json), a header of the settings the
/// records depend on, and the records as one byte string of little-endian float32, 30 each
/// (position, normal, E, R, rotation and translation gradients, quality, level), and when any
/// record was made with rays of its own (`vary ic_rays`) a byte string of their uint16 counts. Version 1
/// (JSON text, 19.6 MB for a 256x256 render's records) is still read. Reading checks every
/// record against the scene before any is kept: a damaged file loads nothing.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "runtime/base/vec3.h"
#include "runtime/cache/irradiance_record.h"

namespace crex {

struct Scene;

/// What a file's records depend on. A file is read only into a cache with the same divisions,
/// bounces, caustic photons and scene extent; min/max radius clamp what is read.
struct IcFileSettings {
    uint32_t divisions = 0, bounces = 0, caustic_photons = 0;
    double min_radius = 0, max_radius = 0, extent = 0;
};

/// The file's bytes for `records` made under `settings`.
std::string encode_irradiance_cache(const IcFileSettings& settings, const std::vector<IrradianceRecord>& records);

/// Reads `data` (named `path` in messages) into `records` when it was made under `expected`
/// and every record is this scene's: finite, inside the extent, irradiance in [0,
/// `max_irradiance`], a level within the bounces. "" on success, else what is wrong and what
/// to do; `records` is untouched then.
std::string decode_irradiance_cache(const std::string& data, const std::string& path, const IcFileSettings& expected, double max_irradiance,
                                    std::vector<IrradianceRecord>& records);

/// The most irradiance `scene` can give (every emitter, the background and `ambient` at their
/// brightest over the whole hemisphere, raised by inter-reflections): the bound a record read
/// from a file must respect.
double brightest_irradiance(const Scene& scene, const Vec3& ambient);

}  // namespace crex
