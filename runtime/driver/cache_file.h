/// \file cache_file.h
/// A render's irradiance cache file (`--ic-file`): the records a run starts from, read before
/// the first camera ray (its bytes read already by whoever read the inputs, else the file if it
/// exists), and the cache saved there at the end, by the one process that saves it. The format
/// is the cache's (runtime/cache/cache_file_format.h); records are validated against the
/// scene's extent either way.
#pragma once

#include <string>

#include "runtime/cache/irradiance_cache.h"

namespace crex {

struct RunSettings;

/// The records of `settings.ic_records` and of the cache file inserted into `cache`; returns
/// how many came from the file. Throws RunInputError for a file the cache cannot use.
size_t load_cache_file(IrradianceCache& cache, const RunSettings& settings);

/// `cache` written to `path`, atomically. Throws std::runtime_error when it cannot be.
void save_cache_file(const IrradianceCache& cache, const std::string& path);

}  // namespace crex
