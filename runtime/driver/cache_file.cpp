#include "runtime/driver/cache_file.h"

#include <filesystem>
#include <stdexcept>

#include "runtime/driver/run_result.h"
#include "runtime/driver/run_settings.h"

namespace crex {

size_t load_cache_file(IrradianceCache& cache, const RunSettings& s) {
    cache.insert(s.ic_records, s.ic_grids.get());
    std::error_code ec;
    if (!s.ic_file_bytes && (s.ic_file.empty() || !s.ic_file_read || !std::filesystem::exists(s.ic_file, ec))) return 0;
    const size_t before = cache.records().size();
    const std::string error = s.ic_file_bytes ? cache.load_bytes(*s.ic_file_bytes, s.ic_file) : cache.load(s.ic_file);
    if (!error.empty()) throw RunInputError("irradiance cache: " + error);
    return cache.records().size() - before;
}

void save_cache_file(const IrradianceCache& cache, const std::string& path) {
    if (std::string error = cache.save(path); !error.empty()) throw std::runtime_error("cannot save the irradiance cache: " + error);
}

}  // namespace crex
