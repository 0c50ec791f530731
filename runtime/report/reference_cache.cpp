#include "runtime/report/reference_cache.h"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "base/fnv1a.h"
#include "runtime/base/cache_folder.h"
#include "runtime/io/image_io.h"
#include "runtime/scene/load_scene.h"

namespace crex {

namespace {
// Not FNV's offset basis (a digit short), but the one every cached and committed reference's
// scene hash was made with: changing it would orphan them all.
constexpr uint64_t kReferenceHashBasis = 1469598103934665603ull;
std::string reference_hash(const std::string& text) { return hex16(fnv1a64(text, kReferenceHashBasis)); }
}  // namespace

std::string scene_content_hash(const Scene& scene) { return reference_hash(scene_identity_text(scene)); }

std::string reference_key(const Scene& scene, const ReferenceSettings& s) {
    return reference_hash(scene_identity_text(scene) +
                          fmt::format("\n{}x{} seed {} crex {} lw {:.17g} max_depth {} v1", s.width, s.height, s.seed, s.crex, s.lw, s.max_depth));
}

std::string reference_cache_dir() { return (std::filesystem::path(crex_cache_folder()) / "references").string(); }

std::string reference_path(const Scene& scene, const ReferenceSettings& s) {
    return (std::filesystem::path(reference_cache_dir()) / fmt::format("{}_spp{}.exr", reference_key(scene, s), s.spp)).string();
}

std::string find_cached_reference(const Scene& scene, const ReferenceSettings& s) {
    namespace fs = std::filesystem;
    std::string prefix = reference_key(scene, s) + "_spp", best;
    unsigned long most = 0;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(reference_cache_dir(), ec)) {
        std::string name = e.path().filename().string();
        if (name.rfind(prefix, 0) != 0) continue;
        // KEY_sppN.exr exactly: an interrupted `crex reference` leaves KEY_sppN.partial.exr
        // beside it, which holds fewer than N samples.
        char* end = nullptr;
        const unsigned long spp = std::strtoul(name.c_str() + prefix.size(), &end, 10);
        if (end == name.c_str() + prefix.size() || std::string(end) != ".exr") continue;
        if (spp > most) most = spp, best = e.path().string();
    }
    return best;
}

bool holds_reference(const std::string& path, const Scene& scene, const ReferenceSettings& s, bool keyed) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return false;
    if (keyed) {
        std::ifstream k(path + ".key");
        std::string stored;
        if (!(k >> stored) || stored != reference_key(scene, s)) return false;
    }
    int w = 0, h = 0;
    std::vector<float> rgb;
    return read_image(path, w, h, rgb).empty() && w == s.width && h == s.height;
}

}  // namespace crex
